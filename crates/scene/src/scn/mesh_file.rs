//! `mesh { file "…" }`: the one place that turns a mesh file into parts, through the
//! general loader ([`crate::load`]), so every mesh format dynray reads works in scene
//! files. Scene files themselves are not meshes: including one goes through `include`.

use crate::load::{load_file_report, FileFormat};
use crate::{LoadError, Material};
use dynray_geom::TriangleMesh;
use std::path::Path;

/// Reads a mesh file as (mesh, material from the file) parts: one part per actor and
/// material, triangles in file order within each part. Lights and cameras of the file
/// are not taken: the scene file places its own.
pub(crate) fn load_mesh_file(path: &Path) -> Result<Vec<(TriangleMesh, Option<Material>)>, LoadError> {
    if FileFormat::of(path) == Some(FileFormat::Scn) {
        return Err(LoadError::parse(path, None, "a scene file is not a mesh: use `include` to read it"));
    }
    // PLY has no materials: its parts take the object's (or the scene's default) material.
    let has_materials = FileFormat::of(path) != Some(FileFormat::Ply);
    let scene = load_file_report(path)?.scene;
    let material = |id: u32| if has_materials { scene.materials.get(id as usize).cloned() } else { None };
    let mut parts = Vec::new();
    for actor in scene.actors {
        let mut ids: Vec<u32> = actor.materials.clone();
        ids.sort_unstable();
        ids.dedup();
        if let [only] = ids[..] {
            parts.push((actor.mesh, material(only)));
            continue;
        }
        for id in ids {
            let mut mesh = actor.mesh.clone();
            mesh.indices =
                actor.mesh.indices.iter().zip(&actor.materials).filter(|(_, &m)| m == id).map(|(t, _)| *t).collect();
            parts.push((mesh, material(id)));
        }
    }
    Ok(parts)
}
