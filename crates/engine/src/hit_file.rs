//! The ray and hit files of the trace job, for other programs (numpy users): what
//! `dynray trace-rays` and the Python package's `dynray.trace_rays` read and write
//! (docs/trace-rays.md).
//!
//! Input: .npy of shape (N, 8): origin xyz, direction xyz, tmin, tmax; float32 in C order
//! as it is, float64 or Fortran order converted (with a note saying so); all rows, or a
//! slice `A..B` read without the rest of the file.
//! Output: .npz with `t` (float32, inf on miss), `prim` (int64, -1 on miss), `u`, `v`
//! (float32), one entry per ray in input order; with occluded queries, one bool `occluded`;
//! a slice's archive adds `rows` = `[A, B, N]` (int64), which `hit_merge` reads.
//! Arrays are stored uncompressed, as numpy's `np.savez` writes them.

use anyhow::{bail, Context, Result};
use bytemuck::Zeroable;
use dynray_geom::{Hit, Ray, TriangleMesh};
use npyz::WriterBuilder;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::ops::Range;
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

/// Which rows of its ray file a slice archive holds: `start..end` (half-open, as
/// Python's `rays[start:end]`) of the file's `total`. Written as the int64 array `rows`
/// = `[start, end, total]` beside the hits, so `merge-hits` can check order and coverage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowSpan {
    /// First row held.
    pub start: u64,
    /// One past the last row held.
    pub end: u64,
    /// Rows of the whole ray file.
    pub total: u64,
}

impl RowSpan {
    /// The array name of the span in a slice archive.
    pub const ARRAY: &'static str = "rows";

    /// Rows held.
    pub fn len(&self) -> u64 {
        self.end - self.start
    }

    /// True when the slice holds no row (`A..A`).
    pub fn is_empty(&self) -> bool {
        self.start == self.end
    }
}

/// Reads and checks the (N, 8) ray array: float32 as it is, float64 and Fortran order
/// (what numpy users often have) converted, with a note saying so.
/// `note` hears of a conversion (what the binary prints as `dynray: note: …`).
pub fn read_rays(path: &Path, note: &mut dyn FnMut(String)) -> Result<Vec<Ray>> {
    Ok(read_ray_rows(path, None, note)?.0)
}

/// Reads rows `rows` (half-open; all of them when `None`) of the (N, 8) ray array and
/// returns them with the span they are. Only those rows' bytes are read: the header,
/// then one seek and one read (C order) or one per column (Fortran order, where a row
/// slice is strided) — so each task of a batch split over machines reads its own part
/// of a file of any size. A range past the file's rows is an error naming the file;
/// `A..A` is an empty slice. Bad rows are named by their row in the file.
pub fn read_ray_rows(
    path: &Path,
    rows: Option<Range<u64>>,
    note: &mut dyn FnMut(String),
) -> Result<(Vec<Ray>, RowSpan)> {
    let file = dynray_geom::file::open(path).with_context(|| format!("{}: cannot open", path.display()))?;
    let file_len = file.metadata().map(|m| m.len()).unwrap_or(u64::MAX);
    // The header's length and nesting first: npyz's parser takes time exponential in
    // the nesting (a 200-byte file hung it; docs/fuzzing.md).
    let mut prefix = Vec::new();
    (&file)
        .take(dynray_scene::formats::npz::NPY_PREFIX_BYTES as u64)
        .read_to_end(&mut prefix)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    dynray_scene::formats::npz::check_npy_header(&prefix).map_err(|m| anyhow::anyhow!("{}: {m}", path.display()))?;
    (&file).seek(SeekFrom::Start(0)).with_context(|| format!("{}: cannot read", path.display()))?;
    let mut reader = BufReader::new(file);
    let header = npyz::NpyHeader::from_reader(&mut reader)
        .with_context(|| format!("{}: not a valid .npy file", path.display()))?;
    let shape = header.shape().to_vec();
    if shape.len() != 2 || shape[1] != 8 {
        bail!("{}: rays must have shape (N, 8), found {:?}", path.display(), shape);
    }
    let n = shape[0];
    let fortran = header.order() == npyz::Order::Fortran;
    let descr = header.dtype().descr();
    let wide = match descr.as_str() {
        "'<f4'" => false,
        "'<f8'" => true,
        _ => bail!("{}: rays must be float32 or float64 (little-endian '<f4' or '<f8'), found {descr}", path.display()),
    };
    let item: u64 = if wide { 8 } else { 4 };
    let data_start = reader.stream_position().with_context(|| format!("{}: cannot read", path.display()))?;
    // The header may promise any number of rows: refuse one the file cannot hold before
    // anything is allocated for it (a product past u64 wrapped into a small one).
    match n.checked_mul(8 * item).and_then(|bytes| bytes.checked_add(data_start)) {
        Some(end) if end <= file_len => {}
        _ => bail!(
            "{}: the header promises {n} rays of 8 values, more than the file's {file_len} bytes hold",
            path.display()
        ),
    }
    let rows = rows.unwrap_or(0..n);
    if rows.start > rows.end {
        bail!("{}: rows {}..{}: the first row is past the end (B is exclusive)", path.display(), rows.start, rows.end);
    }
    if rows.end > n {
        bail!(
            "{}: rows {}..{} reach past the file's {n} rays (rows are 0..{n}, B exclusive)",
            path.display(),
            rows.start,
            rows.end
        );
    }
    let span = RowSpan { start: rows.start, end: rows.end, total: n };
    // Bounded by the file's size (checked above), so it fits in memory's address space.
    let count = usize::try_from(span.len()).context("too many rows for this machine")?;
    let mut rays = vec![Ray::zeroed(); count];
    let mut file = reader.into_inner();
    let truncated = || format!("{}: truncated or unreadable data", path.display());
    if fortran {
        // Column j holds every row's value j: the slice is 8 runs of `count` values.
        let mut column = vec![0f32; count];
        let values: &mut [f32] = bytemuck::cast_slice_mut(&mut rays);
        for j in 0..8u64 {
            let offset = data_start + (j * n + span.start) * item;
            read_values(&mut file, offset, wide, &mut column).with_context(truncated)?;
            for (row, &x) in values.chunks_exact_mut(8).zip(&column) {
                row[j as usize] = x;
            }
        }
    } else {
        let offset = data_start + span.start * 8 * item;
        read_values(&mut file, offset, wide, bytemuck::cast_slice_mut(&mut rays)).with_context(truncated)?;
    }
    if wide || fortran {
        let what = match (wide, fortran) {
            (true, true) => "float64 in Fortran order",
            (true, false) => "float64",
            _ => "Fortran order",
        };
        note(format!("{}: rays given as {what}, converted to C-order float32", path.display()));
    }
    check_rays_from(&rays, span.start).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok((rays, span))
}

/// Reads `out.len()` little-endian values at byte `offset`: float32 straight into `out`
/// (rows are `Ray`s as they lie in memory: no conversion), float64 (`wide`) block by
/// block, rounded to nearest as numpy's `astype(np.float32)` does (the engine is f32).
fn read_values(file: &mut std::fs::File, offset: u64, wide: bool, out: &mut [f32]) -> std::io::Result<()> {
    file.seek(SeekFrom::Start(offset))?;
    if !wide {
        file.read_exact(bytemuck::cast_slice_mut(out))?;
        if cfg!(target_endian = "big") {
            out.iter_mut().for_each(|x| *x = f32::from_bits(u32::from_le(x.to_bits())));
        }
        return Ok(());
    }
    // 64K values (512 KiB) at a time, so a float64 file costs no second copy of itself.
    const BLOCK: usize = 1 << 16;
    let mut bytes = vec![0u8; 8 * BLOCK.min(out.len())];
    for chunk in out.chunks_mut(BLOCK) {
        let bytes = &mut bytes[..8 * chunk.len()];
        file.read_exact(bytes)?;
        for (x, b) in chunk.iter_mut().zip(bytes.chunks_exact(8)) {
            *x = f64::from_le_bytes(b.try_into().expect("chunks of 8 bytes")) as f32;
        }
    }
    Ok(())
}

/// The rule every ray input follows (files and the Python package's arrays alike): a
/// finite origin and direction, and no NaN in `[tmin, tmax]`. The message names the row.
pub fn check_rays(rays: &[Ray]) -> Result<(), String> {
    check_rays_from(rays, 0)
}

/// [`check_rays`] over rows numbered from `first` (a slice of a larger file names the
/// file's row).
pub fn check_rays_from(rays: &[Ray], first: u64) -> Result<(), String> {
    for (i, r) in rays.iter().enumerate() {
        let i = first + i as u64;
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
    check_npz_output(path, "trace-rays")
}

/// [`check_output`] for `command`'s messages.
pub(crate) fn check_npz_output(path: &Path, command: &str) -> Result<()> {
    if path.as_os_str() == "-" {
        bail!("-o -: {command} writes a .npz archive, not a stream; give a file name such as hits.npz");
    }
    let npz = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("npz"));
    if !npz {
        bail!(
            "{}: {command} writes a .npz archive (arrays t, prim, u, v, or occluded); name the output *.npz",
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

pub(crate) type Npz = npyz::npz::NpzWriter<BufWriter<std::fs::File>>;

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
/// float data. ZIP64 only where an array needs it. Every entry is dated zip's epoch
/// (1980-01-01), not the clock, so an archive is a function of its hits alone: a run
/// again, or slices merged (`hit_merge`), give the same bytes.
pub(crate) fn stored(bytes: u64) -> zip::write::FileOptions {
    zip::write::FileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .large_file(bytes >= u32::MAX as u64)
        .last_modified_time(zip::DateTime::default())
}

/// An (N, 3) float32 array.
pub(crate) fn write_rows(npz: &mut Npz, name: &str, rows: &[[f32; 3]]) -> std::io::Result<()> {
    let options = stored(std::mem::size_of_val(rows) as u64);
    let mut w = npz.array::<f32>(name, options)?.default_dtype().shape(&[rows.len() as u64, 3]).begin_nd()?;
    w.extend(rows.iter().flatten().copied())?;
    w.finish()
}

pub(crate) fn write_array<T: npyz::AutoSerialize + npyz::Serialize + Copy>(
    npz: &mut Npz,
    name: &str,
    data: &[T],
) -> std::io::Result<()> {
    let options = stored(std::mem::size_of_val(data) as u64);
    let mut w = npz.array::<T>(name, options)?.default_dtype().shape(&[data.len() as u64]).begin_nd()?;
    w.extend(data.iter().copied())?;
    w.finish()
}

/// Writes the archive atomically ([`crate::output`]): a failure never leaves a partial
/// file behind, and an input is never replaced.
pub(crate) fn write_npz(path: &Path, fill: impl FnOnce(&mut Npz) -> std::io::Result<()>) -> Result<()> {
    crate::output::write_with(path, |file| {
        let mut npz = npyz::npz::NpzWriter::new(BufWriter::new(file.try_clone()?));
        fill(&mut npz)?;
        let mut inner = npz.zip_writer().finish()?;
        inner.flush()?;
        Ok(())
    })
}

/// The `rows` array of a slice archive, after its hits: `[start, end, total]` as int64.
fn write_span(npz: &mut Npz, span: Option<RowSpan>) -> std::io::Result<()> {
    match span {
        None => Ok(()),
        Some(s) => write_array(npz, RowSpan::ARRAY, &[s.start as i64, s.end as i64, s.total as i64]),
    }
}

/// Writes the closest hits' `fields` to the archive `path` (atomically); with `span`
/// (`trace-rays --rows`), the `rows` array after them.
pub fn write_hits(
    path: &Path,
    fields: &[HitField],
    hits: &[Hit],
    mesh: &TriangleMesh,
    span: Option<RowSpan>,
) -> Result<()> {
    write_npz(path, |npz| {
        fields.iter().try_for_each(|&f| write_field(npz, f, hits, mesh))?;
        write_span(npz, span)
    })
}

/// Writes the any-hit answers as one bool array `occluded` (atomically); with `span`,
/// the `rows` array after it.
pub fn write_occluded(path: &Path, occluded: &[bool], span: Option<RowSpan>) -> Result<()> {
    write_npz(path, |npz| {
        write_array(npz, "occluded", occluded)?;
        write_span(npz, span)
    })
}

/// A version-1 `.npy` file of `header` (its Python literal, padded as numpy pads it)
/// and raw `data`, however wrong the header: for tests of hostile files.
#[cfg(test)]
pub(crate) fn npy_with_header(header: &str, data: &[u8]) -> Vec<u8> {
    let mut h = header.to_string();
    h.push_str(&" ".repeat((64 - (10 + h.len() + 1) % 64) % 64));
    h.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(h.len() as u16).to_le_bytes());
    out.extend_from_slice(h.as_bytes());
    out.extend_from_slice(data);
    out
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

    /// The archive is a function of the answers: entries dated zip's epoch, not the
    /// clock, so a merge of slices and a run over every row are one byte string.
    #[test]
    fn archives_carry_no_clock_time() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("o.npz");
        write_occluded(&path, &[true, false], Some(RowSpan { start: 2, end: 4, total: 9 })).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..4], b"PK\x03\x04");
        // The first local header's DOS time and date: 00:00:00, 1980-01-01.
        assert_eq!(&bytes[10..14], &[0, 0, 0x21, 0]);
        let mut npz = npyz::npz::NpzArchive::open(&path).unwrap();
        let rows: Vec<i64> = npz.by_name("rows").unwrap().unwrap().into_vec().unwrap();
        assert_eq!(rows, [2, 4, 9]);
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

    /// Regression (found by fuzzing npyz's header parser, docs/fuzzing.md): 30 unclosed
    /// brackets in a ray file's header hung the reader (the parse takes time exponential
    /// in the nesting); refused before npyz sees it now. A plain file still reads.
    #[test]
    fn a_nested_ray_file_header_is_refused_at_once() {
        let npy = npy_with_header;
        let dir = tempfile::tempdir().unwrap();
        let nested = dir.path().join("nested.npy");
        let header = format!("{{'descr': '<f4', {} 'fortran_order': False, 'shape': (1, 8), }}", "[".repeat(30));
        std::fs::write(&nested, npy(&header, &[0; 32])).unwrap();
        let start = std::time::Instant::now();
        let e = read_rays(&nested, &mut |_| {}).unwrap_err().to_string();
        assert!(start.elapsed().as_secs() < 5 && e.contains("nested.npy") && e.contains("nests brackets"), "{e}");
        let plain = dir.path().join("plain.npy");
        let row: Vec<u8> = [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 10.0].iter().flat_map(|x| x.to_le_bytes()).collect();
        std::fs::write(&plain, npy("{'descr': '<f4', 'fortran_order': False, 'shape': (1, 8), }", &row)).unwrap();
        let rays = read_rays(&plain, &mut |_| {}).unwrap();
        assert_eq!((rays.len(), rays[0].dir, rays[0].tmax), (1, Vec3::X, 10.0));
    }
}
