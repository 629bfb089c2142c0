//! MTL material libraries: the input is a bundle (src/lib.rs) whose main file is
//! `m.mtl` (its further files are its texture maps), read through a fixed OBJ that names
//! it and uses the materials the seeds define, on faces with texture coordinates so that
//! maps are loaded.
#![no_main]

/// Two textured triangles, each with a material of the seeds (an unknown name only
/// warns).
const OBJ: &[u8] = b"mtllib m.mtl
v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
vt 0 0
vt 1 0
vt 0 1
vt 1 1
usemtl light
f 1/1 2/2 3/3
usemtl white
f 2/2 4/4 3/3
";

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let mut files = dynray_fuzz::split_bundle(data, "m.mtl");
    files.retain(|(name, _)| name != "main.obj");
    files.push(("main.obj".to_string(), OBJ));
    let dir = dynray_fuzz::write_case(&files);
    if let Ok(report) = dynray_scene::load_file_report(&dir.join("main.obj")) {
        dynray_fuzz::check_scene(&report.scene);
    }
});
