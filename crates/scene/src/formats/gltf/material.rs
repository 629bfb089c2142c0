//! glTF materials: `baseColorFactor` (and alpha for `BLEND`) into [`Material`],
//! `emissiveFactor` times `KHR_materials_emissive_strength` into its emission (the
//! radiance the path tracer's area lights emit; `emissiveTexture` is not read), and the
//! `baseColorTexture` with its sampler and `KHR_texture_transform`, decoded only for
//! materials that some primitive uses, each image once.

use super::uri::{self, Uri};
use crate::texture::{ColorSpace, Filter, TextureSampler, Wrap};
use crate::{Finish, Material, Scene, Texture, TextureRef, Warning};
use glam::{Affine2, Mat2, Vec2};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// The dynray material for a glTF material, without its texture ([`attach_textures`]
/// adds that).
pub(super) fn convert(m: &gltf::Material, path: &Path, warnings: &mut Vec<Warning>) -> Material {
    let [r, g, b, a] = m.pbr_metallic_roughness().base_color_factor();
    let mut mat = Material::from_finish(m.name().unwrap_or(""), glam::Vec3::new(r, g, b), &Finish::default());
    if m.alpha_mode() == gltf::material::AlphaMode::Blend {
        mat.transparency = glam::Vec3::splat((1.0 - a).clamp(0.0, 1.0));
    }
    // Linear RGB radiance (glTF's emissive colour is linear, like its base colour);
    // negative values emit nothing; a product past f32 is said, not rendered black.
    let strength = m.emissive_strength().unwrap_or(1.0);
    let emission = glam::Vec3::from_array(m.emissive_factor()) * strength;
    mat.emission = if emission.is_finite() {
        emission.max(glam::Vec3::ZERO)
    } else {
        let which = m.index().map_or_else(|| "the default material".to_string(), |i| format!("material {i}"));
        warnings.push(Warning::new(
            path,
            None,
            format!(
                "{which}: emissiveFactor {:?} × emissive strength {strength} is not a finite radiance; it emits nothing",
                m.emissive_factor()
            ),
        ));
        glam::Vec3::ZERO
    };
    mat
}

/// Where the glTF's images come from, and those decoded so far.
pub(super) struct Images<'a> {
    /// The `.gltf`/`.glb` file (names warnings and embedded images).
    pub path: &'a Path,
    /// Its directory, for relative URIs.
    pub base: &'a Path,
    pub buffers: &'a [Vec<u8>],
    /// Per glTF image, why it cannot be read (found in the JSON before gltf would
    /// unwrap on it), or `None`.
    problems: Vec<Option<&'static str>>,
    /// glTF image index -> texture index in the scene (`None`: failed, warned once).
    decoded: HashMap<usize, Option<u32>>,
}

impl<'a> Images<'a> {
    pub fn new(path: &'a Path, base: &'a Path, buffers: &'a [Vec<u8>], problems: Vec<Option<&'static str>>) -> Self {
        Self { path, base, buffers, problems, decoded: HashMap::new() }
    }
}

/// Gives the scene's materials `0..document.materials().len()` that some actor uses their
/// `baseColorTexture`. Images are decoded on first use; one that cannot be read or
/// decoded is a warning naming it, and its materials stay untextured.
pub(super) fn attach_textures(
    scene: &mut Scene,
    document: &gltf::Document,
    images: &mut Images,
    warnings: &mut Vec<Warning>,
) {
    let mut used = vec![false; document.materials().len()];
    for id in scene.actors.iter().flat_map(|a| a.materials.iter()) {
        if let Some(u) = used.get_mut(*id as usize) {
            *u = true;
        }
    }
    for m in document.materials().filter(|m| m.index().is_some_and(|i| used[i])) {
        let Some(i) = m.index() else { continue };
        let Some(info) = m.pbr_metallic_roughness().base_color_texture() else { continue };
        let label =
            format!("material {i} `{}`: base colour texture {}", m.name().unwrap_or(""), info.texture().index());
        let set = info.texture_transform().and_then(|t| t.tex_coord()).unwrap_or(info.tex_coord());
        if set != 0 {
            warnings.push(Warning::new(
                images.path,
                None,
                format!("{label} uses TEXCOORD_{set}; dynray reads TEXCOORD_0 only, so the material is untextured"),
            ));
            continue;
        }
        let Some(texture) = image_texture(scene, &info.texture().source(), images, &label, warnings) else {
            continue;
        };
        let tex = info.texture();
        let sampler = tex.sampler();
        let wrap = |w: gltf::texture::WrappingMode| match w {
            gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
            gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
            gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
        };
        let filter = match sampler.mag_filter() {
            Some(gltf::texture::MagFilter::Nearest) => Filter::Nearest,
            _ => Filter::Bilinear,
        };
        let transform = info.texture_transform().map_or(Affine2::IDENTITY, |t| {
            to_dynray_uv(khr_texture_transform(t.offset().into(), t.rotation(), t.scale().into()))
        });
        scene.materials[i].diffuse_texture = Some(TextureRef {
            texture,
            sampler: TextureSampler { wrap_u: wrap(sampler.wrap_s()), wrap_v: wrap(sampler.wrap_t()), filter },
            transform,
        });
    }
}

/// The scene texture for glTF image `image`, decoding it on first use.
fn image_texture(
    scene: &mut Scene,
    image: &gltf::Image,
    images: &mut Images,
    label: &str,
    warnings: &mut Vec<Warning>,
) -> Option<u32> {
    if let Some(done) = images.decoded.get(&image.index()) {
        return *done;
    }
    let decoded = decode_image(image, images);
    let id = match decoded {
        Ok(t) => {
            scene.textures.push(Arc::new(t));
            Some(scene.textures.len() as u32 - 1)
        }
        Err(m) => {
            warnings.push(Warning::new(images.path, None, format!("{label}: {m}; the material is untextured")));
            None
        }
    };
    images.decoded.insert(image.index(), id);
    id
}

/// Reads and decodes one glTF image (sRGB: it is a base colour).
fn decode_image(image: &gltf::Image, images: &Images) -> Result<Texture, String> {
    let embedded = format!("{} image {}", images.path.display(), image.index());
    if let Some(problem) = images.problems.get(image.index()).copied().flatten() {
        return Err(format!("{embedded} {problem}"));
    }
    match image.source() {
        gltf::image::Source::View { view, mime_type } => {
            let bytes = uri::view_bytes(&view, images.buffers).map_err(|m| format!("{embedded}: {m}"))?;
            Texture::decode(embedded, bytes, mime_extension(mime_type), ColorSpace::Srgb).map_err(|e| e.to_string())
        }
        gltf::image::Source::Uri { uri, mime_type } => {
            let parsed = uri::parse(images.base, uri).map_err(|m| format!("image {}: {m}", image.index()))?;
            let (name, ext) = match &parsed {
                Uri::Data { media_type, .. } => (format!("{embedded} (data URI)"), mime_extension(media_type)),
                Uri::File(f) => (
                    f.display().to_string(),
                    mime_type.and_then(mime_extension).or_else(|| f.extension().and_then(|e| e.to_str())),
                ),
            };
            let bytes = uri::read(images.base, uri)?;
            Texture::decode(name, &bytes, ext, ColorSpace::Srgb).map_err(|e| e.to_string())
        }
    }
}

/// The file extension a glTF image MIME type stands for (the decoder guesses from the
/// content first; this is the fallback).
fn mime_extension(mime: &str) -> Option<&'static str> {
    match mime {
        "image/png" => Some("png"),
        "image/jpeg" => Some("jpg"),
        _ => None,
    }
}

/// `KHR_texture_transform`'s matrix, `translation × rotation × scale`, in glTF's uv
/// space (the extension's spec, whose rotation matrix turns `(1, 0)` to `(cos, -sin)`).
fn khr_texture_transform(offset: Vec2, rotation: f32, scale: Vec2) -> Affine2 {
    let (s, c) = rotation.sin_cos();
    let rot = Mat2::from_cols(Vec2::new(c, -s), Vec2::new(s, c));
    Affine2::from_mat2_translation(rot * Mat2::from_diagonal(scale), offset)
}

/// A transform of glTF uvs as one of dynray uvs: dynray's `(u, v)` is glTF's
/// `(u, 1 - v)`, a flip that is its own inverse, so the result is `flip ∘ t ∘ flip`.
fn to_dynray_uv(t: Affine2) -> Affine2 {
    let flip = Affine2::from_mat2_translation(Mat2::from_diagonal(Vec2::new(1.0, -1.0)), Vec2::new(0.0, 1.0));
    flip * t * flip
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec2, b: Vec2) -> bool {
        (a - b).abs().max_element() < 1e-5
    }

    #[test]
    fn texture_transform_follows_the_extension_spec() {
        // The extension's example: offset (0.5, 0), rotation π/2, scale (2, 2) takes glTF
        // uv (1, 0) through scale (2, 0), rotation (0, -2) and offset (0.5, -2).
        let t = khr_texture_transform(Vec2::new(0.5, 0.0), std::f32::consts::FRAC_PI_2, Vec2::splat(2.0));
        assert!(close(t.transform_point2(Vec2::new(1.0, 0.0)), Vec2::new(0.5, -2.0)));
        assert!(close(t.transform_point2(Vec2::ZERO), Vec2::new(0.5, 0.0)));
        // Conjugated by the flip: dynray (1, 1) is glTF (1, 0) -> glTF (0.5, -2) -> dynray (0.5, 3).
        let d = to_dynray_uv(t);
        assert!(close(d.transform_point2(Vec2::new(1.0, 1.0)), Vec2::new(0.5, 3.0)));
        assert_eq!(to_dynray_uv(Affine2::IDENTITY), Affine2::IDENTITY);
        // An offset in glTF's v (down) is the opposite offset in dynray's v (up).
        let down = to_dynray_uv(khr_texture_transform(Vec2::new(0.0, 0.25), 0.0, Vec2::ONE));
        assert!(close(down.transform_point2(Vec2::new(0.3, 0.5)), Vec2::new(0.3, 0.25)));
    }
}
