//! The trace job: a batch of rays against a scene or mesh file at one instant (posed,
//! its physics simulated to that instant), on the CPU or the GPU — from files (`dynray
//! trace-rays`, Python's `dynray.trace_rays`) or in memory ([`trace`]).
//!
//! Triangle indices follow the faces of the input file (polygons fan-triangulated): the
//! scene is read unshaded. The library does not print: notes and load warnings go to
//! the caller's callback, and [`Summary`]'s `Display` is the binary's last line.

use crate::backend::BackendChoice;
use crate::frame_step::{FrameSettings, Stage};
use crate::hit_file::{check_output, read_ray_rows, write_hits, write_occluded, HitField, RowSpan};
use crate::load::Loaded;
use crate::timeline::TimeChoice;
use anyhow::{Context, Result};
use dynray_accel::{AccelSpec, BatchQuery, Coherent};
use dynray_geom::{Hit, Ray, TriangleMesh};
use std::ops::Range;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// What to ask of every ray.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Query {
    /// Closest hits, writing these arrays.
    Closest(Vec<HitField>),
    /// Any-hit (shadow) queries, writing one bool array `occluded`.
    Occluded,
}

/// One file-to-file run.
#[derive(Clone, Debug)]
pub struct TraceJob {
    /// Mesh or scene file, any format dynray reads.
    pub mesh: PathBuf,
    /// The (N, 8) `.npy` ray array.
    pub rays: PathBuf,
    /// Only these rows of it (half-open, as Python's `rays[a:b]`), read without the rest
    /// of the file; the archive then records them in an int64 array `rows` = `[a, b, N]`
    /// (`dynray merge-hits` joins such slices). `None`: every row, no `rows` array.
    pub rows: Option<Range<u64>>,
    /// The `.npz` archive to write.
    pub output: PathBuf,
    /// The structure and its parameters.
    pub accel: AccelSpec,
    /// Closest hits or any-hit.
    pub query: Query,
    /// The instant of an animated file (frame 0 by default); physics is simulated to it.
    pub when: TimeChoice,
    /// CPU or GPU (the GPU traces a `bvh` built as `gpu_build` says; `build` in the
    /// summary includes opening the device and any upload).
    pub backend: BackendChoice,
}

/// Something a person should see that does not stop the run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Notice {
    /// The rays were converted (float64 or Fortran order): what the binary prints as
    /// `dynray: note: …`.
    Note(String),
    /// A warning of the mesh loader (a missing `.mtl`, …), each distinct one once.
    Warning(String),
}

/// Counts and times of a finished run.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Rays traced.
    pub rays: usize,
    /// The rows traced, when the job asked for a slice.
    pub rows: Option<RowSpan>,
    /// Rays that hit (closest hits) or are occluded (any-hit).
    pub hits: usize,
    /// True for an any-hit run.
    pub occluded: bool,
    /// The structure's name.
    pub accel: &'static str,
    /// Reading the rays and the mesh (and simulating to the instant).
    pub read: Duration,
    /// Building the structure.
    pub build: Duration,
    /// Tracing every ray.
    pub trace: Duration,
    /// Writing the archive.
    pub write: Duration,
}

impl std::fmt::Display for Summary {
    /// `1000000 rays, 512027 hits; read 157.0 ms, bvh build 68.0 ms, trace …, write …`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let what = if self.occluded { "occluded" } else { "hits" };
        if let Some(r) = self.rows {
            write!(f, "rows {}..{} of {}: ", r.start, r.end, r.total)?;
        }
        write!(
            f,
            "{} rays, {} {what}; read {:.1} ms, {} build {:.1} ms, trace {:.1} ms, write {:.1} ms",
            self.rays,
            self.hits,
            ms(self.read),
            self.accel,
            ms(self.build),
            ms(self.trace),
            ms(self.write)
        )
    }
}

/// The answers of a batch, in ray order.
pub enum Answers {
    /// Closest hits.
    Hits(Vec<Hit>),
    /// Any-hit answers.
    Occluded(Vec<bool>),
}

impl Answers {
    /// Rays that hit or are occluded.
    pub fn count(&self) -> usize {
        match self {
            Answers::Hits(h) => h.iter().filter(|h| h.is_hit()).count(),
            Answers::Occluded(o) => o.iter().filter(|&&o| o).count(),
        }
    }
}

impl TraceJob {
    /// Runs the job: checks the output name, reads the rays and the posed mesh, builds,
    /// traces on the current rayon pool and writes the archive atomically.
    pub fn run(&self, notices: &mut dyn FnMut(Notice)) -> Result<Summary> {
        check_output(&self.output)?;
        self.when.check()?;
        self.backend.check()?;
        let t_read = Instant::now();
        let (rays, span) = read_ray_rows(&self.rays, self.rows.clone(), &mut |m| notices(Notice::Note(m)))?;
        // The span goes into the archive only when a slice was asked for: a whole run's
        // archive stays what it always was.
        let span = self.rows.as_ref().map(|_| span);
        if crate::load::is_adf(&self.mesh) {
            anyhow::bail!("{}: a distance field has no triangles to trace; give its source mesh", self.mesh.display());
        }
        let loaded = Loaded::open(Some(&self.mesh))?;
        for w in &loaded.warnings {
            notices(Notice::Warning(w.clone()));
        }
        let mesh = posed_mesh(loaded, &self.when)?;
        let read = t_read.elapsed();
        let occluded = self.query == Query::Occluded;
        let (answers, timing) = trace(&mesh, &rays, &self.accel, occluded, &self.backend)
            .with_context(|| format!("{}: cannot build {}", self.mesh.display(), self.accel))?;
        let t2 = Instant::now();
        match (&answers, &self.query) {
            (Answers::Occluded(o), _) => write_occluded(&self.output, o, span)?,
            (Answers::Hits(h), Query::Closest(fields)) => write_hits(&self.output, fields, h, &mesh, span)?,
            (Answers::Hits(_), Query::Occluded) => unreachable!("occluded queries answer booleans"),
        }
        let write = t2.elapsed();
        Ok(Summary {
            rays: rays.len(),
            rows: span,
            hits: answers.count(),
            occluded,
            accel: timing.accel,
            read,
            build: timing.build,
            trace: timing.trace,
            write,
        })
    }
}

/// The triangles of `loaded` (unshaded) at the instant `when` chooses: posed, its
/// physics simulated to that time.
pub fn posed_mesh(mut loaded: Loaded, when: &TimeChoice) -> Result<TriangleMesh> {
    let time = when.apply(&mut loaded.scene, &loaded.label)?;
    let mut stage = Stage::new(loaded.scene, &loaded.label, FrameSettings::default())?;
    stage.pose(time)?;
    Ok(std::mem::take(&mut stage.frame_mut().mesh))
}

/// The structure's name and times of an in-memory [`trace`].
#[derive(Clone, Copy, Debug)]
pub struct TraceTiming {
    /// The structure's name (`bvh (gpu, sah build)` on the GPU).
    pub accel: &'static str,
    /// Building (on the GPU: with opening the device and the upload).
    pub build: Duration,
    /// Tracing.
    pub trace: Duration,
}

/// Builds `accel` over `mesh` on `backend` and traces `rays` (closest hits, or any hit
/// when `occluded`), on the current rayon pool.
pub fn trace(
    mesh: &TriangleMesh,
    rays: &[Ray],
    accel: &AccelSpec,
    occluded: bool,
    backend: &BackendChoice,
) -> Result<(Answers, TraceTiming)> {
    let t0 = Instant::now();
    match &backend.gpu {
        None => {
            let cpu = accel.build(mesh, None)?;
            let build = t0.elapsed();
            // Both queries through the coherent path: groups of 8 consecutive rays with one
            // origin (a camera's, a point's towards a light) go through the structure's
            // packets where it has them; the answers are the single rays', bit for bit.
            let (answers, trace) = query(&Coherent(cpu.as_ref()), rays, occluded);
            Ok((answers, TraceTiming { accel: cpu.name(), build, trace }))
        }
        Some(options) => {
            let params = accel.binary_bvh_params()?;
            let ctx = std::sync::Arc::new(dynray_gpu::GpuContext::new(options)?);
            let gpu = dynray_gpu::GpuBvh::build(ctx, mesh, backend.gpu_build, &params)?.0;
            let build = t0.elapsed();
            let (answers, trace) = query(&gpu, rays, occluded);
            let name = match backend.gpu_build {
                dynray_gpu::GpuBuild::Cpu => "bvh (gpu)",
                dynray_gpu::GpuBuild::Sah => "bvh (gpu, sah build)",
                dynray_gpu::GpuBuild::Lbvh => "bvh (gpu, lbvh build)",
            };
            Ok((answers, TraceTiming { accel: name, build, trace }))
        }
    }
}

fn query<Q: BatchQuery + ?Sized>(accel: &Q, rays: &[Ray], occluded: bool) -> (Answers, Duration) {
    let t = Instant::now();
    let answers = if occluded {
        Answers::Occluded(accel.occluded_batch(rays))
    } else {
        Answers::Hits(accel.intersect_batch(rays))
    };
    (answers, t.elapsed())
}
