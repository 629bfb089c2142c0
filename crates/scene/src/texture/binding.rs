//! How a material uses a texture ([`TextureRef`]: which one, sampled how, through which
//! uv transform, and the mip level a lookup's footprint asks for), and the load-time rule
//! that a textured material only lands on geometry with texture coordinates.

use super::{Texture, TextureSampler};
use crate::{Color, Material, Scene, Warning};
use dynray_geom::Vec2;
use glam::Affine2;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// A material's use of a texture of [`crate::Scene::textures`] (or the frame's copy of
/// that list, [`crate::Frame::textures`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into the scene's textures.
    pub texture: u32,
    /// Wrap modes and filter.
    pub sampler: TextureSampler,
    /// Applied to the surface's uv before sampling, in dynray's uv convention on both
    /// sides (see [`crate::texture`]): glTF's `KHR_texture_transform`, MTL's `-o`/`-s`.
    pub transform: Affine2,
}

impl TextureRef {
    /// Texture `texture` with the default sampler (repeat, bilinear) and no transform.
    pub fn new(texture: u32) -> Self {
        Self { texture, sampler: TextureSampler::default(), transform: Affine2::IDENTITY }
    }

    /// The texture's colour at the surface's `uv`; `None` when the index names no
    /// texture of `textures`.
    pub fn sample(&self, textures: &[Arc<Texture>], uv: Vec2) -> Option<Color> {
        let t = textures.get(self.texture as usize)?;
        Some(t.sample(self.transform.transform_point2(uv), &self.sampler))
    }

    /// The level of detail of a lookup of `texture` through this reference whose
    /// footprint is `uv_width` wide in the surface's uv units (before the transform):
    /// `log₂` of its width in texels of level 0, `uv_width · √|det T| · √(w · h)` (`T` the
    /// transform's linear part; the square roots are the geometric means of an
    /// anisotropic scale and of a non-square image, as in Akenine-Möller et al.,
    /// "Texture Level of Detail Strategies for Real-Time Ray Tracing", 2019). Level 0 is
    /// a footprint of one texel or less; `-∞` for a zero footprint, NaN for a NaN one
    /// (both read level 0).
    pub fn lod(&self, texture: &Texture, uv_width: f32) -> f32 {
        let scale = self.transform.matrix2.determinant().abs().sqrt();
        let texels = ((texture.width() as f64 * texture.height() as f64).sqrt()) as f32;
        (uv_width * scale * texels).log2()
    }

    /// [`TextureRef::sample`] for a lookup whose footprint is `uv_width` wide in uv
    /// units ([`TextureRef::lod`]): trilinear (or nearest-level) over the mipmaps; a
    /// footprint of at most a texel (0 included) is [`TextureRef::sample`] exactly.
    pub fn sample_footprint(&self, textures: &[Arc<Texture>], uv: Vec2, uv_width: f32) -> Option<Color> {
        let t = textures.get(self.texture as usize)?;
        Some(t.sample_lod(self.transform.transform_point2(uv), &self.sampler, self.lod(t, uv_width)))
    }
}

impl Material {
    /// The diffuse texture's colour at `uv`, white where the material has none (or it
    /// names no texture): what the diffuse and ambient colours are multiplied by. The
    /// one place shading reads a texture, so every integrator and AOV agree.
    pub fn diffuse_texel(&self, textures: &[Arc<Texture>], uv: Vec2) -> Color {
        self.diffuse_texture.as_ref().and_then(|t| t.sample(textures, uv)).unwrap_or(Color::ONE)
    }

    /// [`Material::diffuse_texel`] for a lookup whose footprint is `uv_width` wide in the
    /// surface's uv units (a ray cone's width at the hit, through the triangle's uv
    /// scale): filtered over the mipmaps ([`TextureRef::sample_footprint`]). A zero
    /// width is `diffuse_texel` exactly.
    pub fn diffuse_texel_filtered(&self, textures: &[Arc<Texture>], uv: Vec2, uv_width: f32) -> Color {
        self.diffuse_texture.as_ref().and_then(|t| t.sample_footprint(textures, uv, uv_width)).unwrap_or(Color::ONE)
    }
}

/// Gives actors without texture coordinates untextured copies of their textured
/// materials, with a warning each (naming `path`, the file loaded): their uvs would be
/// made up (zeros in a frame), so one texel would tint the whole surface.
pub(crate) fn untexture_where_no_uvs(scene: &mut Scene, path: &Path, warnings: &mut Vec<Warning>) {
    let mut copies: HashMap<u32, u32> = HashMap::new();
    for (a, actor) in scene.actors.iter_mut().enumerate() {
        if actor.mesh.uvs.is_some() {
            continue;
        }
        let mut warned: Vec<u32> = Vec::new();
        for id in &mut actor.materials {
            let Some(m) = scene.materials.get(*id as usize) else { continue };
            if m.diffuse_texture.is_none() {
                continue;
            }
            if !warned.contains(id) {
                warned.push(*id);
                let who = match &actor.name {
                    Some(n) => format!("`{n}` (object {a})"),
                    None => format!("object {a}"),
                };
                let what =
                    if m.name.is_empty() { "its material".to_string() } else { format!("material `{}`", m.name) };
                warnings.push(Warning::new(
                    path,
                    None,
                    format!(
                        "{who}: {what} has a texture but the mesh has no texture coordinates; \
                         it is rendered untextured"
                    ),
                ));
            }
            *id = *copies.entry(*id).or_insert_with(|| {
                let plain = Material { diffuse_texture: None, ..scene.materials[*id as usize].clone() };
                scene.materials.push(plain);
                scene.materials.len() as u32 - 1
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Actor;
    use dynray_geom::TriangleMesh;

    #[test]
    fn transform_applies_before_sampling() {
        // 2 × 1: left red, right green.
        let tex = vec![Arc::new(Texture::from_linear("t", 2, 1, vec![Color::X, Color::Y]).unwrap())];
        let mut r = TextureRef::new(0);
        r.sampler.filter = super::super::Filter::Nearest;
        assert_eq!(r.sample(&tex, Vec2::new(0.25, 0.5)), Some(Color::X));
        r.transform = Affine2::from_translation(Vec2::new(0.5, 0.0));
        assert_eq!(r.sample(&tex, Vec2::new(0.25, 0.5)), Some(Color::Y), "offset by half the width");
        assert_eq!(TextureRef::new(1).sample(&tex, Vec2::ZERO), None);
        let m = Material { diffuse_texture: Some(TextureRef::new(7)), ..Material::default() };
        assert_eq!(m.diffuse_texel(&tex, Vec2::ZERO), Color::ONE, "a bad index is untextured");
        assert_eq!(Material::default().diffuse_texel(&tex, Vec2::ZERO), Color::ONE);
    }

    #[test]
    fn lod_is_log2_of_the_footprint_in_texels() {
        let t = Texture::from_linear("t", 512, 512, vec![Color::ONE; 512 * 512]).unwrap();
        let r = TextureRef::new(0);
        assert_eq!(r.lod(&t, 1.0 / 512.0), 0.0, "one texel wide");
        assert_eq!(r.lod(&t, 4.0 / 512.0), 2.0);
        assert_eq!(r.lod(&t, 0.5 / 512.0), -1.0, "magnified");
        assert_eq!(r.lod(&t, 0.0), f32::NEG_INFINITY);
        // Non-square: the geometric mean of the sides (128 × 512 → 256).
        let tall = Texture::from_linear("t", 128, 512, vec![Color::ONE; 128 * 512]).unwrap();
        assert_eq!(r.lod(&tall, 1.0 / 256.0), 0.0);
        // A transform that tiles the texture 4 × 4 makes every uv unit 4 images wide;
        // an anisotropic 2 × 8 scale counts as 4 (√16).
        let tiled = TextureRef { transform: Affine2::from_scale(Vec2::splat(4.0)), ..r };
        assert_eq!(tiled.lod(&t, 1.0 / 512.0), 2.0);
        let stretched = TextureRef { transform: Affine2::from_scale(Vec2::new(2.0, 8.0)), ..r };
        assert_eq!(stretched.lod(&t, 1.0 / 512.0), 2.0);
        // Through the material: width 0 is the point lookup, a wide footprint the mean.
        let checker: Vec<Color> = (0..64).map(|i| Color::splat(((i % 8 + i / 8) % 2) as f32)).collect();
        let tex = vec![Arc::new(Texture::from_linear("c", 8, 8, checker).unwrap())];
        let m = Material { diffuse_texture: Some(r), ..Material::default() };
        let uv = Vec2::new(1.5 / 8.0, 1.0 - 0.5 / 8.0);
        assert_eq!(m.diffuse_texel_filtered(&tex, uv, 0.0), m.diffuse_texel(&tex, uv));
        assert_eq!(m.diffuse_texel(&tex, uv), Color::ONE);
        assert!((m.diffuse_texel_filtered(&tex, uv, 2.0 / 8.0) - Color::splat(0.5)).abs().max_element() < 1e-6);
        assert_eq!(Material::default().diffuse_texel_filtered(&tex, uv, 1.0), Color::ONE);
    }

    #[test]
    fn textured_materials_leave_meshes_without_uvs() {
        let tri = || TriangleMesh::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]);
        let textured =
            Material { name: "wood".into(), diffuse_texture: Some(TextureRef::new(0)), ..Default::default() };
        let mut s = Scene { materials: vec![textured.clone()], ..Default::default() };
        let mut with_uvs = tri();
        with_uvs.uvs = Some(vec![[0.0; 2]; 3]);
        s.actors.push(Actor::new(Some("a".into()), with_uvs, 0));
        s.actors.push(Actor::new(Some("b".into()), tri(), 0));
        s.actors.push(Actor::new(None, tri(), 0));
        let mut w = Vec::new();
        untexture_where_no_uvs(&mut s, Path::new("x.scn"), &mut w);
        assert_eq!(s.actors[0].materials, vec![0], "the actor with uvs keeps the texture");
        assert_eq!(s.actors[1].materials, vec![1]);
        assert_eq!(s.actors[2].materials, vec![1], "one untextured copy, shared");
        assert_eq!(s.materials.len(), 2);
        assert_eq!(s.materials[1], Material { diffuse_texture: None, ..textured });
        assert_eq!(w.len(), 2);
        assert!(w[0].to_string().starts_with("x.scn: `b` (object 1): material `wood` has a texture"), "{}", w[0]);
        assert!(w[1].message.starts_with("object 2:"), "{}", w[1]);
    }
}
