//! `.npz` meshes (a zip of `vertices.npy` and `faces.npy`): the input is the archive.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let dir = dynray_fuzz::write_case(&[("mesh.npz".to_string(), data)]);
    if let Ok(report) = dynray_scene::load_file_report(&dir.join("mesh.npz")) {
        dynray_fuzz::check_scene(&report.scene);
    }
});
