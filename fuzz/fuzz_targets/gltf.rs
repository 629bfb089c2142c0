//! glTF 2.0: the input is a bundle (src/lib.rs) whose main file is `main.gltf` (JSON)
//! or, when it starts with the binary magic `glTF`, `main.glb`; buffers and images come
//! from `data:` URIs, the GLB's binary chunk, or the bundle's other files.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if data.starts_with(b"glTF") {
        // A GLB is binary: its chunks could hold the separator, so the input is the
        // file alone (its buffers are the binary chunk or data: URIs).
        let dir = dynray_fuzz::write_case(&[("main.glb".to_string(), data)]);
        if let Ok(report) = dynray_scene::load_file_report(&dir.join("main.glb")) {
            dynray_fuzz::check_scene(&report.scene);
        }
    } else {
        dynray_fuzz::load_bundle(data, "main.gltf");
    }
});
