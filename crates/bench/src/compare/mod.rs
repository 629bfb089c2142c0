//! Side by side (feature `compare`): the same rays on the same mesh through other libraries
//! (Embree 3, obvhs; tinybvh was dropped, see docs/bench.md), timed in the same process and run as our structures, and
//! checked against the same brute-force answers (docs/bench.md, "Side by side").

pub mod embree;
pub mod obvhs;

use crate::measure::{ms, timed_pass, Expected};
use crate::rays::{RayKind, RaySets};
use crate::results::{median, CompetitorKind, CompetitorResult, StructureResult};
use anyhow::{Context, Result};
use dynray_accel::batch::check_batch_lengths;
use dynray_accel::{BatchQuery, BATCH_CHUNK};
use dynray_geom::{Ray, TriangleMesh};
use rayon::prelude::*;
use std::time::Instant;

/// Rays per rayon task: the same as the [`BatchQuery`] blanket implementation that times
/// our structures, so their passes and ours are scheduled alike.
pub const CHUNK: usize = BATCH_CHUNK;

/// The primitive index of a miss in a closest-hit answer.
pub const MISS: u32 = u32::MAX;

/// The structure of ours the ratios compare with.
pub const OURS: &str = "bvh";

/// A library's structure built over one mesh, ready to trace through the same
/// [`BatchQuery`] trait as ours, with what the report says about it besides.
pub struct Built {
    /// The queries (every adapter traces in parallel over chunks of [`CHUNK`] rays).
    pub query: Box<dyn BatchQuery + Send>,
    /// Bytes the structure holds (including its copy of the triangles), where the library
    /// reports it or it can be computed from its arrays.
    pub memory_bytes: Option<usize>,
    /// True when `occluded_into` is the library's own any-hit query (not a closest-hit
    /// query in disguise).
    pub any_hit: bool,
}

/// Runs `f` on matching chunks of [`CHUNK`] rays and answers in parallel, after checking
/// the [`BatchQuery`] slice contract: how every adapter fans a batch out over the threads.
pub(crate) fn par_chunks_into<T: Send>(rays: &[Ray], out: &mut [T], f: impl Fn(&[Ray], &mut [T]) + Sync) {
    check_batch_lengths(rays.len(), out.len());
    rays.par_chunks(CHUNK).zip(out.par_chunks_mut(CHUNK)).for_each(|(r, o)| f(r, o));
}

/// A competitor: one library with one way of building and traversing.
pub trait Competitor: Send + Sync {
    /// Library (`embree`, `obvhs`).
    fn name(&self) -> &'static str;
    /// Layout / API within the library (`single-ray`, `cwbvh`).
    fn variant(&self) -> &'static str;
    /// What runs, in words, for the report (API, layout, build settings).
    fn describe(&self) -> String;
    /// Ray kinds it is measured on (`None`: every kind).
    fn kinds(&self) -> Option<&'static [RayKind]> {
        None
    }
    /// True for a packet API (Embree's `rtcIntersect8`): its primary rays are compared
    /// with our packet path (`primary-packet`) where our structure has one.
    fn packets(&self) -> bool {
        false
    }
    /// Builds over `mesh` (the timed part: everything from our mesh to a traceable
    /// structure, including the library's copy of the triangles).
    fn build(&self, mesh: &TriangleMesh) -> Result<Built>;
}

/// Every competitor compiled in; the ones that cannot run here are left out with a note
/// saying why (e.g. Embree without native 8-wide packets).
pub fn available(notes: &mut Vec<String>) -> Vec<Box<dyn Competitor>> {
    let mut out: Vec<Box<dyn Competitor>> = Vec::new();
    match embree::Embree::new(rayon::current_num_threads()) {
        Ok(e) => {
            let e = std::sync::Arc::new(e);
            out.push(Box::new(embree::SingleRay(e.clone())));
            if e.native_ray8() {
                out.push(Box::new(embree::Packet8(e)));
            } else {
                note(notes, "embree: no native 8-wide packets on this CPU/library: packet variant left out".into());
            }
        }
        Err(err) => note(notes, format!("embree: cannot create a device, left out: {err:#}")),
    }
    out.push(Box::new(obvhs::ObvhsCwBvh));
    out.push(Box::new(obvhs::ObvhsBvh2));
    out
}

/// Adds `n` once (every scene asks for the competitors again).
fn note(notes: &mut Vec<String>, n: String) {
    if !notes.contains(&n) {
        notes.push(n);
    }
}

/// How a competitor's answers compare with brute force's on the sampled rays.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Agreement {
    /// Rays compared.
    pub checked: usize,
    /// Same triangle (closest hit; a miss for a miss) or same `occluded`.
    pub same_answer: usize,
    /// Closest hit: both hit or both miss (whatever the triangle); shadow: = `same_answer`.
    pub same_hit_or_miss: usize,
    /// Largest |t − t_brute| / |t_brute| over the rays that hit the same triangle.
    pub max_rel_t_diff: f64,
}

impl Agreement {
    /// `same_answer / checked` (1 when nothing was checked).
    pub fn fraction(&self) -> f64 {
        if self.checked == 0 {
            1.0
        } else {
            self.same_answer as f64 / self.checked as f64
        }
    }
}

/// Compares `t`'s answers on the sampled rays of `exp` with brute force's.
pub fn agreement<Q: BatchQuery + ?Sized>(t: &Q, rays: &[Ray], exp: &Expected) -> Agreement {
    let sample: Vec<Ray> = exp.indices.iter().map(|&i| rays[i]).collect();
    let mut a = Agreement { checked: sample.len(), ..Default::default() };
    if exp.kind.is_shadow() {
        let got = t.occluded_batch(&sample);
        a.same_answer = got.iter().zip(&exp.occluded).filter(|(g, w)| g == w).count();
        a.same_hit_or_miss = a.same_answer;
    } else {
        let got = t.intersect_batch(&sample);
        for (g, want) in got.iter().zip(&exp.hits) {
            let (gt, gp) = (g.t, g.prim);
            let want_prim = if want.is_hit() { want.prim } else { MISS };
            if (gp != MISS) == want.is_hit() {
                a.same_hit_or_miss += 1;
            }
            if gp == want_prim {
                a.same_answer += 1;
                if gp != MISS {
                    let rel = ((gt as f64 - want.t as f64) / (want.t as f64).abs().max(f64::MIN_POSITIVE)).abs();
                    a.max_rel_t_diff = a.max_rel_t_diff.max(rel);
                }
            }
        }
    }
    a
}

/// Builds `c` once as a warm-up, then `repeat` more times; returns the last structure and
/// the timed builds in ms (as [`crate::measure::timed_builds`]).
pub fn timed_builds(c: &dyn Competitor, mesh: &TriangleMesh, repeat: usize) -> Result<(Built, Vec<f64>)> {
    let mut built = c.build(mesh)?;
    let mut times = Vec::with_capacity(repeat);
    for _ in 0..repeat.max(1) {
        drop(built);
        let t = Instant::now();
        built = c.build(mesh)?;
        times.push(ms(t));
    }
    Ok((built, times))
}

/// Ratio with the convention "> 1: ours is better": `theirs / ours` for costs (ms, bytes).
fn cost_ratio(theirs: f64, ours: f64) -> Option<f64> {
    (ours > 0.0 && theirs.is_finite()).then(|| theirs / ours)
}

/// Measures every competitor on one scene: build (warm-up + `repeat`, median), memory,
/// per ray kind a warm-up and `repeat` timed passes (median), and the agreement with
/// brute force on the sampled rays; ratios against our [`OURS`] row of `ours` when present.
#[allow(clippy::too_many_arguments)] // the standard run's pieces, as run.rs holds them
pub fn measure_scene(
    scene: &str,
    mesh: &TriangleMesh,
    sets: &RaySets,
    expected: &[Expected],
    repeat: usize,
    ours: &[StructureResult],
    notes: &mut Vec<String>,
    step: &dyn Fn(&str),
) -> Result<Vec<CompetitorResult>> {
    let reference = ours.iter().find(|s| s.accel == OURS);
    let mut results = Vec::new();
    for c in available(notes) {
        let label = format!("{} {}", c.name(), c.variant());
        step(&format!("{label}: build"));
        let (built, build_ms_runs) =
            timed_builds(c.as_ref(), mesh, repeat).with_context(|| format!("{scene}: cannot build {label}"))?;
        let build_ms = median(&build_ms_runs);
        let memory_bytes = built.memory_bytes;
        let mut kinds = Vec::new();
        for (kind, rays) in &sets.sets {
            if c.kinds().is_some_and(|ks| !ks.contains(kind)) {
                continue;
            }
            step(&format!("{label}: {}", kind.name()));
            let shadow = kind.is_shadow();
            timed_pass(built.query.as_ref(), rays, shadow);
            let mut runs = Vec::with_capacity(repeat);
            let mut hits = 0;
            for _ in 0..repeat.max(1) {
                let (t, h) = timed_pass(built.query.as_ref(), rays, shadow);
                runs.push(t);
                hits = h;
            }
            let agree = expected
                .iter()
                .find(|e| e.kind == *kind)
                .map(|e| agreement(built.query.as_ref(), rays, e))
                .unwrap_or_default();
            let trace_ms = median(&runs);
            let mrays_per_s = if trace_ms > 0.0 { rays.len() as f64 / trace_ms / 1e3 } else { 0.0 };
            let ours = reference.and_then(|r| match &r.primary_packets {
                Some(p) if c.packets() && *kind == RayKind::Primary => Some(p),
                _ => r.kinds.iter().find(|k| k.kind == kind.name()),
            });
            let ours_mrays = ours.map(|k| k.mrays_per_s);
            kinds.push(CompetitorKind {
                kind: kind.name().to_string(),
                rays: rays.len(),
                any_hit: shadow && built.any_hit,
                trace_ms,
                trace_ms_runs: runs,
                mrays_per_s,
                hits,
                checked: agree.checked,
                same_answer: agree.same_answer,
                same_hit_or_miss: agree.same_hit_or_miss,
                agreement: agree.fraction(),
                max_rel_t_diff: agree.max_rel_t_diff,
                ours_over_theirs_speed: ours_mrays.and_then(|o| (mrays_per_s > 0.0).then(|| o / mrays_per_s)),
                ours_kind: ours.map(|k| k.kind.clone()),
            });
        }
        results.push(CompetitorResult {
            name: c.name().to_string(),
            variant: c.variant().to_string(),
            describe: c.describe(),
            build_ms,
            build_ms_runs,
            memory_bytes,
            ours: reference.map(|r| r.accel.clone()),
            ours_over_theirs_build: reference.and_then(|r| cost_ratio(build_ms, r.build_ms)),
            ours_over_theirs_memory: reference
                .and_then(|r| memory_bytes.and_then(|m| cost_ratio(m as f64, r.memory_bytes as f64))),
            kinds,
        });
    }
    Ok(results)
}

/// Our rays as plain arrays: origin, direction, tmin, tmax (what every adapter converts from).
#[inline]
pub(crate) fn parts(r: &Ray) -> ([f32; 3], [f32; 3], f32, f32) {
    (r.origin.to_array(), r.dir.to_array(), r.tmin, r.tmax)
}
