//! Traversal cost per pixel — nodes visited plus triangles tested by the ray through
//! each pixel centre, from the structure's own counters — and the value a colour scale
//! tops out at: the bench's heat maps (seed 004's Figure 6) and the viewer's live one.

use dynray_accel::{Accel, TraversalCounts};
use dynray_render::CameraRays;
use dynray_scene::Frame;
use rayon::prelude::*;

/// Nodes + triangles of the primary ray of every pixel of `frame` (its camera and size)
/// through `accel`, row-major from the top-left, on the current rayon pool.
pub fn work_map(frame: &Frame, accel: &dyn Accel) -> Vec<u32> {
    let (w, h) = (frame.settings.width, frame.settings.height);
    let camera = CameraRays::new(&frame.camera, w, h);
    (0..w as usize * h as usize)
        .into_par_iter()
        .with_min_len(256)
        .map(|i| {
            let mut c = TraversalCounts::default();
            accel.intersect_counted(&camera.primary(i as u32 % w, i as u32 / w), &mut c);
            (c.nodes + c.triangles).min(u32::MAX as u64) as u32
        })
        .collect()
}

/// The value the colour scale tops out at: the 99.5th percentile, so a handful of
/// pathological rays does not wash out the rest (pixels above it take the top colour).
pub fn scale_max(work: &[u32]) -> u32 {
    if work.is_empty() {
        return 1;
    }
    let mut s = work.to_vec();
    s.sort_unstable();
    s[((s.len() - 1) as f64 * 0.995) as usize].max(1)
}
