//! Writing a film to disk: PNG and BMP as 8-bit sRGB, EXR as linear `f32`, chosen by the
//! file extension. The image is written atomically (a temporary file in the target
//! directory renamed over the target, never over an input), so a failure never leaves a
//! partial output file.

use crate::{Aov, Film, RenderError};
use exr::prelude::{Image, SpecificChannels, Vec2, WritableImage};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// The image formats the renderer writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// 8-bit sRGB PNG.
    Png,
    /// 8-bit sRGB BMP.
    Bmp,
    /// OpenEXR, linear RGB `f32` (HDR values kept).
    Exr,
}

impl OutputFormat {
    /// The format named by the path's extension (case-insensitive), if any.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(Self::Png),
            "bmp" => Some(Self::Bmp),
            "exr" => Some(Self::Exr),
            _ => None,
        }
    }
}

/// Writes `film` to `path` in the format its extension names.
///
/// Errors name `path`: an unknown extension, an empty film, a directory that cannot be
/// written, an encoder failure. On any error the target is left as it was.
pub fn write_image(film: &Film, path: &Path) -> Result<(), RenderError> {
    let format = OutputFormat::from_path(path).ok_or_else(|| RenderError::UnknownFormat { path: path.into() })?;
    write_atomically(film, path, |w| encode(film, format, path, w))
}

/// Writes an AOV film to `path`, which must name an `.exr` file: the AOV's channels as
/// `f32` ([`Aov::channels`]: one for depth and triangle index, three for normal and
/// albedo), values unclamped (`+inf` depth and `-1` index on misses are kept).
pub fn write_aov(film: &Film, aov: Aov, path: &Path) -> Result<(), RenderError> {
    if OutputFormat::from_path(path) != Some(OutputFormat::Exr) {
        return Err(RenderError::AovNeedsExr { path: path.into(), aov: aov.name() });
    }
    write_atomically(film, path, |w| {
        let width = film.width() as usize;
        let px = film.pixels();
        let size = (width, film.height() as usize);
        let names = aov.channels();
        let result = if let [name] = names {
            let channels = SpecificChannels::build()
                .with_channel(*name)
                .with_pixel_fn(|Vec2(x, y): Vec2<usize>| (px[y * width + x].x,));
            Image::from_channels(size, channels).write().to_buffered(w)
        } else {
            let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                let c = px[y * width + x];
                (c.x, c.y, c.z)
            });
            Image::from_channels(size, channels).write().to_buffered(w)
        };
        result.map_err(|e| exr_error(path, e))
    })
}

/// Checks the film and writes it through `fill` atomically
/// ([`dynray_geom::file::atomic`]: a temporary sibling, synced and renamed over `path`,
/// never over an input); on any error the target is left as it was.
fn write_atomically(
    film: &Film,
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<&mut File>) -> Result<(), RenderError>,
) -> Result<(), RenderError> {
    if film.width() == 0 || film.height() == 0 {
        return Err(RenderError::EmptyImage { path: path.into(), width: film.width(), height: film.height() });
    }
    let io = |source| RenderError::Io { path: path.into(), source };
    dynray_geom::file::write_atomic(
        path,
        |file| {
            let mut w = BufWriter::new(file);
            fill(&mut w)?;
            w.flush().map_err(io)
        },
        io,
    )
}

/// The exr crate's error as ours: I/O failures keep their cause.
fn exr_error(path: &Path, e: exr::error::Error) -> RenderError {
    match e {
        exr::error::Error::Io(source) => RenderError::Io { path: path.into(), source },
        e => RenderError::Encode { path: path.into(), message: e.to_string() },
    }
}

/// Encodes the film's colour in `format` into `w`.
fn encode(film: &Film, format: OutputFormat, path: &Path, w: &mut BufWriter<&mut File>) -> Result<(), RenderError> {
    let io = |source| RenderError::Io { path: path.into(), source };
    let encode = |message: String| RenderError::Encode { path: path.into(), message };
    match format {
        OutputFormat::Png | OutputFormat::Bmp => {
            let f = if format == OutputFormat::Png { image::ImageFormat::Png } else { image::ImageFormat::Bmp };
            let bytes = film.to_srgb8();
            image::write_buffer_with_format(w, &bytes, film.width(), film.height(), image::ColorType::Rgb8, f)
                .map_err(|e| match e {
                    image::ImageError::IoError(source) => io(source),
                    e => encode(e.to_string()),
                })?;
        }
        OutputFormat::Exr => {
            let width = film.width() as usize;
            let px = film.pixels();
            let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                let c = px[y * width + x];
                (c.x, c.y, c.z)
            });
            let image = Image::from_channels((width, film.height() as usize), channels);
            image.write().to_buffered(w).map_err(|e| exr_error(path, e))?;
        }
    }
    Ok(())
}
