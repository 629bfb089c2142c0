//! Sphere tracing of the reconstructed field (`geometry.rs` puts it in a scene).
//!
//! A ray is clipped to the cube, then marched by `|d| / L` (a Lipschitz bound of the
//! field, `crack.rs`: no surface lies nearer than that) — `L` the bound of the smallest
//! cell the step stays in, so that a steep spot (the cap the sign vote puts over a
//! mesh's hole) slows only the rays near it — but at least `MIN_STEP` of a finest
//! cell, until the field changes sign relative to where the ray started; the crossing
//! is then refined by bisection to float precision. Where a ray starts on the surface
//! (a shadow or reflection ray leaves a hit offset by a hair) the side it starts on is
//! the side it moves to, by the gradient, so it does not re-hit its own surface. The
//! minimum step can step over a feature thinner than itself (a tenth of a finest cell,
//! below what the samples resolve); a ray still marching after [`MAX_MARCH_STEPS`] is a
//! miss.

use crate::crack::leaf_gradient_bound;
use crate::{Adf, Located, Search};
use dynray_geom::{PreparedRay, Ray, Vec3};

/// Steps a ray may take through the cube before it counts as a miss.
pub const MAX_MARCH_STEPS: u32 = 4096;
/// The smallest step, in finest cells.
const MIN_STEP: f32 = 0.1;
/// Bisection steps refining a crossing (each halves the interval).
const REFINE_STEPS: u32 = 24;

/// What one march found and what it cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarchStats {
    /// `t` of the first crossing, `None` for a miss.
    pub t: Option<f32>,
    /// Field samples taken (steps and bisection).
    pub samples: u32,
    /// Hash probes point location made for those samples (the level search's cost).
    pub probes: u32,
}

impl Adf {
    /// The first crossing of the surface along `ray` within `[tmin, tmax]`: its `t`.
    pub fn march(&self, ray: &Ray) -> Option<f32> {
        self.march_with(ray, Search::CoherentLinear).t
    }

    /// [`Adf::march`] and the field samples it took.
    pub fn march_counted(&self, ray: &Ray) -> (Option<f32>, u32) {
        let s = self.march_with(ray, Search::CoherentLinear);
        (s.t, s.samples)
    }

    /// [`Adf::march`] locating every sample with `search` (all three find the same cells,
    /// so the answer is the same; the probes are not).
    pub fn march_with(&self, ray: &Ray, search: Search) -> MarchStats {
        let mut stats = MarchStats { t: None, samples: 0, probes: 0 };
        let Some((t0, t1)) = self.cube.bounds().clip(&PreparedRay::new(ray), ray.tmin, ray.tmax) else {
            return stats;
        };
        let dl = ray.dir.length();
        if !(dl > 0.0 && dl.is_finite()) {
            return stats;
        }
        let finest = self.cube.size / (1u32 << self.max_level) as f32;
        let min_step = MIN_STEP * finest / dl;
        let du = ray.dir / self.cube.size;
        let mut hint = 0;
        let sample = |t: f32, hint: &mut u32, stats: &mut MarchStats| {
            let s = self.sample_unit(self.unit(ray.at(t)), search, hint);
            stats.samples += 1;
            stats.probes += s.1.probes;
            s
        };
        let mut t = t0.max(ray.tmin);
        let (mut d, mut cell, mut q) = sample(t, &mut hint, &mut stats);
        // The side the ray is on: by the field, or for a start on the surface by where it
        // heads (away from it along the gradient: outside).
        let outside = if d.abs() > 1e-3 * finest {
            d > 0.0
        } else {
            let mut h = 0;
            self.gradient(ray.at(t), &mut h).dot(ray.dir) >= 0.0
        };
        let crossed = |d: f32| if outside { d <= 0.0 } else { d >= 0.0 };
        for _ in 0..MAX_MARCH_STEPS {
            let u = self.unit(ray.at(t));
            let step = self.safe_step(u, du, d.abs() / dl, cell, q).max(min_step);
            let tn = (t + step).min(t1);
            let (dn, cn, qn) = sample(tn, &mut hint, &mut stats);
            if crossed(dn) {
                let (mut lo, mut hi) = (t, tn);
                for _ in 0..REFINE_STEPS {
                    let mid = 0.5 * (lo + hi);
                    if crossed(sample(mid, &mut hint, &mut stats).0) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                stats.t = Some(hi);
                return stats;
            }
            if tn >= t1 {
                return stats;
            }
            (t, d, cell, q) = (tn, dn, cn, qn);
        }
        stats
    }

    /// How far (in ray parameter) a ray at unit point `u`, moving `du` per unit of `t`,
    /// can go without crossing the surface, where the field is `reach` (`|d| / |dir|`):
    /// inside any cell with Lipschitz bound `L`, `reach / L` — but only as far as the ray
    /// stays in that cell. The leaf's own bound is tried first, then each enclosing cell,
    /// up to the root (the global bound); the longest safe step wins, and the search stops
    /// at the first cell the step does not leave.
    fn safe_step(&self, u: Vec3, du: Vec3, reach: f32, cell: Located, q: [u32; 3]) -> f32 {
        let exit = |level: u32| {
            let h = 1.0 / (1u32 << level) as f32;
            let idx = q.map(|c| (c >> (self.max_level - level)) as f32);
            (0..3)
                .map(|k| match du[k] {
                    x if x > 0.0 => ((idx[k] + 1.0) * h - u[k]) / x,
                    x if x < 0.0 => (idx[k] * h - u[k]) / x,
                    _ => f32::INFINITY,
                })
                .fold(f32::INFINITY, f32::min)
                .max(0.0)
        };
        let mut best = 0.0f32;
        let mut consider = |bound: f32, level: u32| {
            let free = if bound > 0.0 { reach / bound } else { f32::INFINITY };
            let e = exit(level);
            best = best.max(free.min(e));
            free <= e
        };
        let leaf_edge = self.cube.size / (1u32 << (cell.level + 1)) as f32;
        if consider(leaf_gradient_bound(&self.leaf_corners(cell, q), leaf_edge), cell.level + 1) {
            return best;
        }
        for level in (0..=cell.level).rev() {
            let block = if level == cell.level { Some(cell.block) } else { self.probe(level, q) };
            let bound = block.and_then(|b| self.cell_lipschitz.get(b as usize)).copied().unwrap_or(self.lipschitz);
            if consider(bound, level) {
                break;
            }
        }
        best
    }
}
