//! The ray and hit files of the trace job, for other programs (numpy users): what
//! `dynray trace-rays` and the Python package's `dynray.trace_rays` read and write
//! (docs/trace-rays.md).
//!
//! Input: .npy of shape (N, 8): origin xyz, direction xyz, tmin, tmax; float32 in C order
//! as it is, float64 or Fortran order converted (with a note saying so).
//! Output: .npz with `t` (float32, inf on miss), `prim` (int64, -1 on miss), `u`, `v`
//! (float32), one entry per ray in input order; with occluded queries, one bool `occluded`.
//! Arrays are stored uncompressed, as numpy's `np.savez` writes them.

use anyhow::{bail, Context, Result};
use dynray_geom::{Hit, Ray, TriangleMesh};
use npyz::WriterBuilder;
use std::io::{BufWriter, Write};
use std::path::Path;

/// An array of closest hits that can be asked for (docs/trace-rays.md, "Output").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HitField {
    /// Ray parameter of the hit (inf on a miss).
    T,
    /// Triangle index (-1 on a miss).
    Prim,
    /// Barycentric weight of the triangle's second vertex.
    U,
    /// Barycentric weight of the third vertex.
    V,
    /// Unit geometric normal, as the triangle is wound (NaN on a miss).
    Normal,
    /// Hit point on the triangle (NaN on a miss).
    Point,
}

impl HitField {
    /// Every field, in the order of their names in [`HitField::NAMES`].
    pub const ALL: [HitField; 6] =
        [HitField::T, HitField::Prim, HitField::U, HitField::V, HitField::Normal, HitField::Point];
    /// The names `--fields` accepts.
    pub const NAMES: [&'static str; 6] = ["t", "prim", "u", "v", "normal", "point"];
    /// What is written without `--fields`.
    pub const DEFAULT: [HitField; 4] = [HitField::T, HitField::Prim, HitField::U, HitField::V];

    /// The array's name in the archive.
    pub fn name(self) -> &'static str {
        Self::NAMES[Self::ALL.iter().position(|&f| f == self).expect("ALL lists every field")]
    }
}

impl std::str::FromStr for HitField {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| format!("unknown hit field `{s}` (expected one of: {})", Self::NAMES.join(", ")))
    }
}

/// Reads and checks the (N, 8) ray array: float32 as it is, float64 and Fortran order
/// (what numpy users often have) converted, with a note saying so.
/// `note` hears of a conversion (what the binary prints as `dynray: note: …`).
pub fn read_rays(path: &Path, note: &mut dyn FnMut(String)) -> Result<Vec<Ray>> {
    let file = dynray_geom::file::open(path).with_context(|| format!("{}: cannot open", path.display()))?;
    let npy = npyz::NpyFile::new(std::io::BufReader::new(file))
        .with_context(|| format!("{}: not a valid .npy file", path.display()))?;
    let shape = npy.shape().to_vec();
    if shape.len() != 2 || shape[1] != 8 {
        bail!("{}: rays must have shape (N, 8), found {:?}", path.display(), shape);
    }
    let n = shape[0];
    let fortran = npy.order() == npyz::Order::Fortran;
    let descr = npy.dtype().descr();
    // The header may promise any number of rows: refuse one the file cannot hold before
    // anything is allocated for it (a product past u64 wrapped into a small one).
    let item = if descr == "'<f8'" { 8 } else { 4 };
    let file_len = std::fs::metadata(path).map(|m| m.len()).unwrap_or(u64::MAX);
    match n.checked_mul(8 * item) {
        Some(bytes) if bytes <= file_len => {}
        _ => bail!(
            "{}: the header promises {n} rays of 8 values, more than the file's {file_len} bytes hold",
            path.display()
        ),
    }
    let truncated = || format!("{}: truncated or unreadable data", path.display());
    let (mut data, converted): (Vec<f32>, bool) = if descr == "'<f4'" {
        (npy.into_vec().with_context(truncated)?, false)
    } else if descr == "'<f8'" {
        // Rounded to nearest, as numpy's astype(np.float32) does; the engine is f32.
        let wide: Vec<f64> = npy.into_vec().with_context(truncated)?;
        (wide.into_iter().map(|x| x as f32).collect(), true)
    } else {
        bail!("{}: rays must be float32 or float64 (little-endian '<f4' or '<f8'), found {descr}", path.display());
    };
    if data.len() as u64 != n * 8 {
        bail!("{}: holds {} values, the header promises {}", path.display(), data.len(), n * 8);
    }
    if fortran {
        data = dynray_scene::formats::npz::row_major(&data, n as usize, 8);
    }
    if converted || fortran {
        let what = match (converted, fortran) {
            (true, true) => "float64 in Fortran order",
            (true, false) => "float64",
            _ => "Fortran order",
        };
        note(format!("{}: rays given as {what}, converted to C-order float32", path.display()));
    }
    // Rows are `Ray`s as they lie in memory (`Ray` is `#[repr(C)]`, 8 f32s): no copy
    // where the vector's capacity allows, one memcpy otherwise.
    let rays: Vec<Ray> = bytemuck::try_cast_vec(data).unwrap_or_else(|(_, data)| bytemuck::cast_slice(&data).to_vec());
    check_rays(&rays).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok(rays)
}

/// The rule every ray input follows (files and the Python package's arrays alike): a
/// finite origin and direction, and no NaN in `[tmin, tmax]`. The message names the row.
pub fn check_rays(rays: &[Ray]) -> Result<(), String> {
    for (i, r) in rays.iter().enumerate() {
        if !(r.origin.is_finite() && r.dir.is_finite()) {
            return Err(format!("ray {i} has a non-finite origin or direction component ({r:?})"));
        }
        if r.tmin.is_nan() || r.tmax.is_nan() {
            return Err(format!("ray {i} has a NaN tmin or tmax"));
        }
    }
    Ok(())
}

/// The output must name a `.npz` archive: `-o -` (no stdout stream here) and `-o x.npy`
/// (one array cannot hold t, prim, u and v) are refused before any work.
pub fn check_output(path: &Path) -> Result<()> {
    if path.as_os_str() == "-" {
        bail!("-o -: trace-rays writes a .npz archive, not a stream; give a file name such as hits.npz");
    }
    let npz = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("npz"));
    if !npz {
        bail!(
            "{}: trace-rays writes a .npz archive (arrays t, prim, u, v, or occluded); name the output *.npz",
            path.display()
        );
    }
    Ok(())
}

/// The unit geometric normal of each hit's triangle as it is wound (`(p1-p0)×(p2-p0)`),
/// NaN on a miss: the `normal` field.
pub fn hit_normals(hits: &[Hit], mesh: &TriangleMesh) -> Vec<[f32; 3]> {
    per_hit(hits, mesh, |p0, p1, p2, _| (p1 - p0).cross(p2 - p0).normalize_or_zero().to_array())
}

/// Each hit point `(1-u-v)·p0 + u·p1 + v·p2`, NaN on a miss: the `point` field.
pub fn hit_points(hits: &[Hit], mesh: &TriangleMesh) -> Vec<[f32; 3]> {
    per_hit(hits, mesh, |p0, p1, p2, h| (p0 * (1.0 - h.u - h.v) + p1 * h.u + p2 * h.v).to_array())
}

type Vec3 = dynray_geom::Vec3;

fn per_hit(hits: &[Hit], mesh: &TriangleMesh, f: impl Fn(Vec3, Vec3, Vec3, &Hit) -> [f32; 3]) -> Vec<[f32; 3]> {
    hits.iter()
        .map(|h| {
            if !h.is_hit() {
                return [f32::NAN; 3];
            }
            let tri = mesh.triangle(h.prim as usize);
            f(tri.p0, tri.p1, tri.p2, h)
        })
        .collect()
}

type Npz = npyz::npz::NpzWriter<BufWriter<std::fs::File>>;

/// Writes one requested array of the closest hits; `normal` and `point` are (N, 3).
fn write_field(npz: &mut Npz, field: HitField, hits: &[Hit], mesh: &TriangleMesh) -> std::io::Result<()> {
    let name = field.name();
    match field {
        HitField::T => write_array(npz, name, &hits.iter().map(|h| h.t).collect::<Vec<f32>>()),
        HitField::Prim => {
            let prim: Vec<i64> = hits.iter().map(|h| if h.is_hit() { h.prim as i64 } else { -1 }).collect();
            write_array(npz, name, &prim)
        }
        HitField::U => write_array(npz, name, &hits.iter().map(|h| h.u).collect::<Vec<f32>>()),
        HitField::V => write_array(npz, name, &hits.iter().map(|h| h.v).collect::<Vec<f32>>()),
        HitField::Normal => write_rows(npz, name, &hit_normals(hits, mesh)),
        HitField::Point => write_rows(npz, name, &hit_points(hits, mesh)),
    }
}

/// Zip options of every array: stored, not deflated (numpy's own `np.savez` default):
/// compressing hit arrays took about 80 % of a 1M-ray round trip and saves little on
/// float data. ZIP64 only where an array needs it.
fn stored(bytes: u64) -> zip::write::FileOptions {
    zip::write::FileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .large_file(bytes >= u32::MAX as u64)
}

/// An (N, 3) float32 array.
fn write_rows(npz: &mut Npz, name: &str, rows: &[[f32; 3]]) -> std::io::Result<()> {
    let options = stored(std::mem::size_of_val(rows) as u64);
    let mut w = npz.array::<f32>(name, options)?.default_dtype().shape(&[rows.len() as u64, 3]).begin_nd()?;
    w.extend(rows.iter().flatten().copied())?;
    w.finish()
}

fn write_array<T: npyz::AutoSerialize + npyz::Serialize + Copy>(
    npz: &mut Npz,
    name: &str,
    data: &[T],
) -> std::io::Result<()> {
    let options = stored(std::mem::size_of_val(data) as u64);
    let mut w = npz.array::<T>(name, options)?.default_dtype().shape(&[data.len() as u64]).begin_nd()?;
    w.extend(data.iter().copied())?;
    w.finish()
}

/// Writes the archive under a temporary name in the target directory and renames it into
/// place, so a failure never leaves a partial file behind.
fn write_npz(path: &Path, fill: impl FnOnce(&mut Npz) -> std::io::Result<()>) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    // Ordinary permissions, not tempfile's private 0600: the hits are for other tools.
    let tmp = crate::output::readable_temp_builder()
        .tempfile_in(dir)
        .with_context(|| format!("{}: cannot write here", path.display()))?;
    let file = tmp.reopen().with_context(|| format!("{}: cannot write", path.display()))?;
    let mut npz = npyz::npz::NpzWriter::new(BufWriter::new(file));
    fill(&mut npz).with_context(|| format!("{}: write failed", path.display()))?;
    let mut inner = npz.zip_writer().finish().with_context(|| format!("{}: write failed", path.display()))?;
    inner.flush().with_context(|| format!("{}: write failed", path.display()))?;
    drop(inner);
    tmp.persist(path).with_context(|| format!("{}: cannot move the finished file into place", path.display()))?;
    Ok(())
}

/// Writes the closest hits' `fields` to the archive `path` (atomically).
pub fn write_hits(path: &Path, fields: &[HitField], hits: &[Hit], mesh: &TriangleMesh) -> Result<()> {
    write_npz(path, |npz| fields.iter().try_for_each(|&f| write_field(npz, f, hits, mesh)))
}

/// Writes the any-hit answers as one bool array `occluded` (atomically).
pub fn write_occluded(path: &Path, occluded: &[bool]) -> Result<()> {
    write_npz(path, |npz| write_array(npz, "occluded", occluded))
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_geom::Vec3;

    #[test]
    fn field_names_parse_back_and_unknown_ones_list_the_choices() {
        for f in HitField::ALL {
            assert_eq!(f.name().parse::<HitField>(), Ok(f));
        }
        let e = "depth".parse::<HitField>().unwrap_err();
        assert!(e.contains("`depth`") && e.contains("t, prim, u, v, normal, point"), "{e}");
    }

    #[test]
    fn check_rays_names_the_first_bad_row() {
        let good = Ray::new(Vec3::ZERO, Vec3::X);
        let mut rays = vec![good; 4];
        assert_eq!(check_rays(&rays), Ok(()));
        rays[2].dir.y = f32::INFINITY;
        assert!(check_rays(&rays).unwrap_err().starts_with("ray 2 has a non-finite"));
        rays[2] = good;
        rays[3].tmin = f32::NAN;
        assert_eq!(check_rays(&rays).unwrap_err(), "ray 3 has a NaN tmin or tmax");
        // An empty interval is legal: it simply never hits.
        rays[3] = Ray::with_interval(Vec3::ZERO, Vec3::X, 2.0, 1.0);
        assert_eq!(check_rays(&rays), Ok(()));
    }

    #[test]
    fn outputs_must_be_npz_archives() {
        assert!(check_output(Path::new("hits.NPZ")).is_ok());
        for bad in ["-", "hits.npy", "hits"] {
            assert!(check_output(Path::new(bad)).is_err(), "{bad}");
        }
    }

    #[test]
    fn normals_and_points_are_nan_on_a_miss() {
        let mesh = TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]);
        let hit = Hit { t: 1.0, u: 0.25, v: 0.5, prim: 0 };
        let hits = [hit, Hit::MISS];
        assert_eq!(hit_normals(&hits, &mesh)[0], [0.0, 0.0, 1.0]);
        assert_eq!(hit_points(&hits, &mesh)[0], [0.25, 0.5, 0.0]);
        assert!(hit_normals(&hits, &mesh)[1].iter().chain(&hit_points(&hits, &mesh)[1]).all(|x| x.is_nan()));
    }
}
