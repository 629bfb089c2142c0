//! `mesh { file "…" }`: the one place that turns a mesh file into parts, through the
//! general loader (`load.rs`), so every mesh format dynray reads works in scene files.
//! Scene files themselves are not meshes: including one goes through `include`.
//! The lights the file itself brings (an OBJ's emissive `Ke` lamp, glTF punctual lights)
//! come with the parts, placed like them; the default light of a bare mesh file does not.

use crate::load::{load_own, FileFormat};
use crate::{Light, LoadError, Material, Texture, Warning};
use dynray_geom::TriangleMesh;
use std::path::Path;
use std::sync::Arc;

/// A mesh file read as parts: (world-space mesh, material from the file).
pub(crate) type Parts = Vec<(TriangleMesh, Option<Material>)>;

/// What a mesh file gives a scene file: its parts, its own lights, the textures its
/// materials name, and the loader's warnings.
pub(crate) struct MeshFile {
    /// One part per actor and material.
    pub parts: Parts,
    /// The lights the file holds (emitters, punctual lights), in the file's world space.
    pub lights: Vec<Light>,
    /// The textures the parts' materials name, by index into this list.
    pub textures: Vec<Arc<Texture>>,
    /// Problems the loader survived (a missing `.mtl`, say), naming the mesh file.
    pub warnings: Vec<Warning>,
}

/// Reads a mesh file as parts: one part per actor and material, triangles in file order
/// within each part, in the file's own world space (a glTF node's matrix is applied
/// here, since the scene file's transform composes with it), with the lights the file
/// holds and the textures its materials name. Its camera is not taken: the scene file
/// places its own.
pub(crate) fn load_mesh_file(path: &Path) -> Result<MeshFile, LoadError> {
    if FileFormat::of(path) == Some(FileFormat::Scn) {
        return Err(LoadError::parse(path, None, "a scene file is not a mesh: use `include` to read it"));
    }
    // PLY has no materials: its parts take the object's (or the scene's default) material.
    let has_materials = FileFormat::of(path) != Some(FileFormat::Ply);
    // Unshaded: the normals the file has; the `mesh` block's `shading` decides the rest
    // once the scene is built.
    let report = load_own(path)?;
    let scene = report.scene;
    let lights = scene.lights.clone();
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
    Ok(MeshFile { parts, lights, textures: scene.textures, warnings: report.warnings })
}
