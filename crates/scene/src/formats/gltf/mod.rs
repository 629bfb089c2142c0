//! glTF 2.0 loader (`.gltf` with its buffers, or self-contained `.glb`): geometry,
//! materials, lights, and animation (node TRS, skins, morph targets).
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
//! - Animation (`animation.rs`, `skin.rs`), into [`crate::Scene::animation`]: every node
//!   of the walked scene becomes a rig [`Node`], in walk order (parents first); each mesh
//!   actor gets [`Actor::node`] and keeps its rest world matrix as [`Actor::transform`].
//!   Nodes that no channel moves are stored as the matrices the static loader always
//!   composed, so a file (or part of one) that nothing animates gives the same frame bits
//!   at every `t` as before (`rig_node`). Each animation is a clip (the first is active,
//!   and the timeline covers its keys at 24 frames a second); channels animate
//!   translation, rotation, scale and morph weights with `STEP`, `LINEAR` or
//!   `CUBICSPLINE` keys. Skins become rig skins (inverse bind matrices, identity when
//!   absent); a skinned mesh's `JOINTS_0`/`WEIGHTS_0` (the first four influences) bind
//!   it, and the skin, not its node, places it. Morph targets' `POSITION` and `NORMAL`
//!   displacements deform the mesh with its node's weights (`node.weights`, else
//!   `mesh.weights`, else zeros at rest). A mesh's primitives are one actor, so their
//!   deformation arrays are concatenated likewise. Actors that move are marked
//!   [`Motion::Dynamic`]. Not read: sparse accessors (sparse morph targets are a warning
//!   and the mesh keeps its base shape), `TANGENT` displacements, cameras; lights on
//!   animated nodes stay at their rest placement.
//! - Materials (`material.rs`): `baseColorFactor` RGB becomes the colour of a
//!   [`crate::Finish::default`] material; with `alphaMode: BLEND` its alpha gives
//!   `transparency = 1 - alpha`. The `baseColorTexture` (sRGB) multiplies that colour, as
//!   glTF's base colour is `factor × texture`: it becomes the material's
//!   [`Material::diffuse_texture`], with the texture's sampler (`wrapS`/`wrapT`; `NEAREST`
//!   magnification gives nearest filtering, anything else bilinear, both over mipmaps) and
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
//!   panic on them; so are bad indices of animations, samplers, skins, joints and morph
//!   targets (`animation::check_indices`), for messages that name the animation,
//!   channel or skin.

mod accessor;
mod animation;
mod lights;
mod material;
mod skin;
mod uri;

use crate::animation::{Node, NodePose, Rig};
use crate::report::{LoadReport, Warning};
use crate::texture::untexture_where_no_uvs;
use crate::{Actor, LoadError, Material, Motion, Scene, Timeline, Transform};
use dynray_geom::{MeshError, TriangleMesh};
use std::path::Path;

/// A GLB's 12-byte header: gltf 1.4 subtracts the header's size from the total length
/// the header gives without a check, which underflows for a length below 12 (a panic
/// with overflow checks, found by fuzzing, docs/fuzzing.md); such a file is refused here.
/// Other bytes (JSON glTF) pass; gltf checks the rest of a GLB itself.
fn check_glb_header(bytes: &[u8]) -> Result<(), String> {
    if bytes.len() < 12 || !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let length = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
    if length < 12 {
        return Err(format!("GLB: the header gives a total length of {length} bytes, less than the header's own 12"));
    }
    Ok(())
}

/// Loads a `.gltf` or `.glb` file into a scene (see module docs).
pub fn load(path: &Path) -> Result<LoadReport, LoadError> {
    let bytes = dynray_geom::file::read(path).map_err(|e| LoadError::io(path, e))?;
    let perr = |m: String| LoadError::parse(path, None, m);
    check_glb_header(&bytes).map_err(perr)?;
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
    animation::check_indices(&json).map_err(|m| perr(format!("glTF: {m}")))?;
    let document = gltf::Document::from_json(json).map_err(|e| perr(format!("glTF: {e}")))?;
    let base = path.parent().unwrap_or(Path::new(""));
    let buffers = uri::read_buffers(&document, base, blob).map_err(|m| perr(format!("glTF {m}")))?;
    let mut warnings = Vec::new();

    let mut scene = Scene {
        materials: document.materials().map(|m| material::convert(&m, path, &mut warnings)).collect(),
        ..Default::default()
    };
    let mut default_material = None;

    // Mesh instances in walk order, and the rig of the walked nodes (`rig_of[gltf node]`).
    let mut instances: Vec<Instance> = Vec::new();
    let mut rig = Rig::default();
    let mut rig_of: Vec<Option<u32>> = vec![None; document.nodes().len()];
    match document.default_scene().or_else(|| document.scenes().next()) {
        Some(s) => {
            let moved = animation::moved_nodes(document.as_json());
            // glTF requires disjoint strict trees. Reaching a node twice means a cycle (an
            // endless walk) or a shared child (exponentially many instances): both errors.
            let mut seen = vec![false; document.nodes().len()];
            let mut stack: Vec<(gltf::Node, glam::Mat4, Option<u32>)> =
                s.nodes().map(|n| (n, glam::Mat4::IDENTITY, None)).collect();
            stack.reverse();
            while let Some((node, parent, parent_rig)) = stack.pop() {
                if std::mem::replace(&mut seen[node.index()], true) {
                    return Err(perr(format!(
                        "node {} is reached twice: the node hierarchy is not a set of trees (a cycle or a shared child)",
                        node.index()
                    )));
                }
                let local = glam::Mat4::from_cols_array_2d(&node.transform().matrix());
                let world = parent * local;
                let here = rig.nodes.len() as u32;
                rig_of[node.index()] = Some(here);
                rig.nodes.push(rig_node(&node, moved[node.index()], parent_rig, world, local));
                if let Some(mesh) = node.mesh() {
                    let name = node.name().or(mesh.name()).map(str::to_string);
                    instances.push(Instance { name, mesh, world, node: Some((here, node.skin())) });
                }
                if let Some(light) = node.light() {
                    match lights::convert(&light, world) {
                        Ok(l) => scene.lights.push(l),
                        Err(why) => {
                            warnings.push(Warning::new(path, None, format!("node {}: light: {why}", node.index())))
                        }
                    }
                }
                let children: Vec<_> = node.children().collect();
                stack.extend(children.into_iter().rev().map(|c| (c, world, Some(here))));
            }
        }
        None => {
            warnings.push(Warning::new(path, None, "the file has no scene; every mesh is placed untransformed"));
            for mesh in document.meshes() {
                instances.push(Instance {
                    name: mesh.name().map(str::to_string),
                    mesh,
                    world: glam::Mat4::IDENTITY,
                    node: None,
                });
            }
        }
    }

    // Skins used by the walked meshes, each once, in order of first use.
    let mut skin_of: Vec<Option<(u32, usize)>> = vec![None; document.skins().len()];
    for skin in instances.iter().filter_map(|i| i.node.as_ref().and_then(|(_, s)| s.clone())) {
        if skin_of[skin.index()].is_none() {
            let s = skin::read_skin(&skin, &buffers, &rig_of).map_err(|m| perr(format!("glTF: {m}")))?;
            skin_of[skin.index()] = Some((rig.skins.len() as u32, s.joints.len()));
            rig.skins.push(s);
        }
    }

    for Instance { name, mesh, world, node } in instances {
        let mut parts = Vec::new();
        let mut materials = Vec::new();
        let rig_node = node.as_ref().map(|(n, _)| *n);
        let binding = node.as_ref().and_then(|(_, s)| s.as_ref()).and_then(|s| skin_of[s.index()]);
        let mut deform = skin::MeshDeform::new(binding, skin::target_count(&mesh));
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
            if rig_node.is_some() {
                deform
                    .add_primitive(&prim, part.vertex_count(), &buffers, &label, path, &mut warnings)
                    .map_err(|m| perr(format!("glTF: {m}")))?;
            }
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
        let has_normals = actor_mesh.normals.is_some();
        // The node's rest world matrix stays on the actor (the frame applies it, as this
        // loader once did per primitive: same matrix, same bits). `Transform::new` even for
        // an identity matrix, because that is what was always applied. With a node, the
        // frame takes the node's matrix at `t` instead, which at rest has the same bits
        // (`rig_node`); a skinned actor is placed by its skin.
        let actor = Actor {
            materials,
            transform: Transform::new(world),
            motion: Motion::Static,
            node: rig_node,
            deform: rig_node.and_then(|n| deform.finish(n, has_normals)),
            ..Actor::new(name, actor_mesh, 0)
        };
        actor.world_mesh().validate().map_err(|source| LoadError::Mesh { path: path.to_path_buf(), source })?;
        scene.actors.push(actor);
    }
    rig.clips = animation::read_clips(&document, &buffers, &rig, &rig_of, path, &mut warnings)
        .map_err(|m| perr(format!("glTF: {m}")))?;
    if let Some((start, end)) = rig.clips.first().and_then(|c| c.range()) {
        scene.animation.timeline = Timeline::covering(start, end, 24.0);
    }
    scene.animation.rig = rig;
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
    scene.validate_animation().map_err(|m| perr(format!("glTF: {m}")))?;
    scene.mark_moving_actors();
    Ok(LoadReport { scene, warnings })
}

/// One mesh to become an actor: its name, the mesh, its node's rest world matrix, and
/// (when it came from a node) that node in the rig and its skin.
struct Instance<'a> {
    name: Option<String>,
    mesh: gltf::Mesh<'a>,
    world: glam::Mat4,
    node: Option<(u32, Option<gltf::Skin<'a>>)>,
}

/// The rig node of `node` (reached under `parent`; `world` its rest world matrix, `local`
/// its local one). A node some channel moves keeps its TRS, as channels replace parts of
/// it. Every other node is stored as a matrix with exactly the bits the static loader
/// composed, so that the rig's world matrices of unanimated nodes equal the old baked
/// placements bit for bit: a root stores `world` (`IDENTITY · local`, which can differ
/// from `local` in the sign of zeros), a child `local` (the rig then forms
/// `parent world · local`, the same product). Rest weights: the node's, else the
/// mesh's, else zeros, one per morph target.
fn rig_node(node: &gltf::Node, moved: bool, parent: Option<u32>, world: glam::Mat4, local: glam::Mat4) -> Node {
    let rest = match node.transform() {
        gltf::scene::Transform::Decomposed { translation, rotation, scale } if moved => {
            // A zero quaternion would make NaNs; channels usually replace it anyway.
            let q = glam::Vec4::from_array(rotation).try_normalize().unwrap_or(glam::Vec4::W);
            NodePose::Trs {
                translation: glam::Vec3::from_array(translation),
                rotation: glam::Quat::from_vec4(q),
                scale: glam::Vec3::from_array(scale),
            }
        }
        _ if parent.is_none() => NodePose::Matrix(world),
        _ => NodePose::Matrix(local),
    };
    let targets = node.mesh().map_or(0, |m| skin::target_count(&m));
    let mut rest_weights: Vec<f32> =
        node.weights().or_else(|| node.mesh().and_then(|m| m.weights())).map(<[f32]>::to_vec).unwrap_or_default();
    rest_weights.resize(targets, 0.0);
    Node { name: node.name().map(str::to_string), parent, rest, rest_weights }
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
