//! Measuring one structure on one scene: build, shape, timed and counted passes per ray
//! kind, the check against brute force, and the time to image of a Whitted render.

use crate::rays::{RayKind, RaySets};
use crate::results::{median, KindResult, Mismatch, StructureResult, Work};
use anyhow::{Context, Result};
use dynray_accel::AccelSpec;
use dynray_accel::{Accel, BatchQuery, Coherent, TraversalCounts};
use dynray_geom::{Hit, Ray};
use dynray_render::{render, RenderOptions};
use dynray_scene::Frame;
use rayon::prelude::*;
use std::hint::black_box;
use std::time::Instant;

/// Brute force's answers for the sampled rays of one kind.
pub struct Expected {
    /// Ray kind.
    pub kind: RayKind,
    /// Sampled ray indices.
    pub indices: Vec<usize>,
    /// Closest hits (non-shadow kinds) of those rays.
    pub hits: Vec<Hit>,
    /// Occlusion answers (shadow kind) of those rays.
    pub occluded: Vec<bool>,
}

/// Evenly spaced indices: all of `0..n` when `sample` is `None` or not smaller than `n`.
pub fn sample_indices(n: usize, sample: Option<usize>) -> Vec<usize> {
    match sample {
        Some(s) if s < n => (0..s).map(|i| i * n / s).collect(),
        _ => (0..n).collect(),
    }
}

/// Brute force's answers on a sample of every ray set (computed once per scene).
pub fn oracle(brute: &dyn Accel, sets: &RaySets, sample: Option<usize>) -> Vec<Expected> {
    sets.sets
        .iter()
        .map(|(kind, rays)| {
            let indices = sample_indices(rays.len(), sample);
            let (hits, occluded) = if kind.is_shadow() {
                (Vec::new(), indices.par_iter().map(|&i| brute.occluded(&rays[i])).collect())
            } else {
                (indices.par_iter().map(|&i| brute.intersect(&rays[i])).collect(), Vec::new())
            };
            Expected { kind: *kind, indices, hits, occluded }
        })
        .collect()
}

/// Compares `q`'s answers (a structure, or the GPU backend: anything with the batch
/// queries) with the oracle's; every disagreement becomes a [`Mismatch`]. Returns the
/// rays checked.
pub fn verify<Q: BatchQuery + ?Sized>(
    q: &Q,
    label: &str,
    scene: &str,
    rays: &[Ray],
    exp: &Expected,
    out: &mut Vec<Mismatch>,
) -> usize {
    let mk = |i: usize, expected: String, got: String| {
        let r = rays[i];
        Mismatch {
            scene: scene.to_string(),
            accel: label.to_string(),
            kind: exp.kind.name().to_string(),
            ray_index: i,
            ray: [r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax],
            expected,
            got,
        }
    };
    let sample: Vec<Ray> = exp.indices.iter().map(|&i| rays[i]).collect();
    if exp.kind.is_shadow() {
        let got = q.occluded_batch(&sample);
        for ((&i, &want), &got) in exp.indices.iter().zip(&exp.occluded).zip(&got) {
            if got != want {
                out.push(mk(i, format!("occluded={want}"), format!("occluded={got}")));
            }
        }
    } else {
        let got = q.intersect_batch(&sample);
        for ((&i, want), got) in exp.indices.iter().zip(&exp.hits).zip(&got) {
            if !got.same_as(want) {
                out.push(mk(i, describe(want), describe(got)));
            }
        }
    }
    exp.indices.len()
}

fn describe(h: &Hit) -> String {
    if h.is_hit() {
        format!("prim {} t {:e} (bits {:#010x})", h.prim, h.t, h.t.to_bits())
    } else {
        "miss".to_string()
    }
}

/// Builds `v` once as a warm-up, then `repeat` more times; returns the last structure and
/// the timed builds in ms.
pub fn timed_builds(v: &AccelSpec, frame: &Frame, repeat: usize) -> Result<(Box<dyn Accel>, Vec<f64>)> {
    let (times, accel) = warm_then_timed(repeat, || Ok(v.build(&frame.mesh, Some(frame.camera.position))?))?;
    Ok((accel, times))
}

/// Runs `f` once untimed (the warm-up: first compilations, uploads, page faults), then
/// `repeat` times (at least once) by the wall clock, each run's predecessor dropped before
/// its timer starts; returns the timed runs' ms and the last result.
pub fn warm_then_timed<T>(repeat: usize, mut f: impl FnMut() -> Result<T>) -> Result<(Vec<f64>, T)> {
    let mut last = f()?;
    let mut times = Vec::with_capacity(repeat.max(1));
    for _ in 0..repeat.max(1) {
        drop(last);
        let t = Instant::now();
        last = f()?;
        times.push(ms(t));
    }
    Ok((times, last))
}

/// Milliseconds since `t`.
pub fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// One timed closest-hit or any-hit pass over `rays` through [`BatchQuery`], the trait
/// our structures and the competitors' adapters share, on the current rayon pool; returns
/// ms and the hit count. The answer buffer is allocated (and its pages touched) before the
/// timer starts and the hits are counted after it stops, so the time is the queries' alone.
pub fn timed_pass<Q: BatchQuery + ?Sized>(q: &Q, rays: &[Ray], shadow: bool) -> (f64, usize) {
    if shadow {
        let mut out = vec![false; rays.len()];
        let t = Instant::now();
        q.occluded_into(rays, &mut out);
        let elapsed = ms(t);
        (elapsed, black_box(out.iter().filter(|o| **o).count()))
    } else {
        let mut hits = vec![Hit::MISS; rays.len()];
        let t = Instant::now();
        q.intersect_into(rays, &mut hits);
        let elapsed = ms(t);
        (elapsed, black_box(hits.iter().filter(|h| h.is_hit()).count()))
    }
}

/// What a counted closest-hit pass found: per-ray work (nodes + triangles, for the heat
/// map), and the totals over every ray, over the rays that hit and over those that
/// escaped (seed 004's worst case is the escaping ray that walks many frustums).
pub struct CountedPass {
    /// Nodes + triangles of each ray.
    pub work: Vec<u32>,
    /// Every ray.
    pub total: TraversalCounts,
    /// The rays that hit, and how many they are.
    pub hit: (TraversalCounts, usize),
    /// The rays that escaped (no hit), and how many they are.
    pub escaped: (TraversalCounts, usize),
}

/// Counts the work of every ray through the closest-hit traversal.
pub fn counted_pass(accel: &dyn Accel, rays: &[Ray]) -> CountedPass {
    let per: Vec<(TraversalCounts, bool)> = rays
        .par_iter()
        .with_min_len(256)
        .map(|r| {
            let mut c = TraversalCounts::default();
            let hit = accel.intersect_counted(r, &mut c).is_hit();
            (c, hit)
        })
        .collect();
    let mut pass = CountedPass {
        work: per.iter().map(|(c, _)| (c.nodes + c.triangles).min(u32::MAX as u64) as u32).collect(),
        total: TraversalCounts::default(),
        hit: Default::default(),
        escaped: Default::default(),
    };
    for &(c, hit) in &per {
        pass.total += c;
        let side = if hit { &mut pass.hit } else { &mut pass.escaped };
        side.0 += c;
        side.1 += 1;
    }
    pass
}

/// What [`measure`] needs besides the structure.
pub struct MeasureInput<'a> {
    /// Scene name.
    pub scene: &'a str,
    /// The frame (mesh, camera, lights).
    pub frame: &'a Frame,
    /// The ray sets.
    pub sets: &'a RaySets,
    /// Brute force's answers (empty: do not verify, e.g. for brute itself).
    pub expected: &'a [Expected],
    /// Timed repetitions.
    pub repeat: usize,
    /// Render size.
    pub width: u32,
    /// Render height.
    pub height: u32,
    /// Measure the time to image (build + Whitted render); presets that only compare
    /// traversal skip it.
    pub time_to_image: bool,
}

/// Everything about one structure on one scene; per-pixel work of the primary rays is
/// returned for the heat map (when primary rays were measured).
pub fn measure(
    v: &AccelSpec,
    input: &MeasureInput<'_>,
    mismatches: &mut Vec<Mismatch>,
    step: &dyn Fn(&str),
) -> Result<(StructureResult, Option<Vec<u32>>)> {
    let label = v.to_string();
    step("build");
    let (accel, build_ms_runs) =
        timed_builds(v, input.frame, input.repeat).with_context(|| format!("{}: cannot build {label}", input.scene))?;
    let stats = accel.stats();
    let mut kinds = Vec::new();
    let mut heat = None;
    let mut primary_packets = None;
    for (kind, rays) in &input.sets.sets {
        step(kind.name());
        let (k, work) = measure_kind(accel.as_ref(), accel.as_ref(), &label, input, *kind, rays, mismatches);
        kinds.push(k);
        if *kind == RayKind::Primary {
            heat = Some(work);
            if accel.traces_packets() {
                // Right after the single rays, so both passes see the same machine load.
                step("primary (packets)");
                primary_packets = Some(measure_packets(accel.as_ref(), &label, input, rays, mismatches));
            }
        }
    }
    drop(accel);

    let (time_to_image_ms, render_ms, render_rays) =
        if input.time_to_image { time_to_image(v, input, step)? } else { (None, None, 0) };
    let result = StructureResult {
        accel: label,
        build_ms: median(&build_ms_runs),
        build_ms_runs,
        memory_bytes: stats.memory_bytes,
        nodes: stats.nodes,
        leaves: stats.leaves,
        max_depth: stats.max_depth,
        primitive_refs: stats.primitive_refs,
        sah_cost: stats.sah_cost,
        extra: stats.extra,
        kinds,
        primary_packets,
        time_to_image_ms,
        render_ms,
        render_rays,
        heatmap: None,
    };
    Ok((result, heat))
}

/// One ray kind through `q`: a warm-up pass then `repeat` timed passes (medians), the
/// work per ray counted on `counted_on` (the same tree, where `q` cannot count: the GPU
/// backend's tree read back), and the check against brute force. Returns the result and
/// each ray's work (nodes + triangles) for the heat map.
pub fn measure_kind<Q: BatchQuery + ?Sized>(
    q: &Q,
    counted_on: &dyn Accel,
    label: &str,
    input: &MeasureInput<'_>,
    kind: RayKind,
    rays: &[Ray],
    mismatches: &mut Vec<Mismatch>,
) -> (KindResult, Vec<u32>) {
    let shadow = kind.is_shadow();
    timed_pass(q, rays, shadow);
    let mut runs = Vec::with_capacity(input.repeat);
    let mut hits = 0;
    for _ in 0..input.repeat.max(1) {
        let (t, h) = timed_pass(q, rays, shadow);
        runs.push(t);
        hits = h;
    }
    // Shadow rays are counted through the closest-hit traversal: the trait has no
    // counted any-hit query, so their figures are an upper bound of `occluded`'s work.
    let counted = counted_pass(counted_on, rays);
    let n = rays.len().max(1) as f64;
    let per_ray = |(c, n): (TraversalCounts, usize)| {
        (n > 0).then(|| Work { nodes: c.nodes as f64 / n as f64, triangles: c.triangles as f64 / n as f64 })
    };
    let verified = input
        .expected
        .iter()
        .find(|e| e.kind == kind)
        .map(|e| verify(q, label, input.scene, rays, e, mismatches))
        .unwrap_or(0);
    let trace_ms = median(&runs);
    let result = KindResult {
        kind: kind.name().to_string(),
        rays: rays.len(),
        trace_ms,
        trace_ms_runs: runs,
        mrays_per_s: if trace_ms > 0.0 { rays.len() as f64 / trace_ms / 1e3 } else { 0.0 },
        nodes_per_ray: counted.total.nodes as f64 / n,
        triangles_per_ray: counted.total.triangles as f64 / n,
        hit_work: per_ray(counted.hit),
        escaped_work: per_ray(counted.escaped),
        hits,
        verified,
    };
    (result, counted.work)
}

/// The kind name of [`crate::results::StructureResult::primary_packets`].
pub const PRIMARY_PACKET: &str = "primary-packet";

/// The primary rays through `accel`'s packet path ([`Coherent`]), measured and checked
/// as [`measure_kind`] measures the single rays (mismatches labelled `LABEL (packets)`).
fn measure_packets(
    accel: &dyn Accel,
    label: &str,
    input: &MeasureInput<'_>,
    rays: &[Ray],
    mismatches: &mut Vec<Mismatch>,
) -> KindResult {
    let label = format!("{label} (packets)");
    let (mut k, _) = measure_kind(&Coherent(accel), accel, &label, input, RayKind::Primary, rays, mismatches);
    k.kind = PRIMARY_PACKET.to_string();
    k
}

/// Build + Whitted render at the bench size, `repeat` times: medians of the whole and of
/// the render alone, and the rays the render traced.
fn time_to_image(v: &AccelSpec, input: &MeasureInput<'_>, step: &dyn Fn(&str)) -> Result<TimeToImage> {
    step("render");
    let mut frame = input.frame.clone();
    frame.settings.width = input.width;
    frame.settings.height = input.height;
    let (mut tti, mut rend) = (Vec::new(), Vec::new());
    let mut render_rays = 0;
    for _ in 0..input.repeat.max(1) {
        let t = Instant::now();
        let accel = v.build(&frame.mesh, Some(frame.camera.position))?;
        let t_render = Instant::now();
        let (film, stats) = render(&frame, accel.as_ref(), &RenderOptions::default());
        black_box(film);
        rend.push(ms(t_render));
        tti.push(ms(t));
        render_rays = stats.total_rays();
    }
    Ok((Some(median(&tti)), Some(median(&rend)), render_rays))
}

/// Time to image, render alone (ms), rays rendered.
type TimeToImage = (Option<f64>, Option<f64>, u64);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_are_spread_and_capped() {
        assert_eq!(sample_indices(5, None), vec![0, 1, 2, 3, 4]);
        assert_eq!(sample_indices(5, Some(10)), vec![0, 1, 2, 3, 4]);
        assert_eq!(sample_indices(10, Some(3)), vec![0, 3, 6]);
    }
}
