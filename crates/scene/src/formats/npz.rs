//! A mesh as numpy arrays: an `.npz` archive with `vertices`, shape (N, 3), and `faces`,
//! shape (M, 3) — what `np.savez("mesh.npz", vertices=v, faces=f)` writes from trimesh
//! or any numpy pipeline, so Python users need not write an OBJ first.
//!
//! Accepted: vertices as float32 or float64 (float64 rounded to nearest float32, the
//! engine's precision), faces as int32, int64, uint32 or uint64; either array in C or
//! Fortran order. Triangle numbers are the rows of `faces`. Errors name the file and the
//! array: a missing array, a wrong shape or dtype, a negative or out-of-range index,
//! NaN or infinite coordinates. Each array's header is checked before npyz parses it
//! ([`check_npy_header`]: length and nesting).

use crate::LoadError;
use dynray_geom::TriangleMesh;
use npyz::npz::NpzArchive;
use std::io::Read;
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
    // The header is looked at before npyz parses it (`check_npy_header`).
    if let Ok(mut entry) = npz.zip_archive().by_name(&format!("{name}.npy")) {
        let mut prefix = Vec::new();
        (&mut entry)
            .take(NPY_PREFIX_BYTES as u64)
            .read_to_end(&mut prefix)
            .map_err(|e| bad(format!("unreadable: {e}")))?;
        check_npy_header(&prefix).map_err(bad)?;
    }
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

/// Longest `.npy` header dynray reads: numpy's own `max_header_size` (numpy writes
/// headers of about 128 bytes; it refuses to read longer than this without a flag).
pub const MAX_NPY_HEADER_BYTES: usize = 10_000;

/// Deepest bracket nesting of a header dynray reads: the dictionary, and the shape tuple
/// inside it. Deeper headers are structured dtypes (lists of fields), which no dynray
/// array has.
const MAX_NPY_HEADER_DEPTH: usize = 2;

/// Bytes [`check_npy_header`] needs to see: the longest preamble and header.
pub const NPY_PREFIX_BYTES: usize = 12 + MAX_NPY_HEADER_BYTES;

/// Checks the header of the `.npy` data starting with `prefix` (its first
/// [`NPY_PREFIX_BYTES`] bytes, or all of a shorter file) before npyz parses it: at most
/// [`MAX_NPY_HEADER_BYTES`] long, and brackets nested at most two deep (outside quoted
/// strings). npyz parses the header's Python literal with a backtracking grammar
/// (py_literal) that takes time exponential in the nesting depth: a 200-byte header of
/// 30 unclosed `[` took hours (found by fuzzing, docs/fuzzing.md). Anything else — a
/// short file, a bad magic — is left to npyz to report.
pub fn check_npy_header(prefix: &[u8]) -> Result<(), String> {
    if prefix.len() < 10 || !prefix.starts_with(b"\x93NUMPY") {
        return Ok(());
    }
    let (len, start) = match prefix[6] {
        1 => (u16::from_le_bytes([prefix[8], prefix[9]]) as usize, 10),
        _ if prefix.len() >= 12 => (u32::from_le_bytes([prefix[8], prefix[9], prefix[10], prefix[11]]) as usize, 12),
        _ => return Ok(()),
    };
    if len > MAX_NPY_HEADER_BYTES {
        return Err(format!(
            "the .npy header is {len} bytes, longer than the {MAX_NPY_HEADER_BYTES} numpy itself reads"
        ));
    }
    let header = &prefix[start.min(prefix.len())..(start + len).min(prefix.len())];
    let (mut depth, mut quote, mut escaped) = (0usize, None, false);
    for &b in header {
        match quote {
            Some(q) => {
                if escaped {
                    escaped = false;
                } else if b == b'\\' {
                    escaped = true;
                } else if b == q {
                    quote = None;
                }
            }
            None => match b {
                b'\'' | b'"' => quote = Some(b),
                b'(' | b'[' | b'{' => {
                    depth += 1;
                    if depth > MAX_NPY_HEADER_DEPTH {
                        return Err(format!(
                            "the .npy header nests brackets more than {MAX_NPY_HEADER_DEPTH} deep \
                             (dynray reads plain arrays, not structured dtypes)"
                        ));
                    }
                }
                b')' | b']' | b'}' => depth = depth.saturating_sub(1),
                _ => {}
            },
        }
    }
    Ok(())
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
