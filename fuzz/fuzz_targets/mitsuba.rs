//! Mitsuba 3 scene XML: the input is a bundle (src/lib.rs) whose main file is
//! `main.xml`; `<include>`s and `obj`/`ply` shapes name the bundle's other files.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| dynray_fuzz::load_bundle(data, "main.xml"));
