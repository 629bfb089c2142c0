//! The one font the PNG charts and heat maps need.
//!
//! plotters is built without its `ttf` feature (font-kit pulls in freetype and
//! fontconfig); text goes through the pure-Rust `ab_glyph` rasteriser instead, which needs
//! a font registered by hand. We load DejaVu Sans from the system (Debian:
//! `fonts-dejavu-core`; `.ci/run` installs it) or from `$DYNRAY_FONT`. SVG charts need no
//! font file: the viewer draws their text.

use anyhow::{bail, Result};
use std::path::PathBuf;
use std::sync::OnceLock;

/// Where DejaVu Sans lives on common systems.
const CANDIDATES: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf",
    "/usr/local/share/fonts/DejaVuSans.ttf",
];

/// The font file that would be used, if any.
pub fn font_path() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("DYNRAY_FONT") {
        return Some(PathBuf::from(p));
    }
    CANDIDATES.iter().map(PathBuf::from).find(|p| p.is_file())
}

/// Registers the font as plotters' `sans-serif` (once per process).
pub fn ensure_font() -> Result<()> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    let r = DONE.get_or_init(|| {
        let Some(path) = font_path() else {
            return Err(format!(
                "PNG charts and heat maps need the DejaVu Sans font: none found at {} \
                 (install Debian's fonts-dejavu-core, set DYNRAY_FONT=/path/to/font.ttf, or pass --no-png)",
                CANDIDATES.join(", ")
            ));
        };
        let bytes = std::fs::read(&path).map_err(|e| format!("font {}: {e}", path.display()))?;
        // plotters keeps fonts for the life of the process; so does this one copy.
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, bytes)
            .map_err(|_| format!("font {}: not a TrueType/OpenType font", path.display()))
    });
    match r {
        Ok(()) => Ok(()),
        Err(e) => bail!("{e}"),
    }
}
