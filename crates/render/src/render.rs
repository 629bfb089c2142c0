//! The render loop every integrator shares: camera rays per pixel sample, traced in
//! parallel over square image tiles with rayon, accumulated into a [`Film`].
//!
//! Each pixel is computed by one thread from its own samples alone (their positions and
//! random numbers depend on the pixel and sample index only, see [`Sampler`]) and tiles
//! are assembled in a fixed order, so the image does not depend on the number of
//! threads or on scheduling.

use crate::{Aov, AovIntegrator, CameraRays, Film, Integrator, IntegratorKind, RayCounts, Sampler, SceneIntersector};
use dynray_accel::Accel;
use dynray_scene::{Color, Frame};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

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
    /// Called after each finished tile with `(done_tiles, total_tiles)`, from worker
    /// threads, in completion order; `done_tiles` reaches `total_tiles` exactly once.
    pub progress: Option<&'a (dyn Fn(usize, usize) + Sync)>,
}

impl Default for RenderOptions<'_> {
    /// 16-pixel tiles, one sample per pixel centre, seed 0, Whitted, no progress.
    fn default() -> Self {
        Self { tile_size: 16, spp: 1, seed: 0, integrator: IntegratorKind::Whitted, progress: None }
    }
}

impl std::fmt::Debug for RenderOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RenderOptions")
            .field("tile_size", &self.tile_size)
            .field("spp", &self.spp)
            .field("seed", &self.seed)
            .field("integrator", &self.integrator)
            .field("progress", &self.progress.map(|_| "callback"))
            .finish()
    }
}

/// Rays traced by one render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Camera rays (one per pixel sample).
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
    let integrator = options.integrator.create(frame, &scene);
    render_with(frame, integrator.as_ref(), options)
}

/// Writes the AOV `aov` of `frame` (traced through `accel`, built on `frame.mesh`) into
/// a film: one sample through each pixel centre, whatever `options.spp` says.
pub fn render_aov(frame: &Frame, accel: &dyn Accel, aov: Aov, options: &RenderOptions<'_>) -> Film {
    let scene = SceneIntersector::triangles(frame, accel);
    render_with(frame, &AovIntegrator::new(aov, &scene), &RenderOptions { spp: 1, ..*options }).0
}

/// The render loop: `options.spp` samples per pixel of `frame`'s camera through
/// `integrator`, in parallel over tiles. Integrators over any geometry (a custom
/// [`SceneIntersector`]) render through here.
pub fn render_with(frame: &Frame, integrator: &dyn Integrator, options: &RenderOptions<'_>) -> (Film, RenderStats) {
    let (w, h) = (frame.settings.width, frame.settings.height);
    let mut film = Film::new(w, h);
    let ts = options.tile_size.max(1);
    let spp = options.spp.max(1);
    let (tx, ty) = (w.div_ceil(ts), h.div_ceil(ts));
    let total = tx as usize * ty as usize;
    let camera = CameraRays::new(&frame.camera, w, h);
    let done = AtomicUsize::new(0);

    let tiles: Vec<(Vec<Color>, RayCounts)> = (0..total)
        .into_par_iter()
        .map(|i| {
            let (x0, y0) = ((i as u32 % tx) * ts, (i as u32 / tx) * ts);
            let (x1, y1) = ((x0 + ts).min(w), (y0 + ts).min(h));
            let mut counts = RayCounts::default();
            let mut px = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
            for y in y0..y1 {
                for x in x0..x1 {
                    let mut sum = Color::ZERO;
                    for s in 0..spp {
                        let mut sampler = Sampler::new(options.seed, w, x, y, s, spp);
                        let (ox, oy) = sampler.pixel_offset();
                        let ray = camera.ray_at(x as f32 + ox, y as f32 + oy);
                        sum += integrator.radiance(&ray, &mut sampler, &mut counts);
                    }
                    px.push(sum);
                }
            }
            if let Some(report) = options.progress {
                report(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            }
            (px, counts)
        })
        .collect();

    let mut stats = RenderStats { primary_rays: w as u64 * h as u64 * spp as u64, tiles: total, ..Default::default() };
    for (i, (px, counts)) in tiles.into_iter().enumerate() {
        let (x0, y0) = ((i as u32 % tx) * ts, (i as u32 / tx) * ts);
        let tw = (x0 + ts).min(w) - x0;
        for (k, sum) in px.into_iter().enumerate() {
            film.add_sum(x0 + k as u32 % tw, y0 + k as u32 / tw, sum, spp as f32);
        }
        stats.shadow_rays += counts.shadow;
        stats.secondary_rays += counts.secondary;
    }
    (film, stats)
}
