//! `preview.gif` of `dynray animate`: the frames, shrunk, looping, for a quick look.

use anyhow::{Context, Result};
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};
use std::path::{Path, PathBuf};

/// Widest preview frame, in pixels.
const MAX_WIDTH: u32 = 320;
/// Most frames a preview holds: longer animations are subsampled evenly (the timing of
/// the preview stays that of the animation).
const MAX_FRAMES: usize = 120;

/// Writes the PNGs `frames`, in order, as a looping GIF at `fps` (atomically,
/// [`crate::output`]).
pub fn write_gif(frames: &[PathBuf], fps: f32, path: &Path) -> Result<()> {
    let step = frames.len().div_ceil(MAX_FRAMES).max(1);
    let delay_ms = (1000.0 * step as f32 / fps.max(1e-3)).round().clamp(20.0, 10_000.0) as u32;
    crate::output::write_with(path, |file| {
        let mut encoder = GifEncoder::new_with_speed(std::io::BufWriter::new(file), 10);
        encoder.set_repeat(Repeat::Infinite)?;
        for p in frames.iter().step_by(step) {
            let img =
                image::open(p).with_context(|| format!("{}: cannot read the frame back", p.display()))?.to_rgba8();
            let img = shrink(img);
            encoder.encode_frame(Frame::from_parts(img, 0, 0, Delay::from_numer_denom_ms(delay_ms, 1)))?;
        }
        Ok(())
    })
}

fn shrink(img: RgbaImage) -> RgbaImage {
    if img.width() <= MAX_WIDTH {
        return img;
    }
    let h = ((img.height() as u64 * MAX_WIDTH as u64) / img.width() as u64).max(1) as u32;
    image::imageops::resize(&img, MAX_WIDTH, h, image::imageops::FilterType::Triangle)
}
