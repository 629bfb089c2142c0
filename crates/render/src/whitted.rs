//! The Whitted integrator of seed 003 §3.7: ambient + per-light Lambert/Phong with one
//! shadow ray each, mirror reflection and Snell refraction, recursion bounded by level
//! and weight.
//!
//! The shading at a hit (local term, children, weight rule) and the decisions it makes
//! where the seed is silent are in `shading.rs`, shared with the cumulative integrator;
//! this file is the recursion: a hit's radiance is its local term plus each child's
//! coefficient times the child's radiance, traced depth first. Each ray carries its
//! footprint ([`RayCone`]: a pixel for camera rays, continued through mirrors and glass),
//! which filters the textures it sees.

use crate::shading::{no_nan, Child, Surface, WhittedShading};
use crate::{Integrator, RayCone, RayCounts, Sampler, SceneIntersector};
use dynray_geom::Ray;
use dynray_scene::{Color, Frame};

/// A Whitted ray tracer over one frame's lights, settings and environment, tracing
/// through the frame's scene intersector.
pub struct Whitted<'a> {
    shading: WhittedShading<'a>,
}

impl<'a> Whitted<'a> {
    /// An integrator for `frame` (lights, settings, environment) whose rays go through
    /// `scene`, the intersector over the frame's geometry.
    pub fn new(frame: &'a Frame, scene: &'a SceneIntersector<'a>) -> Self {
        Self { shading: WhittedShading::new(frame, scene) }
    }

    /// Radiance arriving along `ray` (unit direction expected, any length works) for a
    /// ray of the given `level` (primary = 1) and `weight` (primary = 1), with textures
    /// looked up at a point ([`Integrator::radiance`] gives camera rays their pixel's
    /// footprint instead). Never NaN.
    pub fn trace(&self, ray: &Ray, level: u32, weight: f32, counts: &mut RayCounts) -> Color {
        self.trace_cone(ray, &RayCone::POINT, level, weight, counts)
    }

    /// [`Self::trace`] of a ray whose footprint is `cone`.
    fn trace_cone(&self, ray: &Ray, cone: &RayCone, level: u32, weight: f32, counts: &mut RayCounts) -> Color {
        self.trace_from(ray, cone, self.shading.intersect(ray, cone), level, weight, counts)
    }

    /// [`Self::trace_cone`] of `ray` whose closest hit `hit` is already known.
    fn trace_from(
        &self,
        ray: &Ray,
        cone: &RayCone,
        hit: Option<Surface<'_>>,
        level: u32,
        weight: f32,
        counts: &mut RayCounts,
    ) -> Color {
        let c = match hit {
            Some(s) => self.shade(ray, cone, &s, level, weight, counts),
            None => self.shading.background(),
        };
        // A NaN would spread through every parent ray; stop it here.
        no_nan(c)
    }

    fn shade(
        &self,
        ray: &Ray,
        cone: &RayCone,
        s: &Surface<'_>,
        level: u32,
        weight: f32,
        counts: &mut RayCounts,
    ) -> Color {
        let d = ray.dir.normalize_or_zero();
        let eps = self.shading.eps(s.hit.p);
        let mut c = self.shading.local(d, s, eps, counts);
        if level >= self.shading.max_level {
            return c;
        }
        let scatter = self.shading.scatter(d, s);
        // Children go on from the footprint the cone reached at the hit.
        let cone = cone.advance(s.hit.t * ray.dir.length());
        for child in [scatter.reflect, scatter.refract].into_iter().flatten() {
            c += self.spawn(s, &cone, &child, eps, level, weight, counts);
        }
        c
    }

    /// Traces `child` of the surface (its footprint `cone`) when its weight is above the
    /// threshold, and returns its coefficient-weighted radiance.
    #[allow(clippy::too_many_arguments)]
    fn spawn(
        &self,
        s: &Surface<'_>,
        cone: &RayCone,
        child: &Child,
        eps: f32,
        level: u32,
        weight: f32,
        counts: &mut RayCounts,
    ) -> Color {
        let Some(w) = self.shading.child_weight(weight, child) else {
            return Color::ZERO;
        };
        counts.secondary += 1;
        child.coef * self.trace_cone(&self.shading.child_ray(s, child.dir, eps), cone, level + 1, w, counts)
    }
}

impl Integrator for Whitted<'_> {
    fn name(&self) -> &'static str {
        "whitted"
    }

    /// Deterministic: Whitted draws no random numbers; the sampler only says how many
    /// samples share the pixel, which sizes the camera ray's footprint (its sub-pixel
    /// position has already placed the ray).
    fn radiance(&self, ray: &Ray, sampler: &mut Sampler, counts: &mut RayCounts) -> Color {
        self.trace_cone(ray, &self.shading.camera_cone(sampler), 1, 1.0, counts)
    }

    /// The batch's camera rays are intersected together, through the scene's coherent
    /// path (8-ray packets where the structure has them, bit-identical hits), then each
    /// sample is shaded as [`Integrator::radiance`] shades it: the same image.
    fn radiance_batch(&self, rays: &[Ray], samplers: &mut [Sampler], out: &mut [Color], counts: &mut RayCounts) {
        debug_assert!(rays.len() == out.len() && rays.len() == samplers.len(), "batch slices differ in length");
        let cones: Vec<RayCone> = samplers.iter().map(|s| self.shading.camera_cone(s)).collect();
        let hits = self.shading.intersect_coherent(rays, &cones);
        for (((ray, cone), hit), o) in rays.iter().zip(&cones).zip(hits).zip(out.iter_mut()) {
            *o = self.trace_from(ray, cone, hit, 1, 1.0, counts);
        }
    }
}
