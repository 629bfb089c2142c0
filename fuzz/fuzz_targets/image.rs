//! Image textures (PNG, JPEG, PPM/PNM; BMP too, which the decoder also reads): the input
//! is the file, decoded by the texture loader under its size limits
//! (crates/scene/src/texture/decode.rs), then sampled as a material would sample it.
#![no_main]

use dynray_geom::Vec2;
use dynray_scene::texture::{ColorSpace, TextureSampler};
use dynray_scene::Texture;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(t) = Texture::decode("texture", data, None, ColorSpace::Srgb) else { return };
    assert!(t.width() > 0 && t.height() > 0, "a decoded texture has texels");
    let sampler = TextureSampler::default();
    for uv in [Vec2::ZERO, Vec2::new(0.5, 0.5), Vec2::ONE, Vec2::new(-3.25, 7.5)] {
        let _ = t.sample(uv, &sampler);
    }
});
