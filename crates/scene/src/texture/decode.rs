//! Decoding image files into [`Texture`]s through the `image` crate (PNG, JPEG,
//! PPM/PNM; BMP too, since the crate has it for output), with sRGB decoding for colour
//! textures and limits that keep a hostile header from allocating gigabytes.

use super::Texture;
use crate::Color;
use std::io::Cursor;
use std::path::Path;

/// Most texels a texture may have (8192 × 8192): at 12 bytes a texel that is 768 MiB,
/// a bound on what one bad file can make dynray allocate.
pub const MAX_TEXELS: u64 = 1 << 26;

/// Longest image side accepted, checked by the decoder before it allocates.
const MAX_SIDE: u32 = 1 << 15;

/// How a file's values map to linear RGB.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorSpace {
    /// Colour textures (glTF `baseColorTexture`, MTL `map_Kd`, `.scn` `texture`): values
    /// are sRGB-encoded and decoded to linear with the sRGB transfer function.
    Srgb,
    /// Data textures (none yet: normal or roughness maps would be): values are used as
    /// they are, scaled to `[0, 1]`.
    Linear,
}

/// Why a texture could not be made; loaders turn it into a warning naming the file.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The path names a directory or device, not a file.
    #[error("{path} is not a regular file")]
    NotAFile {
        /// The path.
        path: String,
    },
    /// The bytes are not an image the decoder reads (or not one at all).
    #[error("cannot decode {name}: {message}")]
    Decode {
        /// The image (file path or glTF image).
        name: String,
        /// The decoder's reason.
        message: String,
    },
    /// The image is larger than [`MAX_TEXELS`] or has a zero side.
    #[error("{name}: {width} × {height} texels is outside what dynray accepts (1 to {MAX_TEXELS})")]
    Size {
        /// The image.
        name: String,
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
    },
}

/// The sRGB transfer function's inverse (IEC 61966-2-1): an encoded value in `[0, 1]`
/// to linear light.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

impl Texture {
    /// Reads and decodes the image file at `path` (format from its content, else from its
    /// extension). The texture is named after `path`.
    pub fn load(path: &Path, space: ColorSpace) -> Result<Texture, TextureError> {
        let name = path.display().to_string();
        // A device such as /dev/zero would be read forever; only regular files.
        match std::fs::metadata(path) {
            Ok(m) if m.is_file() => {}
            Ok(_) => return Err(TextureError::NotAFile { path: name }),
            Err(source) => return Err(TextureError::Io { path: name, source }),
        }
        let bytes = dynray_geom::file::read(path).map_err(|source| TextureError::Io { path: name.clone(), source })?;
        let ext = path.extension().and_then(|e| e.to_str());
        Texture::decode(name, &bytes, ext, space)
    }

    /// Decodes an encoded image held in memory (a glTF buffer view or data URI). The
    /// format is guessed from the content, else from `extension` (`"png"`, `"jpg"`, …).
    pub fn decode(
        name: impl Into<String>,
        bytes: &[u8],
        extension: Option<&str>,
        space: ColorSpace,
    ) -> Result<Texture, TextureError> {
        let name = name.into();
        let fail = |message: String| TextureError::Decode { name: name.clone(), message };
        let mut reader =
            image::ImageReader::new(Cursor::new(bytes)).with_guessed_format().map_err(|e| fail(e.to_string()))?;
        if reader.format().is_none() {
            match extension.and_then(image::ImageFormat::from_extension) {
                Some(f) => reader.set_format(f),
                None => return Err(fail("not an image format dynray reads (PNG, JPEG, PPM/PNM, BMP)".into())),
            }
        }
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_SIDE);
        limits.max_image_height = Some(MAX_SIDE);
        reader.limits(limits);
        let img = reader.decode().map_err(|e| fail(e.to_string()))?;
        let (width, height) = (img.width(), img.height());
        let n = width as u64 * height as u64;
        if n == 0 || n > MAX_TEXELS {
            return Err(TextureError::Size { name, width, height });
        }
        let texels = linear_texels(img, space);
        Texture::from_linear(name.clone(), width, height, texels).ok_or(TextureError::Size { name, width, height })
    }
}

/// The image's RGB as linear colours: 8-bit images through a 256-entry table, deeper
/// ones through the formula. Grey images are replicated to RGB; alpha is dropped.
fn linear_texels(img: image::DynamicImage, space: ColorSpace) -> Vec<Color> {
    let decode = |c: f32| match space {
        ColorSpace::Srgb => srgb_to_linear(c),
        ColorSpace::Linear => c,
    };
    let eight_bit = matches!(
        img,
        image::DynamicImage::ImageLuma8(_)
            | image::DynamicImage::ImageLumaA8(_)
            | image::DynamicImage::ImageRgb8(_)
            | image::DynamicImage::ImageRgba8(_)
    );
    if eight_bit {
        let table: Vec<f32> = (0..=255u8).map(|b| decode(b as f32 / 255.0)).collect();
        let rgb = img.into_rgb8();
        rgb.pixels().map(|p| Color::new(table[p[0] as usize], table[p[1] as usize], table[p[2] as usize])).collect()
    } else {
        let rgb = img.into_rgb32f();
        rgb.pixels().map(|p| Color::new(decode(p[0]), decode(p[1]), decode(p[2]))).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A PNG of `w × h` RGB8 pixels, encoded by the same `image` crate.
    fn png(w: u32, h: u32, rgb: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        image::RgbImage::from_raw(w, h, rgb.to_vec())
            .unwrap()
            .write_to(&mut Cursor::new(&mut out), image::ImageFormat::Png)
            .unwrap();
        out
    }

    #[test]
    fn srgb_decoding_matches_the_standard() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        // The linear segment, and 188/255 (sRGB's "half grey" is about 0.5 linear).
        assert!((srgb_to_linear(0.04) - 0.04 / 12.92).abs() < 1e-9);
        assert!((srgb_to_linear(188.0 / 255.0) - 0.5029).abs() < 1e-3);
        assert!((srgb_to_linear(0.5) - 0.21404).abs() < 1e-4);
        // Continuous where the two pieces meet.
        let (a, b) = (srgb_to_linear(0.04045), srgb_to_linear(0.04045 + 1e-6));
        assert!((a - b).abs() < 1e-5);
    }

    #[test]
    fn png_texels_are_decoded_from_srgb_top_row_first() {
        // Row 0: red, 128 grey; row 1: black, white.
        let bytes = png(2, 2, &[255, 0, 0, 128, 128, 128, 0, 0, 0, 255, 255, 255]);
        let t = Texture::decode("t.png", &bytes, None, ColorSpace::Srgb).unwrap();
        assert_eq!((t.width(), t.height()), (2, 2));
        assert_eq!(t.texel(0, 0), Color::new(1.0, 0.0, 0.0));
        let g = srgb_to_linear(128.0 / 255.0);
        assert_eq!(t.texel(1, 0), Color::splat(g));
        assert!((g - 0.2158).abs() < 1e-3, "128 is about 0.216 linear, got {g}");
        assert_eq!(t.texel(0, 1), Color::ZERO);
        assert_eq!(t.texel(1, 1), Color::ONE);
        let lin = Texture::decode("t.png", &bytes, None, ColorSpace::Linear).unwrap();
        assert_eq!(lin.texel(1, 0), Color::splat(128.0 / 255.0));
    }

    #[test]
    fn ppm_decodes_by_content_and_extension() {
        let ppm = b"P6\n2 1\n255\n\xff\x00\x00\x00\x00\xff";
        let t = Texture::decode("a.ppm", ppm, None, ColorSpace::Srgb).unwrap();
        assert_eq!(t.texel(0, 0), Color::X);
        assert_eq!(t.texel(1, 0), Color::Z);
        let ascii = b"P3 1 1 255 0 255 0";
        let t = Texture::decode("b.ppm", ascii, Some("ppm"), ColorSpace::Srgb).unwrap();
        assert_eq!(t.texel(0, 0), Color::Y);
    }

    #[test]
    fn bad_images_are_errors_not_panics() {
        let e = Texture::decode("junk.png", b"not an image", Some("png"), ColorSpace::Srgb).unwrap_err();
        assert!(e.to_string().starts_with("cannot decode junk.png"), "{e}");
        let e = Texture::decode("junk", b"not an image", None, ColorSpace::Srgb).unwrap_err();
        assert!(e.to_string().contains("not an image format"), "{e}");
        // A header claiming 30000 × 30000 (2.7 GB of RGB) fails before allocating.
        let e = Texture::decode("big.ppm", b"P6\n30000 30000\n255\n\0\0\0", None, ColorSpace::Srgb).unwrap_err();
        assert!(matches!(e, TextureError::Decode { .. } | TextureError::Size { .. }), "{e}");
        // Truncated pixel data.
        let e = Texture::decode("short.ppm", b"P6\n4 4\n255\n\0\0\0", None, ColorSpace::Srgb).unwrap_err();
        assert!(e.to_string().contains("short.ppm"), "{e}");
        let dir = std::env::temp_dir();
        let e = Texture::load(&dir, ColorSpace::Srgb).unwrap_err();
        assert!(matches!(e, TextureError::NotAFile { .. }), "{e}");
        let e = Texture::load(Path::new("/nonexistent/dynray/x.png"), ColorSpace::Srgb).unwrap_err();
        assert!(e.to_string().contains("/nonexistent/dynray/x.png"), "{e}");
    }
}
