//! `mesh { file "…" }`: the one place that turns a mesh file into parts, through the
//! general loader ([`crate::load_file_unshaded`]), so every mesh format dynray reads works in scene
//! files. Scene files themselves are not meshes: including one goes through `include`.

use crate::load::{load_file_unshaded, FileFormat};
use crate::{LoadError, Material, Warning};
use dynray_geom::TriangleMesh;
use std::path::Path;

/// A mesh file read as parts: (world-space mesh, material from the file).
pub(crate) type Parts = Vec<(TriangleMesh, Option<Material>)>;

/// Reads a mesh file as parts: one part per actor and material, triangles in file order
/// within each part, in the file's own world space (a glTF node's matrix is applied
/// here, since the scene file's transform composes with it). Lights and cameras of the
/// file are not taken: the scene file places its own. The loader's warnings (a missing
/// `.mtl`, say) come back with the parts, naming the mesh file, for the scene's report.
pub(crate) fn load_mesh_file(path: &Path) -> Result<(Parts, Vec<Warning>), LoadError> {
    if FileFormat::of(path) == Some(FileFormat::Scn) {
        return Err(LoadError::parse(path, None, "a scene file is not a mesh: use `include` to read it"));
    }
    // PLY has no materials: its parts take the object's (or the scene's default) material.
    let has_materials = FileFormat::of(path) != Some(FileFormat::Ply);
    // Unshaded: the normals the file has; the `mesh` block's `shading` decides the rest
    // once the scene is built.
    let report = load_file_unshaded(path)?;
    let scene = report.scene;
    let material = |id: u32| if has_materials { scene.materials.get(id as usize).cloned() } else { None };
    let mut parts = Vec::new();
    for actor in scene.actors {
        let mut ids: Vec<u32> = actor.materials.clone();
        ids.sort_unstable();
        ids.dedup();
        let mut world = actor.mesh;
        actor.transform.apply(&mut world);
        if let [only] = ids[..] {
            parts.push((world, material(only)));
            continue;
        }
        for id in ids {
            let mut mesh = world.clone();
            mesh.indices =
                world.indices.iter().zip(&actor.materials).filter(|(_, &m)| m == id).map(|(t, _)| *t).collect();
            parts.push((mesh, material(id)));
        }
    }
    Ok((parts, report.warnings))
}
