//! Reading a primitive's accessors (positions, normals, TEXCOORD_0, indices) into a
//! [`TriangleMesh`], every accessor checked before gltf slices it; and
//! [`read_components`], which reads any checked accessor as numbers (animation keys,
//! skin joints and weights, morph displacements, inverse bind matrices).

use super::uri::view_bytes;
use dynray_geom::TriangleMesh;
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

/// Reads one primitive in its mesh's local space; `Ok(None)` for points and lines.
pub(super) fn read_primitive(prim: &gltf::Primitive, buffers: &[Vec<u8>]) -> Result<Option<TriangleMesh>, String> {
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
    // glTF's uv origin is the image's top-left, v down; dynray's is bottom-left, v up
    // (see `crate::texture`), so v becomes 1 - v. Normalised integers are allowed here,
    // as the spec allows them for texture coordinates.
    let uv = prim.get(&gltf::Semantic::TexCoords(0));
    if let Some(t) = &uv {
        check_accessor_with(t, Dimensions::Vec2, &[DataType::F32, DataType::U8, DataType::U16], true, buffers)
            .map_err(|m| format!("TEXCOORD_0: {m}"))?;
        if t.count() != pos.count() {
            return Err(format!("TEXCOORD_0 has {} entries for {} positions", t.count(), pos.count()));
        }
        if t.data_type() != DataType::F32 && !t.normalized() {
            return Err(format!("TEXCOORD_0: accessor {} is an integer type but not normalized", t.index()));
        }
    }
    if let Some(ix) = prim.indices() {
        check_accessor(&ix, Dimensions::Scalar, &[DataType::U8, DataType::U16, DataType::U32], buffers)
            .map_err(|m| format!("indices: {m}"))?;
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let positions: Vec<[f32; 3]> = reader.read_positions().ok_or("POSITION has no data")?.collect();
    let normals: Option<Vec<[f32; 3]>> = match normal {
        Some(_) => Some(reader.read_normals().ok_or("NORMAL has no data")?.collect()),
        None => None,
    };
    let uvs: Option<Vec<[f32; 2]>> = match uv {
        Some(_) => Some(
            reader.read_tex_coords(0).ok_or("TEXCOORD_0 has no data")?.into_f32().map(|[u, v]| [u, 1.0 - v]).collect(),
        ),
        None => None,
    };
    let corners: Vec<u32> = match prim.indices() {
        Some(_) => reader.read_indices().ok_or("indices have no data")?.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let indices = triangles(prim.mode(), &corners)?;
    Ok(Some(TriangleMesh { positions, indices, normals, uvs }))
}

/// Triangles of a list, strip or fan, in order (glTF 2.0 §3.7.2.1 winding rules).
pub(super) fn triangles(mode: Mode, c: &[u32]) -> Result<Vec<[u32; 3]>, String> {
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

/// Checks that reading `acc` stays inside its data and has the expected layout (plain,
/// not normalised, values).
fn check_accessor(
    acc: &gltf::Accessor,
    dims: Dimensions,
    types: &[DataType],
    buffers: &[Vec<u8>],
) -> Result<(), String> {
    check_accessor_with(acc, dims, types, false, buffers)
}

/// [`check_accessor`], allowing normalised integers when `normalized_ok`.
pub(super) fn check_accessor_with(
    acc: &gltf::Accessor,
    dims: Dimensions,
    types: &[DataType],
    normalized_ok: bool,
    buffers: &[Vec<u8>],
) -> Result<(), String> {
    if acc.dimensions() != dims || !types.contains(&acc.data_type()) {
        return Err(format!(
            "accessor {} is {:?} {:?}, expected {dims:?} of {types:?}",
            acc.index(),
            acc.dimensions(),
            acc.data_type()
        ));
    }
    if acc.normalized() && !normalized_ok {
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
    view_bytes(&view, buffers)?;
    Ok(())
}

/// Every component of every element of `acc`, in order, as `f32`: floats as they are,
/// normalised integers mapped to [0, 1] or [-1, 1] by glTF's rules (§3.11: `c / 255`,
/// `max(c / 127, -1)`, …), plain integers as their value. Call [`check_accessor_with`]
/// first: this relies on its bounds check and slices only inside the checked range.
pub(super) fn read_components(acc: &gltf::Accessor, buffers: &[Vec<u8>]) -> Result<Vec<f32>, String> {
    let view = acc.view().ok_or_else(|| format!("accessor {} has no buffer view", acc.index()))?;
    let bytes = view_bytes(&view, buffers)?;
    let size = acc.size();
    let stride = view.stride().unwrap_or(size);
    let n = acc.dimensions().multiplicity();
    let csize = acc.data_type().size();
    // Matrices of 1- and 2-byte components pad their columns to 4 bytes (§3.6.2.4);
    // dynray reads only float matrices, which have no padding.
    if n * csize != size {
        return Err(format!("accessor {}: padded matrix layouts are not read", acc.index()));
    }
    let normalized = acc.normalized();
    let mut out = Vec::with_capacity(acc.count() * n);
    for e in 0..acc.count() {
        let start = acc.offset() + e * stride;
        let elem = bytes
            .get(start..start + size)
            .ok_or_else(|| format!("accessor {} element {e} lies outside its buffer view", acc.index()))?;
        for c in elem.chunks_exact(csize) {
            out.push(component(acc.data_type(), c, normalized));
        }
    }
    Ok(out)
}

/// One little-endian component as `f32` (normalised per glTF §3.11 when asked).
fn component(t: DataType, b: &[u8], normalized: bool) -> f32 {
    match t {
        DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
        DataType::I8 => {
            let v = b[0] as i8 as f32;
            if normalized {
                (v / 127.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U8 => {
            let v = b[0] as f32;
            if normalized {
                v / 255.0
            } else {
                v
            }
        }
        DataType::I16 => {
            let v = i16::from_le_bytes([b[0], b[1]]) as f32;
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = u16::from_le_bytes([b[0], b[1]]) as f32;
            if normalized {
                v / 65535.0
            } else {
                v
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_follow_the_spec_order() {
        assert_eq!(triangles(Mode::TriangleStrip, &[0, 1, 2, 3]).unwrap(), vec![[0, 1, 2], [1, 3, 2]]);
        assert_eq!(triangles(Mode::TriangleFan, &[0, 1, 2, 3]).unwrap(), vec![[1, 2, 0], [2, 3, 0]]);
        assert_eq!(triangles(Mode::Triangles, &[0, 1, 2, 2, 1, 0]).unwrap().len(), 2);
        assert!(triangles(Mode::Triangles, &[0, 1]).is_err());
        assert!(triangles(Mode::TriangleStrip, &[0, 1]).unwrap().is_empty());
    }
}
