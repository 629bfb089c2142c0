//! A mesh as numpy arrays: an `.npz` archive with `vertices`, shape (N, 3), and `faces`,
//! shape (M, 3) — what `np.savez("mesh.npz", vertices=v, faces=f)` writes from trimesh
//! or any numpy pipeline, so Python users need not write an OBJ first.
//!
//! Accepted: vertices as float32 or float64 (float64 rounded to nearest float32, the
//! engine's precision), faces as int32, int64, uint32 or uint64; either array in C or
//! Fortran order. Triangle numbers are the rows of `faces`. Errors name the file and the
//! array: a missing array, a wrong shape or dtype, a negative or out-of-range index,
//! NaN or infinite coordinates.

use crate::LoadError;
use dynray_geom::TriangleMesh;
use npyz::npz::NpzArchive;
use std::path::Path;

/// Reads an `.npz` mesh into a validated mesh.
pub fn load(path: &Path) -> Result<TriangleMesh, LoadError> {
    dynray_geom::file::check_regular(path).map_err(|e| LoadError::io(path, e))?;
    let mut npz = NpzArchive::open(path).map_err(|e| LoadError::io(path, e))?;
    let vertices = matrix(&mut npz, path, "vertices", Kind::Float)?;
    let faces = matrix(&mut npz, path, "faces", Kind::Index)?;
    let positions: Vec<[f32; 3]> = vertices.chunks_exact(3).map(|v| [v[0] as f32, v[1] as f32, v[2] as f32]).collect();
    let n = positions.len() as f64;
    let indices = faces
        .chunks_exact(3)
        .enumerate()
        .map(|(row, f)| {
            if let Some(&bad) = f.iter().find(|&&i| !(0.0..n).contains(&i)) {
                return Err(LoadError::parse(
                    path,
                    None,
                    format!("faces row {row}: index {bad} is outside 0..{} (the vertices)", positions.len()),
                ));
            }
            Ok([f[0] as u32, f[1] as u32, f[2] as u32])
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mesh = TriangleMesh::new(positions, indices);
    mesh.validate().map_err(|source| LoadError::Mesh { path: path.to_path_buf(), source })?;
    Ok(mesh)
}

/// What an array must hold.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Float,
    Index,
}

/// The (K, 3) array `name` as row-major `f64`s (exact for every accepted dtype: f32,
/// f64, and integers below 2^53, far past any index a u32 mesh can use).
fn matrix(
    npz: &mut NpzArchive<std::io::BufReader<std::fs::File>>,
    path: &Path,
    name: &str,
    kind: Kind,
) -> Result<Vec<f64>, LoadError> {
    let bad = |m: String| LoadError::parse(path, None, format!("array `{name}`: {m}"));
    let npy = npz.by_name(name).map_err(|e| bad(format!("unreadable: {e}")))?.ok_or_else(|| {
        LoadError::parse(
            path,
            None,
            format!("no array `{name}` (a mesh .npz holds `vertices` (N, 3) and `faces` (M, 3))"),
        )
    })?;
    let shape = npy.shape().to_vec();
    if shape.len() != 2 || shape[1] != 3 {
        return Err(bad(format!("shape must be (K, 3), found {shape:?}")));
    }
    // A header may claim any shape: a product past usize (or u64) wrapped into a small
    // one and read the data wrongly or indexed out of bounds (issue 43).
    let rows = match shape[0].checked_mul(3).and_then(|n| usize::try_from(n).ok()) {
        Some(_) => shape[0] as usize,
        None => return Err(bad(format!("shape ({}, 3) is larger than any array this machine can hold", shape[0]))),
    };
    let fortran = npy.order() == npyz::Order::Fortran;
    let descr = npy.dtype().descr();
    let read = |e: std::io::Error| bad(format!("truncated or unreadable data: {e}"));
    let values: Vec<f64> = match (kind, descr.as_str()) {
        (Kind::Float, "'<f4'") => npy.into_vec::<f32>().map_err(read)?.into_iter().map(f64::from).collect(),
        (Kind::Float, "'<f8'") => npy.into_vec::<f64>().map_err(read)?,
        (Kind::Index, "'<i4'") => npy.into_vec::<i32>().map_err(read)?.into_iter().map(f64::from).collect(),
        (Kind::Index, "'<i8'") => npy.into_vec::<i64>().map_err(read)?.into_iter().map(|i| i as f64).collect(),
        (Kind::Index, "'<u4'") => npy.into_vec::<u32>().map_err(read)?.into_iter().map(f64::from).collect(),
        (Kind::Index, "'<u8'") => npy.into_vec::<u64>().map_err(read)?.into_iter().map(|i| i as f64).collect(),
        (Kind::Float, d) => return Err(bad(format!("dtype must be float32 or float64, found {d}"))),
        (Kind::Index, d) => return Err(bad(format!("dtype must be int32, int64, uint32 or uint64, found {d}"))),
    };
    if values.len() != rows * 3 {
        return Err(bad(format!("holds {} values, the header promises {}", values.len(), rows * 3)));
    }
    if fortran {
        return Ok(row_major(&values, rows, 3));
    }
    Ok(values)
}

/// A `rows × cols` array stored in Fortran (column-major) order, as numpy writes
/// `np.asfortranarray` data, rearranged into C (row-major) order: element `(i, j)` is
/// read from `j·rows + i`.
///
/// # Panics
/// When `values.len() != rows * cols`; callers check the length against the header.
pub fn row_major<T: Copy>(values: &[T], rows: usize, cols: usize) -> Vec<T> {
    assert_eq!(values.len(), rows * cols, "a {rows}×{cols} array holds {} values", values.len());
    (0..rows * cols).map(|k| values[(k % cols) * rows + k / cols]).collect()
}
