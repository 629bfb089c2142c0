//! `adf { file "…" [material …] [transform …]* }`: a distance field (seed 001, built
//! by `dynray adf build`) placed in the scene beside the meshes (docs §5.6).
//!
//! The parser checks that the file exists, at the string that names it; reading it is
//! the renderer's (the format belongs to `dynray-adf`, which builds on this crate).

use super::diag::FileId;
use super::parser::{Parser, Span, R};
use crate::Material;
use glam::DMat4;
use std::path::PathBuf;
use std::rc::Rc;

/// A parsed `adf` statement.
pub(crate) struct FieldEntry {
    /// The file, resolved against the including file's directory.
    pub file: PathBuf,
    /// Field-to-world: the block's transforms, later ones applied after earlier ones.
    pub transform: DMat4,
    /// `None`: the scene's default material.
    pub material: Option<Rc<Material>>,
    /// The statement, for errors found when the scene is built.
    pub at: (FileId, Span),
}

impl Parser<'_> {
    /// The `adf` statement (the keyword is the current token).
    pub(crate) fn distance_field(&mut self) -> R<FieldEntry> {
        let start = self.bump().span;
        let mut file = None;
        let mut transform = DMat4::IDENTITY;
        let mut material = None;
        let block = self.block("adf", &["file", "material", "transform"], &["transform"], |p, key, span| {
            match key {
                "file" => {
                    let (rel, s) = p.string("a quoted .adf file name")?;
                    let path = p.dir.join(&rel);
                    if !path.is_file() {
                        return Err(p
                            .err(s, format!("no distance field `{rel}`"))
                            .label("this file does not exist")
                            .note(format!(
                                "looked for {}; make one with `dynray adf build MESH -o FILE.adf`",
                                path.display()
                            )));
                    }
                    file = Some(path);
                }
                "material" => material = Some(p.material()?),
                "transform" => transform = p.transform()? * transform,
                other => return Err(p.unhandled(span, other, "adf")),
            }
            Ok(())
        })?;
        let file = self.required(file, "file", "adf", &block)?;
        Ok(FieldEntry { file, transform, material, at: (self.file, start.start..block.end) })
    }
}
