//! Distance fields placed in a scene (`.scn` `adf { file … }`, docs/scene-language.md).
//!
//! The scene only names the field's file: its format and its ray query belong to
//! `dynray-adf`, which builds on this crate, so the caller that renders a frame loads
//! each file and puts the field beside the triangles in the scene-level intersector.

use crate::Transform;
use std::path::PathBuf;

/// One distance field in the scene: which file, where, and how it is shaded.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldPlacement {
    /// The `.adf` file, resolved against the directory of the scene file that names it.
    pub file: PathBuf,
    /// Field-to-world transform (affine; the identity leaves the field where it was built).
    pub transform: Transform,
    /// Index into the scene's (and frame's) materials.
    pub material: u32,
}
