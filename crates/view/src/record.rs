//! `--record FILE.gif`: every frame the window shows (the canvas read back, overlays
//! included unless `--no-overlay`), with its real duration, written as a looping GIF when
//! the window closes (under a temporary name, then renamed).

use anyhow::Result;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};
use std::path::Path;

/// Widest recorded frame: larger windows are shrunk, so a recording stays small.
const MAX_WIDTH: u32 = 640;
/// Most frames kept (about a minute at 10 fps); later ones are dropped and counted.
pub const MAX_FRAMES: usize = 600;

/// The frames recorded so far.
#[derive(Default)]
pub struct Recording {
    frames: Vec<(RgbaImage, f64)>,
    dropped: usize,
}

impl Recording {
    /// Adds a frame shown for `ms` milliseconds.
    pub fn push(&mut self, image: RgbaImage, ms: f64) {
        if self.frames.len() >= MAX_FRAMES {
            self.dropped += 1;
            return;
        }
        let image = if image.width() > MAX_WIDTH {
            let h = ((image.height() as u64 * MAX_WIDTH as u64) / image.width() as u64).max(1) as u32;
            image::imageops::resize(&image, MAX_WIDTH, h, image::imageops::FilterType::Triangle)
        } else {
            image
        };
        self.frames.push((image, ms));
    }

    /// Frames kept.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// True before the first frame.
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Frames past [`MAX_FRAMES`] that were not kept.
    pub fn dropped(&self) -> usize {
        self.dropped
    }

    /// Writes the frames as a looping GIF to `path`.
    pub fn write(&self, path: &Path) -> Result<()> {
        dynray_engine::output::write_with(path, |file| {
            let mut encoder = GifEncoder::new_with_speed(std::io::BufWriter::new(file), 10);
            encoder.set_repeat(Repeat::Infinite)?;
            for (image, ms) in &self.frames {
                // GIF delays are hundredths of a second; 20 ms is the shortest viewers honour.
                let delay = Delay::from_numer_denom_ms(ms.round().clamp(20.0, 10_000.0) as u32, 1);
                encoder.encode_frame(Frame::from_parts(image.clone(), 0, 0, delay))?;
            }
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_kept_shrunk_and_written_with_their_durations() {
        let mut r = Recording::default();
        r.push(RgbaImage::from_pixel(1280, 720, image::Rgba([200, 10, 10, 255])), 50.0);
        r.push(RgbaImage::from_pixel(1280, 720, image::Rgba([10, 200, 10, 255])), 120.0);
        assert_eq!(r.len(), 2);
        assert_eq!(r.frames[0].0.dimensions(), (640, 360));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.gif");
        r.write(&path).unwrap();
        let decoder =
            image::codecs::gif::GifDecoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap())).unwrap();
        let frames = image::AnimationDecoder::into_frames(decoder).collect_frames().unwrap();
        assert_eq!(frames.len(), 2);
        assert_eq!(frames[1].delay().numer_denom_ms(), (120, 1));
    }
}
