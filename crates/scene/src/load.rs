//! One entry point for mesh and scene files: picks the loader from the file name and
//! turns what it reads into a [`Scene`].
//!
//! Formats, chosen by extension (case-insensitive): `.npz` numpy arrays
//! ([`crate::formats::npz`]), `.ply` and `.ply.gz` ([`crate::formats::ply`]), `.obj` with its `.mtl` ([`crate::formats::obj`]), `.gltf` and
//! `.glb` ([`crate::formats::gltf`]), BART's animated scenes and NFF, `.aff` and `.nff`
//! ([`crate::formats::aff`]), and scene files in seed 003's language, `.scn`
//! ([`crate::scn`]).
//!
//! What every loaded file becomes: its meshes as actors (each in its own space with the
//! transform that places it, see [`crate::Actor`]), its materials (or one default material
//! when it has none), and its lights: OBJ emitters (`Ke`) and glTF `KHR_lights_punctual`
//! lights, or, for a mesh file without any, one default point light
//! ([`Scene::add_default_light`]). A mesh file without a camera gets the default view
//! ([`Camera::default_view`]: from the front, or into an enclosure's open side). A scene
//! file (`.scn`) is taken as written: no light added (a warning says when it has none)
//! and, without a `camera`, the same default view.
//!
//! Shading normals (`shading.rs`): [`load_file`] and [`load_file_report`] give every actor
//! the normals its [`crate::Shading`] asks for — a mesh file without normals gets smooth,
//! angle-weighted ones — so the scene is ready to render. [`load_file_unshaded`] and
//! [`load_mesh`] return the files' vertices as they are (no generated normals, no split
//! vertices), for callers that want geometry or choose their own shading.
//!
//! Problems that do not stop loading (a missing `.mtl` file, an unknown material name, a
//! glTF point primitive that is skipped, a texture that cannot be read or decoded, any
//! of these in a mesh file that a `.scn` reads)
//! are returned as [`Warning`](crate::Warning)s in a [`LoadReport`](crate::LoadReport)
//! (`report.rs`) by [`load_file_report`]; [`load_file`] drops them. A library does not
//! print: the caller (the binary) decides whether to show them.

use crate::{Actor, Camera, LoadError, LoadReport, Material, Scene, Warning};
use dynray_geom::TriangleMesh;
use std::path::Path;

/// The file formats [`load_file`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileFormat {
    /// Stanford PLY, ASCII or binary, optionally gzip-compressed.
    Ply,
    /// Wavefront OBJ with MTL material libraries.
    Obj,
    /// glTF 2.0, JSON (`.gltf`) or binary (`.glb`).
    Gltf,
    /// A mesh as numpy arrays (`vertices` (N, 3), `faces` (M, 3)) in an `.npz` archive.
    Npz,
    /// A scene in seed 003's scene language.
    Scn,
    /// BART's AFF (NFF with animation), `.aff`, or plain NFF, `.nff`.
    Aff,
    /// A Mitsuba 3 scene, `.xml`.
    Mitsuba,
}

impl FileFormat {
    /// The format named by `path`'s extension (case-insensitive), if dynray reads it.
    pub fn of(path: &Path) -> Option<FileFormat> {
        let name = path.file_name()?.to_string_lossy().to_ascii_lowercase();
        let ends = |s: &str| name.len() > s.len() && name.ends_with(s);
        if ends(".ply") || ends(".ply.gz") {
            Some(FileFormat::Ply)
        } else if ends(".obj") {
            Some(FileFormat::Obj)
        } else if ends(".gltf") || ends(".glb") {
            Some(FileFormat::Gltf)
        } else if ends(".npz") {
            Some(FileFormat::Npz)
        } else if ends(".scn") {
            Some(FileFormat::Scn)
        } else if ends(".aff") || ends(".nff") {
            Some(FileFormat::Aff)
        } else if ends(".xml") {
            Some(FileFormat::Mitsuba)
        } else {
            None
        }
    }
}

/// Loads a mesh or scene file into a [`Scene`]; warnings are dropped (see
/// [`load_file_report`] to get them).
pub fn load_file(path: &Path) -> Result<Scene, LoadError> {
    load_file_report(path).map(|r| r.scene)
}

/// Loads any file dynray reads as one world-space triangle mesh: every actor placed by
/// its transform and concatenated in order (the mesh of the unshaded scene's frame at
/// time 0), for library users who only want geometry to build a structure over. The
/// file's vertices come as they are: normals only where the file has them, none
/// generated, no vertex split. Materials, lights and warnings are dropped (use
/// [`load_file_report`] for those).
pub fn load_mesh(path: &Path) -> Result<TriangleMesh, LoadError> {
    Ok(load_file_unshaded(path)?.scene.frame(0.0).mesh)
}

/// Loads a mesh or scene file into a [`Scene`] ready to render (each actor's shading
/// applied, see the module docs) and returns the warnings met on the way.
pub fn load_file_report(path: &Path) -> Result<LoadReport, LoadError> {
    let mut report = load_file_unshaded(path)?;
    report.scene.apply_shading().map_err(|source| LoadError::Mesh { path: path.to_path_buf(), source })?;
    Ok(report)
}

/// Loads a mesh or scene file as [`load_file_report`] does, but leaves each actor's
/// normals as the files give them: its [`crate::Actor::shading`] records what was asked,
/// and [`Scene::apply_shading`] does it.
pub fn load_file_unshaded(path: &Path) -> Result<LoadReport, LoadError> {
    let mut report = load_own(path)?;
    let scene = &mut report.scene;
    let format = FileFormat::of(path);
    if format == Some(FileFormat::Mitsuba) {
        // A scene file taken as written: its emitters are its lights.
        let emissive = scene.materials.iter().any(|m| m.emission.max_element() > 0.0);
        if scene.lights.is_empty() && !emissive && scene.environment.background == crate::Color::ZERO {
            report.warnings.push(Warning::new(path, None, "the scene has no emitters: it renders black"));
        }
    } else if format == Some(FileFormat::Scn) {
        if scene.lights.is_empty() && !scene.actors.is_empty() {
            let a = scene.environment.ambient;
            report.warnings.push(Warning::new(
                path,
                None,
                format!(
                    "the scene has no lights: only its ambient light (rgb({}, {}, {})) reaches the image",
                    a.x, a.y, a.z
                ),
            ));
        }
    } else {
        scene.add_default_light();
    }
    if scene.camera.is_none() && !scene.actors.is_empty() {
        scene.camera = Some(Camera::default_view(scene));
    }
    Ok(report)
}

/// What a file itself holds — its actors, materials, lights and camera — unshaded and
/// without the defaults [`load_file_unshaded`] adds: what a `.scn`'s `mesh { file }`
/// takes from it.
pub(crate) fn load_own(path: &Path) -> Result<LoadReport, LoadError> {
    let format = FileFormat::of(path).ok_or_else(|| LoadError::UnknownFormat { path: path.to_path_buf() })?;
    match format {
        FileFormat::Ply | FileFormat::Npz => {
            let mesh = if format == FileFormat::Ply {
                crate::formats::ply::load(path)?
            } else {
                crate::formats::npz::load(path)?
            };
            let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
            let mut scene = Scene { materials: vec![Material::default()], ..Default::default() };
            scene.actors.push(Actor::new(name, mesh, 0));
            Ok(LoadReport { scene, warnings: Vec::new() })
        }
        FileFormat::Obj => crate::formats::obj::load(path),
        FileFormat::Gltf => crate::formats::gltf::load(path),
        FileFormat::Scn => crate::scn::load_scn_unshaded(path),
        FileFormat::Aff => crate::formats::aff::load(path),
        FileFormat::Mitsuba => crate::formats::mitsuba::load(path),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_are_case_insensitive_and_need_a_stem() {
        assert_eq!(FileFormat::of(Path::new("a/B.PLY")), Some(FileFormat::Ply));
        assert_eq!(FileFormat::of(Path::new("dragon.ply.GZ")), Some(FileFormat::Ply));
        assert_eq!(FileFormat::of(Path::new("box.Obj")), Some(FileFormat::Obj));
        assert_eq!(FileFormat::of(Path::new("duck.glb")), Some(FileFormat::Gltf));
        assert_eq!(FileFormat::of(Path::new("duck.gltf")), Some(FileFormat::Gltf));
        assert_eq!(FileFormat::of(Path::new("x.gz")), None);
        assert_eq!(FileFormat::of(Path::new(".obj")), None);
        assert_eq!(FileFormat::of(Path::new("whitted.SCN")), Some(FileFormat::Scn));
        assert_eq!(FileFormat::of(Path::new("scene.txt")), None);
        assert_eq!(FileFormat::of(Path::new("kitchen.aff")), Some(FileFormat::Aff));
        assert_eq!(FileFormat::of(Path::new("balls.NFF")), Some(FileFormat::Aff));
        assert_eq!(FileFormat::of(Path::new("")), None);
        assert_eq!(FileFormat::of(Path::new("cbox.XML")), Some(FileFormat::Mitsuba));
    }
}
