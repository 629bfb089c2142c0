//! The render loop every integrator shares: camera rays per pixel sample, traced in
//! parallel over square image tiles with rayon, accumulated into a [`Film`].
//!
//! Each pixel is computed by one thread from its own samples alone (their positions and
//! random numbers depend on the pixel and sample index only, see [`Sampler`]) and tiles
//! are assembled in a fixed order, so the image does not depend on the number of
//! threads or on scheduling.
//!
//! A tile's samples go to the integrator in batches ([`Integrator::radiance_batch`]) of
//! at most [`BATCH_RAYS`] camera rays, whole pixels at a time, and each pixel's samples
//! are summed in sample order whatever the batch, so an integrator that answers one ray
//! at a time gives exactly the image it gave before batches existed.
//!
//! Passes ([`RenderOptions::passes`]): the image is rendered `passes` times over, each
//! pass adding `spp` samples per pixel into the same film (progressive refinement; the
//! film after pass `p` is a complete image of `p · spp` samples). Every pass re-uses the
//! same sub-pixel positions (the `spp`-sample pattern) with fresh random streams (sample
//! indices `p · spp .. (p + 1) · spp`), so the passes of a deterministic camera converge
//! to the image the same `spp` gives with an integrator that draws no random numbers
//! (Whitted's), which is what the cumulative integrator's passes are for.
//!
//! Progressive frames (the live viewer): a render of `spp: 1` with
//! [`RenderOptions::pattern`] `Some(n)` and [`RenderOptions::first_sample`] `k` draws
//! exactly sample `k` of each pixel of an `spp: n` render. Added into one film with
//! [`Film::add_film`] for `k = 0, 1, …, n − 1`, the film holds the same sums, summed in
//! the same order, as the `spp: n` render's, so it resolves to the same bits; frames
//! `n .. 2n` then add the samples of the second pass of `passes: 2`, and so on (one at a
//! time where a pass adds their sum, so those films agree to rounding).

use crate::{
    Aov, AovIntegrator, CameraRays, Film, Integrator, IntegratorKind, IntegratorParams, RayCounts, Sampler,
    SceneIntersector,
};
use dynray_accel::Accel;
use dynray_scene::{Color, Frame};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// What [`RenderOptions::pass_done`] calls: `(pass number from 1, film so far)`.
pub type PassCallback<'a> = dyn Fn(u32, &Film) + Sync + 'a;

/// How to render (what the frame's settings do not say).
#[derive(Clone, Copy)]
pub struct RenderOptions<'a> {
    /// Edge of the square tiles handed to threads, in pixels (clamped to at least 1).
    /// 16 keeps a tile's rays coherent and gives thousands of tiles to balance.
    pub tile_size: u32,
    /// Samples per pixel (clamped to at least 1). One sample is the ray through the
    /// pixel centre, exactly as the seeds measured; more are correlated multi-jittered
    /// over the pixel and box-filtered (averaged).
    pub spp: u32,
    /// Seed of every random number of the image (sample positions, integrator draws).
    pub seed: u64,
    /// Which integrator [`render`] uses.
    pub integrator: IntegratorKind,
    /// Settings of that integrator beyond the frame's (the cumulative branch depth).
    pub params: IntegratorParams,
    /// Sample passes accumulated into the film, `spp` samples per pixel each (clamped
    /// to at least 1; module docs): `passes · spp` samples per pixel in all.
    pub passes: u32,
    /// Called after each finished tile with `(done_tiles, total_tiles)` (tiles of every
    /// pass), from worker threads, in completion order; `done_tiles` reaches
    /// `total_tiles` exactly once.
    pub progress: Option<&'a (dyn Fn(usize, usize) + Sync)>,
    /// Called after each pass with its number (1 = the first) and the film so far, on
    /// the calling thread: the progressive image.
    pub pass_done: Option<&'a PassCallback<'a>>,
    /// Index of the first sample this render draws: sample `s` of pass `p` is sample
    /// `first_sample + p · spp + s` of its pixel (its sub-pixel position and random
    /// streams). 0 for a whole image; a progressive front end that draws one sample per
    /// frame passes the frame's number (module docs, "Progressive frames").
    pub first_sample: u32,
    /// The sub-pixel pattern's sample count; `None`: `spp`. Sample `i` lies at position
    /// `i mod pattern` of the `pattern`-sample pattern, so renders of one sample each
    /// with `pattern: Some(n)` and `first_sample` 0, 1, … draw exactly the samples of one
    /// `spp: n` render (module docs, "Progressive frames").
    pub pattern: Option<u32>,
}

impl Default for RenderOptions<'_> {
    /// 16-pixel tiles, one sample per pixel centre, one pass, seed 0, Whitted, no
    /// callbacks.
    fn default() -> Self {
        Self {
            tile_size: 16,
            spp: 1,
            seed: 0,
            integrator: IntegratorKind::Whitted,
            params: IntegratorParams::default(),
            passes: 1,
            progress: None,
            pass_done: None,
            first_sample: 0,
            pattern: None,
        }
    }
}

impl std::fmt::Debug for RenderOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RenderOptions")
            .field("tile_size", &self.tile_size)
            .field("spp", &self.spp)
            .field("seed", &self.seed)
            .field("integrator", &self.integrator)
            .field("params", &self.params)
            .field("passes", &self.passes)
            .field("progress", &self.progress.map(|_| "callback"))
            .field("pass_done", &self.pass_done.map(|_| "callback"))
            .field("first_sample", &self.first_sample)
            .field("pattern", &self.pattern)
            .finish()
    }
}

/// Rays traced by one render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Camera rays (one per pixel sample of every pass).
    pub primary_rays: u64,
    /// Shadow rays.
    pub shadow_rays: u64,
    /// Reflection, refraction and other continuation rays.
    pub secondary_rays: u64,
    /// Tiles rendered.
    pub tiles: usize,
}

impl RenderStats {
    /// Every ray sent to the acceleration structure: primary, shadow and secondary.
    pub fn total_rays(&self) -> u64 {
        self.primary_rays + self.shadow_rays + self.secondary_rays
    }
}

/// Renders `frame` (size, camera, recursion limits from its settings) with
/// `options.integrator` over the frame's triangles traced through `accel`, which must be
/// built on `frame.mesh`. Runs on the current rayon pool.
pub fn render(frame: &Frame, accel: &dyn Accel, options: &RenderOptions<'_>) -> (Film, RenderStats) {
    let scene = SceneIntersector::triangles(frame, accel);
    let integrator = options.integrator.create(frame, &scene, &options.params);
    render_with(frame, integrator.as_ref(), options)
}

/// Writes the AOV `aov` of `frame` (traced through `accel`, built on `frame.mesh`) into
/// a film: one sample through each pixel centre, whatever `options.spp` says.
pub fn render_aov(frame: &Frame, accel: &dyn Accel, aov: Aov, options: &RenderOptions<'_>) -> Film {
    let scene = SceneIntersector::triangles(frame, accel);
    render_with(frame, &AovIntegrator::new(aov, &scene), &RenderOptions { spp: 1, passes: 1, ..*options }).0
}

/// Most camera rays handed to [`Integrator::radiance_batch`] at once: a 16-pixel tile
/// with 16 samples per pixel. Bounds a wavefront integrator's per-thread buffers at any
/// `spp`; a tile with more samples is handed over in several batches.
pub const BATCH_RAYS: usize = 4096;

/// The render loop: `options.passes` passes of `options.spp` samples per pixel of
/// `frame`'s camera through `integrator`, in parallel over tiles. Integrators over any
/// geometry (a custom [`SceneIntersector`]) render through here.
pub fn render_with(frame: &Frame, integrator: &dyn Integrator, options: &RenderOptions<'_>) -> (Film, RenderStats) {
    let (w, h) = (frame.settings.width, frame.settings.height);
    let mut film = Film::new(w, h);
    let ts = options.tile_size.max(1);
    let spp = options.spp.max(1);
    let passes = options.passes.max(1);
    let (tx, ty) = (w.div_ceil(ts), h.div_ceil(ts));
    let tiles_per_pass = tx as usize * ty as usize;
    let total = tiles_per_pass * passes as usize;
    let camera = CameraRays::new(&frame.camera, w, h);
    let done = AtomicUsize::new(0);
    let mut stats = RenderStats {
        primary_rays: w as u64 * h as u64 * spp as u64 * passes as u64,
        tiles: tiles_per_pass,
        ..Default::default()
    };

    for pass in 0..passes {
        let job = TileJob {
            camera: &camera,
            integrator,
            seed: options.seed,
            width: w,
            spp,
            pattern: options.pattern.unwrap_or(spp).max(1),
            first_sample: options.first_sample.wrapping_add(pass * spp),
        };
        let tiles: Vec<(Vec<Color>, RayCounts)> = (0..tiles_per_pass)
            .into_par_iter()
            .map(|i| {
                let (x0, y0) = ((i as u32 % tx) * ts, (i as u32 / tx) * ts);
                let out = job.render((x0, y0), ((x0 + ts).min(w), (y0 + ts).min(h)));
                if let Some(report) = options.progress {
                    report(done.fetch_add(1, Ordering::Relaxed) + 1, total);
                }
                out
            })
            .collect();
        for (i, (px, counts)) in tiles.into_iter().enumerate() {
            let (x0, y0) = ((i as u32 % tx) * ts, (i as u32 / tx) * ts);
            let tw = (x0 + ts).min(w) - x0;
            for (k, sum) in px.into_iter().enumerate() {
                film.add_sum(x0 + k as u32 % tw, y0 + k as u32 / tw, sum, spp as f32);
            }
            stats.shadow_rays += counts.shadow;
            stats.secondary_rays += counts.secondary;
        }
        if let Some(report) = options.pass_done {
            report(pass + 1, &film);
        }
    }
    (film, stats)
}

/// One pass's work on a tile: what every tile of the pass shares.
struct TileJob<'a> {
    camera: &'a CameraRays,
    integrator: &'a dyn Integrator,
    seed: u64,
    width: u32,
    spp: u32,
    /// The sub-pixel pattern's sample count ([`RenderOptions::pattern`]).
    pattern: u32,
    /// Index of the pass's first sample (`first_sample + pass · spp`): its samplers'
    /// streams and pattern positions.
    first_sample: u32,
}

impl TileJob<'_> {
    /// Per pixel of the tile `[x0, x1) × [y0, y1)` (row-major), the sum of its `spp`
    /// samples in sample order, and the rays traced besides the camera rays.
    fn render(&self, (x0, y0): (u32, u32), (x1, y1): (u32, u32)) -> (Vec<Color>, RayCounts) {
        let pixels: Vec<(u32, u32)> = (y0..y1).flat_map(|y| (x0..x1).map(move |x| (x, y))).collect();
        let mut sums = vec![Color::ZERO; pixels.len()];
        let mut counts = RayCounts::default();
        // Whole pixels per batch when they fit, else a pixel's samples in several.
        let per_batch = (BATCH_RAYS / self.spp as usize).max(1);
        let chunk = (self.spp as usize).min(BATCH_RAYS) as u32;
        let (mut rays, mut samplers, mut out) = (Vec::new(), Vec::new(), Vec::new());
        for (group, sums) in pixels.chunks(per_batch).zip(sums.chunks_mut(per_batch)) {
            let mut s0 = 0;
            while s0 < self.spp {
                let s1 = (s0 + chunk).min(self.spp);
                rays.clear();
                samplers.clear();
                for &(x, y) in group {
                    for s in s0..s1 {
                        let sampler =
                            Sampler::new(self.seed, self.width, x, y, self.first_sample.wrapping_add(s), self.pattern);
                        let (ox, oy) = sampler.pixel_offset();
                        rays.push(self.camera.ray_at(x as f32 + ox, y as f32 + oy));
                        samplers.push(sampler);
                    }
                }
                out.clear();
                out.resize(rays.len(), Color::ZERO);
                self.integrator.radiance_batch(&rays, &mut samplers, &mut out, &mut counts);
                let n = (s1 - s0) as usize;
                for (sum, samples) in sums.iter_mut().zip(out.chunks(n)) {
                    for c in samples {
                        *sum += *c;
                    }
                }
                s0 = s1;
            }
        }
        (sums, counts)
    }
}
