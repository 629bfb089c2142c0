//! Image textures: a decoded image as linear-RGB `f32` texels with its mipmaps
//! ([`Texture`], the pyramid in `mip.rs`), how it is sampled ([`TextureSampler`]: wrap
//! modes, bilinear or trilinear filtering by a footprint, `sample.rs`), and how a
//! material uses one ([`TextureRef`]: which texture, sampler, uv transform, the level of
//! detail of a footprint, `binding.rs`). Decoding (PNG, JPEG, PPM/PNM through the `image`
//! crate, sRGB to linear) is `decode.rs`.
//!
//! Textures live once in [`crate::Scene::textures`] as `Arc<Texture>` and materials name
//! them by index, so [`crate::Scene::frame_into`] (which copies materials every frame)
//! copies pointers, never texels.
//!
//! # Texture coordinates
//! dynray's uv convention is OBJ's (and OpenGL's, pbrt's, Blender's): `(0, 0)` is the
//! **bottom-left** corner of the image, `u` grows to the right and `v` upwards; `(1, 1)`
//! is the top-right corner. Mesh uvs ([`dynray_geom::TriangleMesh::uvs`]) are stored in
//! it, so one texture looks the same on meshes from any file. glTF puts `(0, 0)` at the
//! top-left with `v` down; its loader stores `1 - v` (see [`crate::formats::gltf`]).
//! Texel `(x, y)` (row `y` counted from the top of the image, as files store it) covers
//! `u ∈ [x, x + 1] / width`, `v ∈ [height - y - 1, height - y] / height`; its centre
//! is at `((x + ½) / width, 1 - (y + ½) / height)`.

mod binding;
mod decode;
mod mip;
mod sample;

pub(crate) use binding::untexture_where_no_uvs;
pub use binding::TextureRef;
pub use decode::{srgb_to_linear, ColorSpace, TextureError, MAX_TEXELS};
pub use sample::{Filter, TextureSampler, Wrap};

use crate::Color;

/// A decoded image: `width × height` linear-RGB texels, row by row from the top of the
/// image (as image files store them), and its mipmaps (`mip.rs`), built once when the
/// texture is made. Alpha is not kept.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Where it came from, for messages: a file path, or `file.glb image 0`.
    pub name: String,
    width: u32,
    height: u32,
    texels: Vec<Color>,
    /// Levels 1, 2, … down to 1 × 1 (empty for a 1 × 1 image, or after
    /// [`Texture::without_mipmaps`]).
    mips: Vec<mip::MipLevel>,
}

impl Texture {
    /// A texture of linear-RGB `texels`, row-major from the top row, with its mipmaps;
    /// `None` when the size is zero, above [`MAX_TEXELS`], or does not match
    /// `texels.len()`.
    pub fn from_linear(name: impl Into<String>, width: u32, height: u32, texels: Vec<Color>) -> Option<Self> {
        let n = (width as u64) * (height as u64);
        if !(n > 0 && n <= MAX_TEXELS && n == texels.len() as u64) {
            return None;
        }
        let mips = mip::pyramid(width, height, &texels);
        Some(Self { name: name.into(), width, height, texels, mips })
    }

    /// The same image without mipmaps: every lookup reads level 0, whatever its
    /// footprint (the unfiltered image, for comparisons; a data texture whose texels
    /// must not be averaged).
    pub fn without_mipmaps(mut self) -> Self {
        self.mips = Vec::new();
        self
    }

    /// Number of mip levels, level 0 (the image) included: `1 + ⌈log₂ max(width,
    /// height)⌉`, or 1 without mipmaps.
    pub fn levels(&self) -> usize {
        1 + self.mips.len()
    }

    /// Width and height of mip level `level` (0: the image); `None` past the last.
    pub fn level_size(&self, level: usize) -> Option<(u32, u32)> {
        match level {
            0 => Some((self.width, self.height)),
            k => self.mips.get(k - 1).map(|l| (l.width, l.height)),
        }
    }

    /// Texel `(x, y)` of mip level `level` (0: [`Texture::texel`]), `y` from the top
    /// row; black out of range.
    pub fn level_texel(&self, level: usize, x: u32, y: u32) -> Color {
        let (w, h, texels) = match level {
            0 => (self.width, self.height, &self.texels),
            k => match self.mips.get(k - 1) {
                Some(l) => (l.width, l.height, &l.texels),
                None => return Color::ZERO,
            },
        };
        if x >= w || y >= h {
            return Color::ZERO;
        }
        texels[y as usize * w as usize + x as usize]
    }

    /// Width in texels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Texel `(x, y)`, `y` counted from the top row; `x` and `y` must be in range
    /// (callers wrap first), otherwise black.
    pub fn texel(&self, x: u32, y: u32) -> Color {
        if x >= self.width || y >= self.height {
            return Color::ZERO;
        }
        self.texels[y as usize * self.width as usize + x as usize]
    }

    /// Bytes held by the texels, mipmaps included (about 4/3 of the image's).
    pub fn memory_bytes(&self) -> usize {
        let texels = self.texels.len() + self.mips.iter().map(|l| l.texels.len()).sum::<usize>();
        texels * std::mem::size_of::<Color>()
    }
}
