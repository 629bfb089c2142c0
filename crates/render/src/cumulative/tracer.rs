//! The cumulative integrator: batches of camera rays traced as a wavefront of bounce
//! passes (module docs of `cumulative`).

use super::bounce::Bounce;
use super::paths::Paths;
use crate::shading::WhittedShading;
use crate::{Integrator, RayCone, RayCounts, Sampler, SceneIntersector};
use dynray_geom::Ray;
use dynray_scene::{Color, Frame};

/// Default `--branch-depth`: the first two bounces expanded (a glass object's entry and
/// exit, or a mirror seen in glass), the seed's "first bounces", choices after them.
pub const DEFAULT_BRANCH_DEPTH: u32 = 2;

/// Most live paths one wavefront holds: a batch whose paths could outgrow it (every
/// expanded bounce can double them) is traced in slices of fewer camera rays, which
/// changes no result (samples are independent). 2^16 paths are about 4 MB per thread.
pub const MAX_LIVE_PATHS: usize = 1 << 16;

/// Seed 004's cumulative tracer over one frame (Whitted's shading, no recursion).
pub struct Cumulative<'a> {
    shading: WhittedShading<'a>,
    branch_depth: u32,
}

impl<'a> Cumulative<'a> {
    /// An integrator for `frame` whose rays go through `scene`, expanding every
    /// reflection/refraction pair at the hits of the first `branch_depth` ray levels.
    pub fn new(frame: &'a Frame, scene: &'a SceneIntersector<'a>, branch_depth: u32) -> Self {
        Self { shading: WhittedShading::new(frame, scene), branch_depth }
    }

    /// The branch depth `K`.
    pub fn branch_depth(&self) -> u32 {
        self.branch_depth
    }

    /// Camera rays per wavefront so that the live list stays within [`MAX_LIVE_PATHS`]:
    /// a camera ray has at most `2^min(K, max_level − 1)` live paths in any pass.
    fn slice_len(&self) -> usize {
        let doublings = self.branch_depth.min(self.shading.max_level.saturating_sub(1)).min(16);
        (MAX_LIVE_PATHS >> doublings).max(1)
    }

    /// The wavefront over one slice of camera rays: `sums[i]` is sample `i`'s `S`.
    fn wavefront(
        &self,
        rays: &[Ray],
        samplers: &mut [Sampler],
        sums: &mut [Color],
        lists: &mut (Paths, Paths),
        counts: &mut RayCounts,
    ) {
        sums.fill(Color::ZERO);
        // One draw per sample keys all its choices (the GPU uploads the same numbers).
        let keys: Vec<u32> = samplers.iter_mut().map(Sampler::next_u32).collect();
        let cones: Vec<RayCone> = samplers.iter().map(|s| self.shading.camera_cone(s)).collect();
        let (live, next) = lists;
        live.camera(rays, &cones);
        let mut level = 1;
        while !live.is_empty() {
            next.clear();
            let pass = Bounce { shading: &self.shading, level, expand: level <= self.branch_depth };
            pass.run(live, next, sums, &keys, counts);
            std::mem::swap(live, next);
            level += 1;
        }
    }
}

impl Integrator for Cumulative<'_> {
    fn name(&self) -> &'static str {
        "cumulative"
    }

    /// A batch of one: the same paths and draws as within any batch.
    fn radiance(&self, ray: &Ray, sampler: &mut Sampler, counts: &mut RayCounts) -> Color {
        let mut out = [Color::ZERO];
        self.radiance_batch(std::slice::from_ref(ray), std::slice::from_mut(sampler), &mut out, counts);
        out[0]
    }

    fn radiance_batch(&self, rays: &[Ray], samplers: &mut [Sampler], out: &mut [Color], counts: &mut RayCounts) {
        assert!(
            rays.len() == samplers.len() && rays.len() == out.len(),
            "batch of {} rays, {} samplers, {} outputs",
            rays.len(),
            samplers.len(),
            out.len()
        );
        let n = self.slice_len();
        let mut lists = (Paths::with_capacity(n.min(rays.len())), Paths::with_capacity(n.min(rays.len())));
        for ((r, s), o) in rays.chunks(n).zip(samplers.chunks_mut(n)).zip(out.chunks_mut(n)) {
            self.wavefront(r, s, o, &mut lists, counts);
        }
    }
}
