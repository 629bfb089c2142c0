//! The scene language (`.scn`): the input is a bundle (src/lib.rs) whose main file is
//! `main.scn`; `include`, `mesh { file }` and `texture` name the bundle's other files.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| dynray_fuzz::load_bundle(data, "main.scn"));
