//! `.adf` distance fields: the input is the file. The target writes the FNV-1a checksum
//! the format ends with over the mutated bytes first, so that mutations reach the table
//! checks behind it (a wrong checksum is one early `Err`, which the seeds' own bytes
//! cover). A field that loads is then used as `dynray render` and `info` use it: its
//! memory figures, and sphere tracing through its cube.
#![no_main]

use dynray_geom::{Ray, Vec3};

/// FNV-1a, 64 bits, as crates/adf/src/file.rs writes it.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let mut bytes = data.to_vec();
    if bytes.len() >= 8 {
        let body = bytes.len() - 8;
        let sum = fnv1a(&bytes[..body]);
        bytes[body..].copy_from_slice(&sum.to_le_bytes());
    }
    let Ok(adf) = dynray_adf::Adf::from_bytes(&bytes, std::path::Path::new("field.adf")) else { return };
    let _ = adf.memory();
    let b = adf.cube().bounds();
    let center = b.center();
    // Rays from outside each corner of the cube through its centre, and one from inside.
    for corner in 0..8u32 {
        let pick = |bit: u32, lo: f32, hi: f32| if corner >> bit & 1 == 0 { lo } else { hi };
        let c = Vec3::new(pick(0, b.min.x, b.max.x), pick(1, b.min.y, b.max.y), pick(2, b.min.z, b.max.z));
        let origin = center + (c - center) * 1.5;
        let _ = adf.march(&Ray::new(origin, center - origin));
    }
    let _ = adf.march(&Ray::new(center, Vec3::new(0.3, 0.5, 0.8)));
});
