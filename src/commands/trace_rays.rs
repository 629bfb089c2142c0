//! `dynray trace-rays`: a batch ray-query interface for other programs (numpy users).
//!
//! Input: float32 .npy of shape (N, 8) in C order: origin xyz, direction xyz, tmin, tmax.
//! Output: .npz with `t` (float32, inf on miss), `prim` (int64, -1 on miss), `u`, `v`
//! (float32), one entry per ray in input order; with `--occluded`, one bool `occluded`.
//! Triangle indices follow the faces of the input file (polygons fan-triangulated).
//! Arrays are stored uncompressed, as numpy's `np.savez` writes them.

use crate::cli::TraceRaysArgs;
use anyhow::{bail, Context, Result};
use dynray_accel::BatchQuery;
use dynray_geom::{Ray, Vec3};
use npyz::WriterBuilder;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::time::Instant;

pub fn run(a: TraceRaysArgs) -> Result<()> {
    let t_read = Instant::now();
    let rays = read_rays(&a.rays)?;
    let frame = super::load_scene(&a.mesh)?.frame(0.0);
    let read = t_read.elapsed();
    let t0 = Instant::now();
    let accel =
        a.accel.build(&frame.mesh, None).with_context(|| format!("{}: cannot build {}", a.mesh.display(), a.accel))?;
    let build = t0.elapsed();
    let t1 = Instant::now();
    let (summary, trace, write) = if a.occluded {
        let occ = accel.occluded_batch(&rays);
        let trace = t1.elapsed();
        let t2 = Instant::now();
        write_npz(&a.output, |npz| write_array(npz, "occluded", &occ))?;
        (format!("{} occluded", occ.iter().filter(|&&o| o).count()), trace, t2.elapsed())
    } else {
        let hits = accel.intersect_batch(&rays);
        let trace = t1.elapsed();
        let t2 = Instant::now();
        let t: Vec<f32> = hits.iter().map(|h| h.t).collect();
        let prim: Vec<i64> = hits.iter().map(|h| if h.is_hit() { h.prim as i64 } else { -1 }).collect();
        let u: Vec<f32> = hits.iter().map(|h| h.u).collect();
        let v: Vec<f32> = hits.iter().map(|h| h.v).collect();
        write_npz(&a.output, |npz| {
            write_array(npz, "t", &t)?;
            write_array(npz, "prim", &prim)?;
            write_array(npz, "u", &u)?;
            write_array(npz, "v", &v)
        })?;
        (format!("{} hits", hits.iter().filter(|h| h.is_hit()).count()), trace, t2.elapsed())
    };
    let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
    eprintln!(
        "{} rays, {summary}; read {:.1} ms, {} build {:.1} ms, trace {:.1} ms, write {:.1} ms",
        rays.len(),
        ms(read),
        accel.name(),
        ms(build),
        ms(trace),
        ms(write)
    );
    Ok(())
}

/// Reads and checks the (N, 8) float32 ray array.
fn read_rays(path: &Path) -> Result<Vec<Ray>> {
    let file = std::fs::File::open(path).with_context(|| format!("{}: cannot open", path.display()))?;
    let npy = npyz::NpyFile::new(std::io::BufReader::new(file))
        .with_context(|| format!("{}: not a valid .npy file", path.display()))?;
    let shape = npy.shape().to_vec();
    if shape.len() != 2 || shape[1] != 8 {
        bail!("{}: rays must have shape (N, 8), found {:?}", path.display(), shape);
    }
    if npy.order() != npyz::Order::C {
        bail!("{}: rays must be in C order (numpy's default), found Fortran order", path.display());
    }
    let dtype = npy.dtype();
    if dtype != npyz::DType::Plain("<f4".parse().unwrap()) {
        bail!("{}: rays must be float32 (little-endian '<f4'), found {}", path.display(), dtype.descr());
    }
    let data: Vec<f32> = npy.into_vec().with_context(|| format!("{}: truncated or unreadable data", path.display()))?;
    if data.len() as u64 != shape[0] * 8 {
        bail!("{}: holds {} values, the header promises {}", path.display(), data.len(), shape[0] * 8);
    }
    data.chunks_exact(8)
        .enumerate()
        .map(|(i, r)| {
            if let Some(bad) = r[..6].iter().find(|x| !x.is_finite()) {
                bail!("{}: ray {i} has a non-finite origin or direction component ({bad})", path.display());
            }
            if r[6].is_nan() || r[7].is_nan() {
                bail!("{}: ray {i} has a NaN tmin or tmax", path.display());
            }
            Ok(Ray::with_interval(Vec3::new(r[0], r[1], r[2]), Vec3::new(r[3], r[4], r[5]), r[6], r[7]))
        })
        .collect()
}

type Npz = npyz::npz::NpzWriter<BufWriter<std::fs::File>>;

fn write_array<T: npyz::AutoSerialize + npyz::Serialize + Copy>(
    npz: &mut Npz,
    name: &str,
    data: &[T],
) -> std::io::Result<()> {
    // Stored, not deflated (numpy's own `np.savez` default): compressing hit arrays took
    // about 80 % of a 1M-ray round trip and saves little on float data. ZIP64 only where
    // an array needs it.
    let bytes = std::mem::size_of_val(data) as u64;
    let options = zip::write::FileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .large_file(bytes >= u32::MAX as u64);
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
    let tmp = dynray_bench::output::readable_temp_builder()
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
