//! `dynray trace-rays`: a batch ray-query interface for other programs (numpy users).
//!
//! Input: .npy of shape (N, 8): origin xyz, direction xyz, tmin, tmax; float32 in C order
//! as it is, float64 or Fortran order converted (with a note on stderr).
//! Output: .npz with `t` (float32, inf on miss), `prim` (int64, -1 on miss), `u`, `v`
//! (float32), one entry per ray in input order; with `--occluded`, one bool `occluded`.
//! Triangle indices follow the faces of the input file (polygons fan-triangulated).
//! Arrays are stored uncompressed, as numpy's `np.savez` writes them.

use crate::cli::{HitField, TraceRaysArgs};
use anyhow::{bail, Context, Result};
use dynray_accel::BatchQuery;
use dynray_geom::{Hit, Ray, TriangleMesh};
use npyz::WriterBuilder;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::time::Instant;

pub fn run(a: TraceRaysArgs) -> Result<()> {
    check_output(&a.output)?;
    let t_read = Instant::now();
    let rays = read_rays(&a.rays)?;
    // Hits need only the triangles: the file's vertices as they are, as `load_mesh`.
    let mut scene = super::load_unshaded(&a.mesh)?;
    let time = super::time::apply(&mut scene, &a.mesh.display().to_string(), &a.when)?;
    let frame = scene.frame(time);
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
        write_npz(&a.output, |npz| {
            for field in &a.fields {
                write_field(npz, *field, &hits, &frame.mesh)?;
            }
            Ok(())
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

/// Reads and checks the (N, 8) ray array: float32 as it is, float64 and Fortran order
/// (what numpy users often have) converted, with a note on stderr saying so.
fn read_rays(path: &Path) -> Result<Vec<Ray>> {
    let file = std::fs::File::open(path).with_context(|| format!("{}: cannot open", path.display()))?;
    let npy = npyz::NpyFile::new(std::io::BufReader::new(file))
        .with_context(|| format!("{}: not a valid .npy file", path.display()))?;
    let shape = npy.shape().to_vec();
    if shape.len() != 2 || shape[1] != 8 {
        bail!("{}: rays must have shape (N, 8), found {:?}", path.display(), shape);
    }
    let n = shape[0];
    let fortran = npy.order() == npyz::Order::Fortran;
    let descr = npy.dtype().descr();
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
        eprintln!("dynray: note: {}: rays given as {what}, converted to C-order float32", path.display());
    }
    // Rows are `Ray`s as they lie in memory (`Ray` is `#[repr(C)]`, 8 f32s): no copy
    // where the vector's capacity allows, one memcpy otherwise.
    let rays: Vec<Ray> = bytemuck::try_cast_vec(data).unwrap_or_else(|(_, data)| bytemuck::cast_slice(&data).to_vec());
    for (i, r) in rays.iter().enumerate() {
        if !(r.origin.is_finite() && r.dir.is_finite()) {
            bail!("{}: ray {i} has a non-finite origin or direction component ({r:?})", path.display());
        }
        if r.tmin.is_nan() || r.tmax.is_nan() {
            bail!("{}: ray {i} has a NaN tmin or tmax", path.display());
        }
    }
    Ok(rays)
}

/// The output must name a `.npz` archive: `-o -` (no stdout stream here) and `-o x.npy`
/// (one array cannot hold t, prim, u and v) are refused before any work.
fn check_output(path: &Path) -> Result<()> {
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

type Npz = npyz::npz::NpzWriter<BufWriter<std::fs::File>>;

/// Writes one requested array of the closest hits. `normal` and `point` are (N, 3):
/// the unit geometric normal as the triangle is wound (`(p1-p0)×(p2-p0)`) and the hit
/// point `(1-u-v)·p0 + u·p1 + v·p2`, NaN on a miss.
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
        HitField::Normal | HitField::Point => {
            let miss = [f32::NAN; 3];
            let rows: Vec<[f32; 3]> = hits
                .iter()
                .map(|h| {
                    if !h.is_hit() {
                        return miss;
                    }
                    let tri = mesh.triangle(h.prim as usize);
                    let (p0, p1, p2) = (tri.p0, tri.p1, tri.p2);
                    if field == HitField::Normal {
                        (p1 - p0).cross(p2 - p0).normalize_or_zero().to_array()
                    } else {
                        (p0 * (1.0 - h.u - h.v) + p1 * h.u + p2 * h.v).to_array()
                    }
                })
                .collect();
            write_rows(npz, name, &rows)
        }
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
