//! Writing result files through a temporary name and a rename, so an interrupted or
//! failed run never leaves a half-written report, chart or heat map.

use anyhow::{Context, Result};
use std::path::Path;

/// Atomic, readable writes: the engine's (shared with every front end).
pub use dynray_engine::output::write_atomic;

/// Encodes an RGB8 buffer as PNG and writes it atomically.
pub fn write_png(path: &Path, rgb: &[u8], width: u32, height: u32) -> Result<()> {
    let mut bytes = Vec::new();
    image::write_buffer_with_format(
        &mut std::io::Cursor::new(&mut bytes),
        rgb,
        width,
        height,
        image::ColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .with_context(|| format!("{}: PNG encoding failed", path.display()))?;
    write_atomic(path, &bytes)
}
