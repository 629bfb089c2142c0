//! glTF 2.0 loader (`.gltf` with its buffers, or self-contained `.glb`), static geometry.
//!
//! - The default scene (or, when the file names none, the first) is walked from its root
//!   nodes; each node's local matrix (or TRS) is composed with its parents'. A file
//!   without scenes gets every mesh once, untransformed, and a warning.
//! - Each node with a mesh becomes one [`Actor`] (named after the node, else the mesh)
//!   whose primitives are appended in order, with a material per triangle. The mesh stays
//!   in the node's space and the node's world matrix becomes the actor's [`Transform`],
//!   which the frame applies to positions and normals; normals are kept when every
//!   primitive of the mesh has them. `TEXCOORD_0` (float, or normalised 8/16-bit) is
//!   kept as the mesh's uvs with `v` flipped to dynray's convention (`1 - v`: glTF's
//!   origin is the image's top-left, dynray's the bottom-left, see [`crate::texture`]);
//!   when only some primitives of a mesh have it, the others get zeros (and their
//!   material's texture is then of no use, but neither is lost).
//! - Primitive modes: `TRIANGLES`, plus `TRIANGLE_STRIP` and `TRIANGLE_FAN` converted to
//!   triangles in order; points and lines are skipped with a warning. Indexed and
//!   non-indexed primitives are read.
//! - Lights: `KHR_lights_punctual` lights on the walked nodes, in walk order
//!   (`lights.rs`). Cameras in the file are not read.
//! - Static pose only: morph targets are ignored (the base shape is used) and skinned
//!   meshes keep their bind pose, placed by their node hierarchy (for CesiumMan this is
//!   the upright bind pose). Animation is a separate concern.
//! - Materials (`material.rs`): `baseColorFactor` RGB becomes the colour of a
//!   [`crate::Finish::default`] material; with `alphaMode: BLEND` its alpha gives
//!   `transparency = 1 - alpha`. The `baseColorTexture` (sRGB) multiplies that colour, as
//!   glTF's base colour is `factor × texture`: it becomes the material's
//!   [`Material::diffuse_texture`], with the texture's sampler (`wrapS`/`wrapT`; `NEAREST`
//!   magnification gives nearest filtering, anything else bilinear; no mipmaps) and
//!   `KHR_texture_transform` (offset, rotation, scale). Only texture coordinate set 0 is
//!   read; a texture on another set is a warning and the material stays untextured.
//!   Images are PNG or JPEG from a relative/`file:` URI, a `data:` URI or a buffer
//!   view (`.glb`), decoded only when a material some primitive uses needs them, each
//!   once; an image that cannot be read or decoded is a warning naming it, and its
//!   materials render untextured. Alpha (`MASK` cut-outs, texture alpha) is not used.
//!   Primitives without a material get [`Material::default`].
//! - Every accessor dynray reads is checked before reading (type, component type,
//!   stride, and that `offset + stride × (count - 1) + size` lies inside its buffer view
//!   and buffer) because the gltf crate slices without such checks in places. A node
//!   reached twice (a cycle, or a child shared by two parents) is an error rather than an
//!   endless or exponential walk. Buffers and images are read by `uri.rs` (not gltf's
//!   importer, which decodes every image): URIs must name regular files (no devices),
//!   and bad attribute indices are caught before gltf-json's validation, which would
//!   panic on them.

mod accessor;
mod lights;
mod material;
mod uri;

use crate::report::{LoadReport, Warning};
use crate::texture::untexture_where_no_uvs;
use crate::{Actor, LoadError, Material, Motion, Scene, Transform};
use dynray_geom::{MeshError, TriangleMesh};
use std::path::Path;

/// Loads a `.gltf` or `.glb` file into a scene (see module docs).
pub fn load(path: &Path) -> Result<LoadReport, LoadError> {
    let bytes = std::fs::read(path).map_err(|e| LoadError::io(path, e))?;
    let perr = |m: String| LoadError::parse(path, None, m);
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| perr(format!("glTF: {e}")))?;
    let json = document.into_json();
    // gltf-json 1.4's validation indexes `accessors[POSITION]` before checking the
    // index, and panics on a bad one; check it first.
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, acc) in &prim.attributes {
                if acc.value() >= json.accessors.len() {
                    return Err(perr(format!(
                        "glTF: mesh {m} primitive {p}: attribute {semantic:?} names accessor {}, but there are {}",
                        acc.value(),
                        json.accessors.len()
                    )));
                }
            }
        }
    }
    // gltf 1.4's `Image::source` unwraps a missing `uri` or `mimeType`; note such images
    // here so that a material using one warns instead.
    let image_problems: Vec<Option<&'static str>> = json
        .images
        .iter()
        .map(|im| match (&im.buffer_view, &im.mime_type, &im.uri) {
            (Some(_), None, _) => Some("has a bufferView but no mimeType"),
            (None, _, None) => Some("has neither a uri nor a bufferView"),
            _ => None,
        })
        .collect();
    let document = gltf::Document::from_json(json).map_err(|e| perr(format!("glTF: {e}")))?;
    let base = path.parent().unwrap_or(Path::new(""));
    let buffers = uri::read_buffers(&document, base, blob).map_err(|m| perr(format!("glTF {m}")))?;
    let mut warnings = Vec::new();

    let mut scene =
        Scene { materials: document.materials().map(|m| material::convert(&m)).collect(), ..Default::default() };
    let mut default_material = None;

    // (node or mesh name, mesh, world matrix) for every mesh instance, in walk order.
    let mut instances: Vec<(Option<String>, gltf::Mesh, glam::Mat4)> = Vec::new();
    match document.default_scene().or_else(|| document.scenes().next()) {
        Some(s) => {
            // glTF requires disjoint strict trees. Reaching a node twice means a cycle (an
            // endless walk) or a shared child (exponentially many instances): both errors.
            let mut seen = vec![false; document.nodes().len()];
            let mut stack: Vec<(gltf::Node, glam::Mat4)> = s.nodes().map(|n| (n, glam::Mat4::IDENTITY)).collect();
            stack.reverse();
            while let Some((node, parent)) = stack.pop() {
                if std::mem::replace(&mut seen[node.index()], true) {
                    return Err(perr(format!(
                        "node {} is reached twice: the node hierarchy is not a set of trees (a cycle or a shared child)",
                        node.index()
                    )));
                }
                let world = parent * glam::Mat4::from_cols_array_2d(&node.transform().matrix());
                if let Some(mesh) = node.mesh() {
                    let name = node.name().or(mesh.name()).map(str::to_string);
                    instances.push((name, mesh, world));
                }
                if let Some(light) = node.light() {
                    match lights::convert(&light, world) {
                        Some(l) => scene.lights.push(l),
                        None => warnings.push(Warning::new(
                            path,
                            None,
                            format!("node {}: its light cannot be placed (matrix not finite); skipped", node.index()),
                        )),
                    }
                }
                let children: Vec<_> = node.children().collect();
                stack.extend(children.into_iter().rev().map(|c| (c, world)));
            }
        }
        None => {
            warnings.push(Warning::new(path, None, "the file has no scene; every mesh is placed untransformed"));
            for mesh in document.meshes() {
                instances.push((mesh.name().map(str::to_string), mesh, glam::Mat4::IDENTITY));
            }
        }
    }

    for (name, mesh, world) in instances {
        let mut parts = Vec::new();
        let mut materials = Vec::new();
        for prim in mesh.primitives() {
            let label = format!("mesh {} primitive {}", mesh.index(), prim.index());
            let Some(part) = accessor::read_primitive(&prim, &buffers).map_err(|m| perr(format!("{label}: {m}")))?
            else {
                warnings.push(Warning::new(
                    path,
                    None,
                    format!("{label}: mode {:?} has no surface; skipped", prim.mode()),
                ));
                continue;
            };
            part.validate().map_err(|e| perr(format!("{label}: {e}")))?;
            let material = match prim.material().index() {
                Some(i) => i as u32,
                None => *default_material.get_or_insert_with(|| {
                    scene.materials.push(Material::default());
                    scene.materials.len() as u32 - 1
                }),
            };
            materials.resize(materials.len() + part.triangle_count(), material);
            parts.push(part);
        }
        let actor_mesh = concat(parts);
        if actor_mesh.indices.is_empty() {
            continue;
        }
        // The node's world matrix stays on the actor (the frame applies it, as this loader
        // once did per primitive: same matrix, same bits). `Transform::new` even for an
        // identity matrix, because that is what was always applied.
        let actor = Actor {
            materials,
            transform: Transform::new(world),
            motion: Motion::Static,
            node: None,
            deform: None,
            ..Actor::new(name, actor_mesh, 0)
        };
        actor.world_mesh().validate().map_err(|source| LoadError::Mesh { path: path.to_path_buf(), source })?;
        scene.actors.push(actor);
    }
    if scene.actors.is_empty() {
        return Err(LoadError::Mesh { path: path.to_path_buf(), source: MeshError::Empty });
    }
    material::attach_textures(
        &mut scene,
        &document,
        &mut material::Images::new(path, base, &buffers, image_problems),
        &mut warnings,
    );
    untexture_where_no_uvs(&mut scene, path, &mut warnings);
    Ok(LoadReport { scene, warnings })
}

/// A mesh's primitives as one mesh, in order. Normals survive when every primitive has
/// them (as [`TriangleMesh::append`] keeps them); uvs when any has them, the others
/// padded with zeros, so one primitive without uvs does not strip its neighbours'
/// textures.
fn concat(parts: Vec<TriangleMesh>) -> TriangleMesh {
    let any_uvs = parts.iter().any(|p| p.uvs.is_some());
    let mut mesh = TriangleMesh::default();
    let mut uvs = Vec::new();
    for mut part in parts {
        if any_uvs {
            match part.uvs.take() {
                Some(t) => uvs.extend(t),
                None => uvs.resize(uvs.len() + part.vertex_count(), [0.0; 2]),
            }
        }
        if mesh.positions.is_empty() {
            mesh = part;
        } else {
            mesh.append(&part);
        }
    }
    mesh.uvs = any_uvs.then_some(uvs);
    mesh
}
