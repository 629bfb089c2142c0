//! Textures of a scene file: `material { … texture "file" }` and the textures that mesh
//! files bring with their materials, in one list that materials name by index while the
//! file is read. `.scn` texture files are only decoded when the scene is built, and only
//! those a placed object's material uses, each file once; one that cannot be read is a
//! warning naming it and the line that referenced it, and the material is untextured.

use super::parser::{Parser, R};
use crate::texture::ColorSpace;
use crate::{Scene, Texture, TextureRef, Warning};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// A texture materials may name while the scene file is read.
pub(crate) enum SceneTexture {
    /// Decoded already (it came with a mesh file's materials).
    Decoded(Arc<Texture>),
    /// A `.scn` `texture` statement: the image file, and where it was first named (the
    /// scene file as diagnostics show it, 1-based line) for the warning if it fails.
    File { path: PathBuf, named_in: PathBuf, line: usize },
}

impl Parser<'_> {
    /// `texture "file"` inside `material { … }` (the key already read): the texture's
    /// index. The path is relative to this file's directory; naming one file twice gives
    /// one texture.
    pub(crate) fn texture_param(&mut self) -> R<u32> {
        let (rel, span) = self.string("a quoted image file name")?;
        let path = self.dir.join(&rel);
        if let Some(&i) = self.st.texture_files.get(&path) {
            return Ok(i);
        }
        let named_in = PathBuf::from(self.st.sources.name(self.file));
        let line = self.st.sources.line(self.file, span.start);
        self.st.textures.push(SceneTexture::File { path: path.clone(), named_in, line });
        let i = self.st.textures.len() as u32 - 1;
        self.st.texture_files.insert(path, i);
        Ok(i)
    }

    /// Appends a mesh file's decoded textures and returns the index its first one takes,
    /// by which the file's own texture indices are shifted.
    pub(crate) fn add_decoded_textures(&mut self, textures: Vec<Arc<Texture>>) -> u32 {
        let base = self.st.textures.len() as u32;
        self.st.textures.extend(textures.into_iter().map(SceneTexture::Decoded));
        base
    }
}

/// Gives `scene` the textures its materials use: decodes the `.scn` files among them
/// (warning for each that fails, whose materials then lose the texture) and renumbers
/// the materials' indices into [`Scene::textures`].
pub(crate) fn resolve(scene: &mut Scene, textures: Vec<SceneTexture>, warnings: &mut Vec<Warning>) {
    let mut textures: Vec<Option<SceneTexture>> = textures.into_iter().map(Some).collect();
    // Parse-time index -> scene index (`None`: failed).
    let mut done: HashMap<u32, Option<u32>> = HashMap::new();
    for m in &mut scene.materials {
        let Some(r) = &mut m.diffuse_texture else { continue };
        let resolved = *done.entry(r.texture).or_insert_with(|| {
            let texture = match textures.get_mut(r.texture as usize).and_then(Option::take)? {
                SceneTexture::Decoded(t) => t,
                SceneTexture::File { path, named_in, line } => match Texture::load(&path, ColorSpace::Srgb) {
                    Ok(t) => Arc::new(t),
                    Err(e) => {
                        warnings.push(Warning::new(
                            &named_in,
                            Some(line),
                            format!("texture: {e}; the material is untextured"),
                        ));
                        return None;
                    }
                },
            };
            scene.textures.push(texture);
            Some(scene.textures.len() as u32 - 1)
        });
        match resolved {
            Some(i) => r.texture = i,
            None => m.diffuse_texture = None,
        }
    }
}

/// A texture reference of a mesh file's material, shifted into the scene file's list.
pub(crate) fn shifted(r: TextureRef, base: u32) -> TextureRef {
    TextureRef { texture: r.texture + base, ..r }
}
