//! glTF 2.0 loader (`.gltf` with its buffers, or self-contained `.glb`), static geometry.
//!
//! - The default scene (or, when the file names none, the first) is walked from its root
//!   nodes; each node's local matrix (or TRS) is composed with its parents'. A file
//!   without scenes gets every mesh once, untransformed, and a warning.
//! - Each node with a mesh becomes one [`Actor`] (named after the node, else the mesh)
//!   whose primitives are appended in order, with a material per triangle. The mesh stays
//!   in the node's space and the node's world matrix becomes the actor's [`Transform`],
//!   which the frame applies to positions and normals; normals are kept when every
//!   primitive of the mesh has them.
//! - Primitive modes: `TRIANGLES`, plus `TRIANGLE_STRIP` and `TRIANGLE_FAN` converted to
//!   triangles in order; points and lines are skipped with a warning. Indexed and
//!   non-indexed primitives are read.
//! - Static pose only: morph targets are ignored (the base shape is used) and skinned
//!   meshes keep their bind pose, placed by their node hierarchy (for CesiumMan this is
//!   the upright bind pose). Animation is a separate concern.
//! - Materials: `baseColorFactor` RGB becomes the colour of a [`Finish::default`]
//!   material; with `alphaMode: BLEND` its alpha gives `transparency = 1 - alpha`. Base
//!   colour textures are not sampled (the factor alone is used; Duck's factor is white).
//!   Primitives without a material get [`Material::default`].
//! - Every accessor dynray reads is checked before reading (type, component type,
//!   stride, and that `offset + stride × (count - 1) + size` lies inside its buffer view
//!   and buffer) because the gltf crate slices without such checks in places. A node
//!   reached twice (a cycle, or a child shared by two parents) is an error rather than an
//!   endless or exponential walk. External buffer
//!   URIs must name regular files (no devices), and bad attribute indices are caught
//!   before gltf-json's validation, which would panic on them.

use crate::report::{LoadReport, Warning};
use crate::{Actor, Finish, LoadError, Material, Motion, Scene, Transform};
use dynray_geom::{MeshError, TriangleMesh};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
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
    let document = gltf::Document::from_json(json).map_err(|e| perr(format!("glTF: {e}")))?;
    let base = path.parent().unwrap_or(Path::new(""));
    for buffer in document.buffers() {
        if let gltf::buffer::Source::Uri(uri) = buffer.source() {
            check_buffer_uri(base, uri).map_err(|m| perr(format!("glTF buffer {}: {m}", buffer.index())))?;
        }
    }
    let buffers = gltf::import_buffers(&document, Some(base), blob).map_err(|e| {
        // gltf's error does not say which file; name the external ones.
        let uris: Vec<String> = document
            .buffers()
            .filter_map(|b| match b.source() {
                gltf::buffer::Source::Uri(u) if !u.starts_with("data:") => Some(base.join(u).display().to_string()),
                _ => None,
            })
            .collect();
        let named = if uris.is_empty() { String::new() } else { format!(" (buffer files: {})", uris.join(", ")) };
        perr(format!("glTF buffer data: {e}{named}"))
    })?;
    let mut warnings = Vec::new();

    let mut scene =
        Scene { materials: document.materials().map(|m| convert_material(&m)).collect(), ..Default::default() };
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
        let mut actor_mesh = TriangleMesh::default();
        let mut materials = Vec::new();
        for prim in mesh.primitives() {
            let label = format!("mesh {} primitive {}", mesh.index(), prim.index());
            let Some(part) = read_primitive(&prim, &buffers).map_err(|m| perr(format!("{label}: {m}")))? else {
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
            if actor_mesh.positions.is_empty() {
                actor_mesh = part;
            } else {
                actor_mesh.append(&part);
            }
        }
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
            ..Actor::new(name, actor_mesh, 0)
        };
        actor.world_mesh().validate().map_err(|source| LoadError::Mesh { path: path.to_path_buf(), source })?;
        scene.actors.push(actor);
    }
    if scene.actors.is_empty() {
        return Err(LoadError::Mesh { path: path.to_path_buf(), source: MeshError::Empty });
    }
    scene.add_default_light();
    Ok(LoadReport { scene, warnings })
}

/// Checks an external buffer URI before gltf reads it: gltf 1.4 panics when a relative
/// URI percent-decodes to invalid UTF-8, and would read a device such as `/dev/zero`
/// forever. So a relative or `file:` URI must decode to UTF-8 and name a regular file.
fn check_buffer_uri(base: &Path, uri: &str) -> Result<(), String> {
    if uri.starts_with("data:") {
        return Ok(());
    }
    let file = if let Some(rest) = uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:")) {
        std::path::PathBuf::from(rest)
    } else if uri.contains(':') {
        return Err(format!("URI scheme of `{uri}` is not supported (only relative, file: and data:)"));
    } else {
        base.join(percent_decode(uri).ok_or_else(|| format!("URI `{uri}` does not decode to UTF-8"))?)
    };
    match std::fs::metadata(&file) {
        Ok(m) if m.is_file() => Ok(()),
        Ok(_) => Err(format!("{} is not a regular file", file.display())),
        Err(e) => Err(format!("{}: {e}", file.display())),
    }
}

/// `%XX` decoding as the glTF importer does it; `None` when the result is not UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        match (b[i], b.get(i + 1).copied().and_then(hex), b.get(i + 2).copied().and_then(hex)) {
            (b'%', Some(h), Some(l)) => {
                out.push((h * 16 + l) as u8);
                i += 3;
            }
            (c, _, _) => {
                out.push(c);
                i += 1;
            }
        }
    }
    String::from_utf8(out).ok()
}

/// The dynray material for a glTF material (module docs).
fn convert_material(m: &gltf::Material) -> Material {
    let [r, g, b, a] = m.pbr_metallic_roughness().base_color_factor();
    let mut mat = Material::from_finish(m.name().unwrap_or(""), glam::Vec3::new(r, g, b), &Finish::default());
    if m.alpha_mode() == gltf::material::AlphaMode::Blend {
        mat.transparency = glam::Vec3::splat((1.0 - a).clamp(0.0, 1.0));
    }
    mat
}

/// Reads one primitive in its mesh's local space; `Ok(None)` for points and lines.
fn read_primitive(prim: &gltf::Primitive, buffers: &[gltf::buffer::Data]) -> Result<Option<TriangleMesh>, String> {
    if matches!(prim.mode(), Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip) {
        return Ok(None);
    }
    let pos = prim.get(&gltf::Semantic::Positions).ok_or("no POSITION attribute")?;
    check_accessor(&pos, Dimensions::Vec3, &[DataType::F32], buffers).map_err(|m| format!("POSITION: {m}"))?;
    let normal = prim.get(&gltf::Semantic::Normals);
    if let Some(n) = &normal {
        check_accessor(n, Dimensions::Vec3, &[DataType::F32], buffers).map_err(|m| format!("NORMAL: {m}"))?;
        if n.count() != pos.count() {
            return Err(format!("NORMAL has {} entries for {} positions", n.count(), pos.count()));
        }
    }
    if let Some(ix) = prim.indices() {
        check_accessor(&ix, Dimensions::Scalar, &[DataType::U8, DataType::U16, DataType::U32], buffers)
            .map_err(|m| format!("indices: {m}"))?;
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let positions: Vec<[f32; 3]> = reader.read_positions().ok_or("POSITION has no data")?.collect();
    let normals: Option<Vec<[f32; 3]>> = match normal {
        Some(_) => Some(reader.read_normals().ok_or("NORMAL has no data")?.collect()),
        None => None,
    };
    let corners: Vec<u32> = match prim.indices() {
        Some(_) => reader.read_indices().ok_or("indices have no data")?.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let indices = triangles(prim.mode(), &corners)?;
    Ok(Some(TriangleMesh { positions, indices, normals, uvs: None }))
}

/// Triangles of a list, strip or fan, in order (glTF 2.0 §3.7.2.1 winding rules).
fn triangles(mode: Mode, c: &[u32]) -> Result<Vec<[u32; 3]>, String> {
    Ok(match mode {
        Mode::Triangles => {
            #[allow(clippy::manual_is_multiple_of)] // is_multiple_of needs Rust 1.87; MSRV is 1.85
            if c.len() % 3 != 0 {
                return Err(format!("TRIANGLES with {} indices, not a multiple of 3", c.len()));
            }
            c.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
        }
        Mode::TriangleStrip => (0..c.len().saturating_sub(2))
            .map(|i| if i % 2 == 0 { [c[i], c[i + 1], c[i + 2]] } else { [c[i], c[i + 2], c[i + 1]] })
            .collect(),
        Mode::TriangleFan => (1..c.len().saturating_sub(1)).map(|i| [c[i], c[i + 1], c[0]]).collect(),
        _ => Vec::new(),
    })
}

/// Checks that reading `acc` stays inside its data and has the expected layout.
fn check_accessor(
    acc: &gltf::Accessor,
    dims: Dimensions,
    types: &[DataType],
    buffers: &[gltf::buffer::Data],
) -> Result<(), String> {
    if acc.dimensions() != dims || !types.contains(&acc.data_type()) {
        return Err(format!(
            "accessor {} is {:?} {:?}, expected {dims:?} of {types:?}",
            acc.index(),
            acc.dimensions(),
            acc.data_type()
        ));
    }
    if acc.normalized() {
        return Err(format!("accessor {} is normalized; dynray reads plain values", acc.index()));
    }
    if acc.sparse().is_some() {
        return Err(format!("accessor {} is sparse, which dynray does not read", acc.index()));
    }
    let count = acc.count();
    if count == 0 {
        return Err(format!("accessor {} is empty", acc.index()));
    }
    let view = acc.view().ok_or_else(|| format!("accessor {} has no buffer view", acc.index()))?;
    let size = acc.size();
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!("buffer view {} has stride {stride} < element size {size}", view.index()));
    }
    let end = stride.checked_mul(count - 1).and_then(|s| s.checked_add(size)).and_then(|s| s.checked_add(acc.offset()));
    if end.is_none_or(|e| e > view.length()) {
        return Err(format!("accessor {} ({count} elements) runs past its buffer view {}", acc.index(), view.index()));
    }
    let buffer = buffers.get(view.buffer().index()).map_or(0, |d| d.0.len());
    if view.offset().checked_add(view.length()).is_none_or(|e| e > buffer) {
        return Err(format!("buffer view {} runs past its buffer ({buffer} bytes)", view.index()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buffer_uris_must_name_regular_files() {
        assert_eq!(percent_decode("a%20b%2Fc%zz%4"), Some("a b/c%zz%4".into()));
        assert_eq!(percent_decode("%FF"), None);
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a b.bin"), [0u8; 4]).unwrap();
        assert!(check_buffer_uri(dir.path(), "a%20b.bin").is_ok());
        assert!(check_buffer_uri(dir.path(), "data:application/octet-stream;base64,AAAA").is_ok());
        assert!(check_buffer_uri(dir.path(), "%FF.bin").unwrap_err().contains("UTF-8"));
        assert!(check_buffer_uri(dir.path(), ".").unwrap_err().contains("not a regular file"));
        assert!(check_buffer_uri(dir.path(), "missing.bin").is_err());
        assert!(check_buffer_uri(dir.path(), "http://example.com/x.bin").unwrap_err().contains("not supported"));
        if Path::new("/dev/zero").exists() {
            assert!(check_buffer_uri(dir.path(), "file:///dev/zero").unwrap_err().contains("not a regular file"));
        }
    }

    #[test]
    fn strips_and_fans_follow_the_spec_order() {
        assert_eq!(triangles(Mode::TriangleStrip, &[0, 1, 2, 3]).unwrap(), vec![[0, 1, 2], [1, 3, 2]]);
        assert_eq!(triangles(Mode::TriangleFan, &[0, 1, 2, 3]).unwrap(), vec![[1, 2, 0], [2, 3, 0]]);
        assert_eq!(triangles(Mode::Triangles, &[0, 1, 2, 2, 1, 0]).unwrap().len(), 2);
        assert!(triangles(Mode::Triangles, &[0, 1]).is_err());
        assert!(triangles(Mode::TriangleStrip, &[0, 1]).unwrap().is_empty());
    }
}
