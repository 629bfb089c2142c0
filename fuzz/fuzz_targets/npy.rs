//! `.npy` arrays (header, dtype, shape, order, data) without the zip around them: the
//! input is a bundle (src/lib.rs) whose main file is `vertices.npy` (a `faces.npy`
//! section gives the other array); the target stores the sections in an `.npz`, as
//! `np.savez` does, and loads that. Mutations then land on the arrays rather than on the
//! zip's headers and checksums (the `npz` target fuzzes those).
#![no_main]

use std::io::Write;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let files = dynray_fuzz::split_bundle(data, "vertices.npy");
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::FileOptions::default().compression_method(zip::CompressionMethod::Stored);
    for (name, bytes) in &files {
        // A name twice is an error of the writer, not of the reader under test.
        if zip.start_file(name.as_str(), options).is_err() {
            continue;
        }
        zip.write_all(bytes).expect("writing to memory");
    }
    let npz = zip.finish().expect("writing to memory").into_inner();
    let dir = dynray_fuzz::write_case(&[("mesh.npz".to_string(), &npz[..])]);
    if let Ok(report) = dynray_scene::load_file_report(&dir.join("mesh.npz")) {
        dynray_fuzz::check_scene(&report.scene);
    }
});
