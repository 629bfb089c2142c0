//! BART's AFF (and NFF): the input is a bundle (src/lib.rs) whose main file is
//! `main.aff`; `i` includes and texture files are the bundle's other files.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| dynray_fuzz::load_bundle(data, "main.aff"));
