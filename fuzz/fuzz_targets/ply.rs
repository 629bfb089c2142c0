//! PLY (ASCII, binary little- and big-endian, gzip-compressed): the input is the file,
//! read by the mesh loader as `dynray render mesh.ply` would (docs/fuzzing.md).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    // No bundle: a PLY names no other file, and a separator line would be a legal part of
    // a binary body.
    let dir = dynray_fuzz::write_case(&[("mesh.ply".to_string(), data)]);
    if let Ok(report) = dynray_scene::load_file_report(&dir.join("mesh.ply")) {
        dynray_fuzz::check_scene(&report.scene);
    }
});
