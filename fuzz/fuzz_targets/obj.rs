//! Wavefront OBJ with its material libraries: the input is a bundle (src/lib.rs) whose
//! main file is `main.obj`; `mtllib` names the bundle's other files.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| dynray_fuzz::load_bundle(data, "main.obj"));
