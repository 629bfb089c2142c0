//! Rendering a frame: primary rays per pixel centre, traced in parallel over square
//! image tiles with rayon, written into a [`Film`].
//!
//! Each pixel is computed by one thread from its own ray alone and tiles are assembled in
//! a fixed order, so the image does not depend on the number of threads or on scheduling.

use crate::{CameraRays, Film, RayCounts, Whitted};
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
    /// Called after each finished tile with `(done_tiles, total_tiles)`, from worker
    /// threads, in completion order; `done_tiles` reaches `total_tiles` exactly once.
    pub progress: Option<&'a (dyn Fn(usize, usize) + Sync)>,
}

impl Default for RenderOptions<'_> {
    fn default() -> Self {
        Self { tile_size: 16, progress: None }
    }
}

impl std::fmt::Debug for RenderOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RenderOptions")
            .field("tile_size", &self.tile_size)
            .field("progress", &self.progress.map(|_| "callback"))
            .finish()
    }
}

/// Rays traced by one render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Camera rays (one per pixel).
    pub primary_rays: u64,
    /// Shadow rays.
    pub shadow_rays: u64,
    /// Reflection and refraction rays.
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

/// Renders `frame` (size, camera, recursion limits from its settings) through `accel`,
/// which must be built on `frame.mesh`. Runs on the current rayon pool.
pub fn render(frame: &Frame, accel: &dyn Accel, options: &RenderOptions<'_>) -> (Film, RenderStats) {
    let (w, h) = (frame.settings.width, frame.settings.height);
    let mut film = Film::new(w, h);
    let ts = options.tile_size.max(1);
    let (tx, ty) = (w.div_ceil(ts), h.div_ceil(ts));
    let total = tx as usize * ty as usize;
    let camera = CameraRays::new(&frame.camera, w, h);
    let tracer = Whitted::new(frame, accel);
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
                    px.push(tracer.trace(&camera.primary(x, y), 1, 1.0, &mut counts));
                }
            }
            if let Some(report) = options.progress {
                report(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            }
            (px, counts)
        })
        .collect();

    let mut stats = RenderStats { primary_rays: w as u64 * h as u64, tiles: total, ..Default::default() };
    for (i, (px, counts)) in tiles.into_iter().enumerate() {
        let (x0, y0) = ((i as u32 % tx) * ts, (i as u32 / tx) * ts);
        let tw = (x0 + ts).min(w) - x0;
        for (k, c) in px.into_iter().enumerate() {
            film.set(x0 + k as u32 % tw, y0 + k as u32 / tw, c);
        }
        stats.shadow_rays += counts.shadow;
        stats.secondary_rays += counts.secondary;
    }
    (film, stats)
}
