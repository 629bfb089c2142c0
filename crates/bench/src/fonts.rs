//! The one font of the charts and heat maps.
//!
//! plotters is built without its `ttf` feature (font-kit pulls in freetype and
//! fontconfig); text goes through the pure-Rust `ab_glyph` rasteriser instead, which needs
//! a font registered by hand, for PNG drawing and for SVG layout alike (plotters measures
//! every label). DejaVu Sans is embedded (crate `dejavu`), so no system font is needed;
//! `$DYNRAY_FONT` may name another TTF/OTF file.

use anyhow::{bail, Result};
use std::sync::OnceLock;

/// The font's bytes: `$DYNRAY_FONT`'s file, or the embedded DejaVu Sans.
fn font_bytes() -> Result<&'static [u8], String> {
    let Some(path) = std::env::var_os("DYNRAY_FONT") else {
        return Ok(dejavu::sans::regular());
    };
    let bytes = std::fs::read(&path).map_err(|e| format!("DYNRAY_FONT={}: {e}", path.to_string_lossy()))?;
    // plotters keeps fonts for the life of the process; so does this one copy.
    Ok(Box::leak(bytes.into_boxed_slice()))
}

/// Registers the font as plotters' `sans-serif` (once per process).
pub fn ensure_font() -> Result<()> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    let r = DONE.get_or_init(|| {
        let bytes = font_bytes()?;
        plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, bytes)
            .map_err(|_| "chart font: not a TrueType/OpenType font (check DYNRAY_FONT)".to_string())
    });
    match r {
        Ok(()) => Ok(()),
        Err(e) => bail!("{e}"),
    }
}
