//! Materials of AFF/NFF (`f`, BART's `fm`) and the PPM textures of textured triangles
//! (`tt`, `ttp`) and meshes (`texturecoords N file`).
//!
//! | command | dynray |
//! |---|---|
//! | `f r g b Kd Ks shine T ior` | `diffuse = rgb·Kd`, `ambient = rgb·0.1` (the default finish's ambient share), `spot = specular = Ks` (NFF's one specular coefficient is both the highlight and the mirror weight), `shine`, `transparency = T`, `ior` |
//! | `fm ambient(3) diffuse(3) specular(3) shine T ior` | `ambient`, `diffuse`, `spot = specular = specular(3)`, `shine`, `transparency = T`, `ior` |
//!
//! A textured primitive uses the material in effect with the texture multiplying its
//! diffuse and ambient colours (one derived material per material and texture). Texture
//! files are looked for next to the file that names them, then in `../TextureFiles/`
//! beside it and beside the top-level file (BART's layout: `aff/` and `TextureFiles/`
//! side by side). A texture that cannot be found or decoded is a [`Warning`] and the
//! primitive gets the plain material, as the other loaders do.

use super::lexer::Tokens;
use crate::texture::ColorSpace;
use crate::{Color, LoadError, Material, Scene, Texture, TextureRef, Warning};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The materials read so far, the one in effect, and the textures loaded.
#[derive(Default)]
pub(super) struct Materials {
    /// The material of the last `f`/`fm`, or `None` before the first.
    current: Option<u32>,
    /// The default material's index once something used it.
    default: Option<u32>,
    /// Texture file → index in the scene's textures (`None`: it failed, warned once).
    loaded: HashMap<PathBuf, Option<u32>>,
    /// (material, texture) → the textured copy.
    textured: HashMap<(u32, u32), u32>,
    /// Directory of the top-level file.
    pub root_dir: PathBuf,
}

impl Materials {
    /// Reads `f r g b Kd Ks shine T ior` (after the `f`) and makes it current.
    pub fn read_f(&mut self, t: &mut Tokens<'_>, scene: &mut Scene) -> Result<(), LoadError> {
        let rgb = Color::from_array(t.vec3("`f` colour")?);
        let kd = t.number("`f` Kd")?;
        let ks = t.number("`f` Ks")?;
        let shine = t.number("`f` shine")?;
        let tr = t.number("`f` transmittance")?;
        let ior = t.number("`f` index of refraction")?;
        let m = Material {
            name: format!("f@{}", t.line()),
            ambient: rgb * 0.1,
            diffuse: rgb * kd,
            spot: Color::splat(ks),
            shine,
            specular: Color::splat(ks),
            transparency: Color::splat(tr),
            ior: if ior > 0.0 { ior } else { 1.0 },
            diffuse_texture: None,
            emission: Color::ZERO,
            bsdf: None,
        };
        self.push(scene, m);
        Ok(())
    }

    /// Reads BART's `fm ambient diffuse specular shine T ior` (after the `fm`).
    pub fn read_fm(&mut self, t: &mut Tokens<'_>, scene: &mut Scene) -> Result<(), LoadError> {
        let line = t.line();
        let ambient = Color::from_array(t.vec3("`fm` ambient colour")?);
        let diffuse = Color::from_array(t.vec3("`fm` diffuse colour")?);
        let specular = Color::from_array(t.vec3("`fm` specular colour")?);
        let shine = t.number("`fm` shine")?;
        let tr = t.number("`fm` transmittance")?;
        let ior = t.number("`fm` index of refraction")?;
        let m = Material {
            name: format!("fm@{line}"),
            ambient,
            diffuse,
            spot: specular,
            shine,
            specular,
            transparency: Color::splat(tr),
            // BART writes 0 for "not refractive".
            ior: if ior > 0.0 { ior } else { 1.0 },
            diffuse_texture: None,
            emission: Color::ZERO,
            bsdf: None,
        };
        self.push(scene, m);
        Ok(())
    }

    fn push(&mut self, scene: &mut Scene, m: Material) {
        scene.materials.push(m);
        self.current = Some(scene.materials.len() as u32 - 1);
    }

    /// The material in effect (the default material before any `f`/`fm`).
    pub fn current(&mut self, scene: &mut Scene) -> u32 {
        if let Some(c) = self.current {
            return c;
        }
        *self.default.get_or_insert_with(|| {
            scene.materials.push(Material::default());
            scene.materials.len() as u32 - 1
        })
    }

    /// The current material textured with image `name`, named at `line` of `file`;
    /// the plain material (and a warning) when the image cannot be read.
    pub fn textured(
        &mut self,
        scene: &mut Scene,
        warnings: &mut Vec<Warning>,
        file: &Path,
        line: usize,
        name: &str,
    ) -> u32 {
        let material = self.current(scene);
        let path = match self.root().check(&self.find(file, name)) {
            Ok(p) => p,
            Err(e) => {
                warnings.push(Warning::new(file, Some(line), format!("texture `{name}`: {e}; rendered untextured")));
                return material;
            }
        };
        let texture =
            *self.loaded.entry(path.clone()).or_insert_with(|| match Texture::load(&path, ColorSpace::Srgb) {
                Ok(tex) => {
                    scene.textures.push(Arc::new(tex));
                    Some(scene.textures.len() as u32 - 1)
                }
                Err(e) => {
                    warnings.push(Warning::new(
                        file,
                        Some(line),
                        format!("texture `{name}`: {e}; rendered untextured"),
                    ));
                    None
                }
            });
        let Some(texture) = texture else { return material };
        *self.textured.entry((material, texture)).or_insert_with(|| {
            let base = &scene.materials[material as usize];
            let m = Material {
                name: format!("{} + {name}", base.name),
                diffuse_texture: Some(TextureRef::new(texture)),
                ..base.clone()
            };
            scene.materials.push(m);
            scene.materials.len() as u32 - 1
        })
    }

    /// The folders the scene's files must stay in ([`crate::reference`]): the top-level
    /// file's, and BART's `TextureFiles/` beside it.
    pub fn root(&self) -> crate::reference::Root {
        crate::reference::Root::folder(&self.root_dir, &[self.root_dir.join("..").join("TextureFiles")])
    }

    /// Where texture `name` named in `file` is (module docs); the first candidate when
    /// none exists, so the warning names the obvious place.
    fn find(&self, file: &Path, name: &str) -> PathBuf {
        let dir = file.parent().unwrap_or(Path::new(""));
        let candidates = [
            dir.join(name),
            dir.join("..").join("TextureFiles").join(name),
            self.root_dir.join("..").join("TextureFiles").join(name),
            self.root_dir.join(name),
        ];
        candidates.iter().find(|p| p.is_file()).unwrap_or(&candidates[0]).clone()
    }
}
