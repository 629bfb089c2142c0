//! The integrator seam: what computes a pixel sample's radiance from its camera ray.
//!
//! The render loop ([`crate::render_with`]) owns the tiles, the samples, progress,
//! statistics and thread-count independence; an integrator only answers "how much light
//! arrives along this ray", drawing any random numbers it needs from the sample's
//! [`Sampler`] so that its answer depends on nothing but the pixel and the sample index.
//!
//! The render loop hands an integrator a batch of camera rays at a time (one tile's
//! samples, [`Integrator::radiance_batch`]); the default answers them one by one through
//! [`Integrator::radiance`], and a wavefront integrator ([`crate::Cumulative`]) overrides
//! it to trace the whole batch one bounce at a time, as a GPU kernel would.

use crate::{Cumulative, PathTracer, Sampler, SceneIntersector, Whitted, DEFAULT_BRANCH_DEPTH};
use dynray_geom::Ray;
use dynray_scene::{Color, Frame};

/// Rays an integrator traced besides the camera rays, counted per tile and summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Shadow (occlusion) rays.
    pub shadow: u64,
    /// Reflection, refraction and other continuation rays.
    pub secondary: u64,
}

/// Computes the radiance of one pixel sample.
pub trait Integrator: Sync {
    /// Short name, as `--integrator` spells it.
    fn name(&self) -> &'static str;

    /// Radiance arriving along the camera ray `ray` of one pixel sample. Random numbers
    /// come from `sampler` only; rays traced besides `ray` are counted in `counts`.
    /// Never NaN.
    fn radiance(&self, ray: &Ray, sampler: &mut Sampler, counts: &mut RayCounts) -> Color;

    /// Radiance of a batch of camera rays: `out[i]` for `rays[i]`, drawing from
    /// `samplers[i]` only, so each answer is the one [`Self::radiance`] would give
    /// (exactly, for the default; in distribution, for an integrator that draws its
    /// numbers in another order). The three slices have the same length. The default
    /// calls [`Self::radiance`] on each ray in order.
    fn radiance_batch(&self, rays: &[Ray], samplers: &mut [Sampler], out: &mut [Color], counts: &mut RayCounts) {
        debug_assert!(rays.len() == samplers.len() && rays.len() == out.len(), "batch slices differ in length");
        for ((ray, sampler), o) in rays.iter().zip(samplers.iter_mut()).zip(out.iter_mut()) {
            *o = self.radiance(ray, sampler, counts);
        }
    }
}

/// Integrator settings the frame does not carry (command-line flags).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IntegratorParams {
    /// [`Cumulative`]: bounces whose reflection/refraction pairs are all expanded before
    /// paths start choosing one child at random ([`DEFAULT_BRANCH_DEPTH`]).
    pub branch_depth: u32,
}

impl Default for IntegratorParams {
    fn default() -> Self {
        Self { branch_depth: DEFAULT_BRANCH_DEPTH }
    }
}

/// Every integrator the engine offers, by the name `--integrator` accepts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum IntegratorKind {
    /// [`Whitted`]: seed 003's recursive ray tracer (Phong, shadows, mirrors, glass).
    #[default]
    Whitted,
    /// [`PathTracer`]: unidirectional path tracing with next-event estimation and MIS,
    /// converging to Mitsuba 3's `path` integrator.
    Path,
    /// [`Cumulative`]: seed 004's non-recursive form of Whitted's tracer (running product
    /// and sum per path, one wavefront pass per bounce, a Fresnel choice past the
    /// branch depth), whose expected image is Whitted's.
    Cumulative,
}

impl IntegratorKind {
    /// All kinds, in the order listings show them.
    pub const ALL: &'static [IntegratorKind] =
        &[IntegratorKind::Whitted, IntegratorKind::Path, IntegratorKind::Cumulative];

    /// The names of [`Self::ALL`], for command-line value lists.
    pub const NAMES: &'static [&'static str] = &["whitted", "path", "cumulative"];

    /// The `--integrator` spelling.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Whitted => "whitted",
            IntegratorKind::Path => "path",
            IntegratorKind::Cumulative => "cumulative",
        }
    }

    /// The integrator for `frame`, tracing through `scene` (the intersector over that
    /// frame's geometry), with `params` where it takes any.
    pub fn create<'a>(
        self,
        frame: &'a Frame,
        scene: &'a SceneIntersector<'a>,
        params: &IntegratorParams,
    ) -> Box<dyn Integrator + 'a> {
        match self {
            IntegratorKind::Whitted => Box::new(Whitted::new(frame, scene)),
            IntegratorKind::Path => Box::new(PathTracer::new(frame, scene)),
            IntegratorKind::Cumulative => Box::new(Cumulative::new(frame, scene, params.branch_depth)),
        }
    }
}

impl std::str::FromStr for IntegratorKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        IntegratorKind::ALL
            .iter()
            .copied()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("unknown integrator `{s}` (expected one of: {})", IntegratorKind::NAMES.join(", ")))
    }
}

impl std::fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_list_every_kind() {
        assert_eq!(IntegratorKind::ALL.len(), IntegratorKind::NAMES.len());
        for (k, n) in IntegratorKind::ALL.iter().zip(IntegratorKind::NAMES) {
            assert_eq!(k.name(), *n);
            assert_eq!(n.parse::<IntegratorKind>(), Ok(*k));
        }
        assert!("path-tracer".parse::<IntegratorKind>().unwrap_err().contains("whitted"));
    }
}
