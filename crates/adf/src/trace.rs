//! Sphere tracing of the reconstructed field, and the field as a geometry of the
//! scene-level intersector (so every integrator and AOV shades it).
//!
//! A ray is clipped to the cube, then marched by `|d| / L` (the field's Lipschitz bound,
//! `crack.rs`: no surface lies nearer than that), but at least [`MIN_STEP`] of a finest
//! cell, until the field changes sign relative to where the ray started; the crossing
//! is then refined by bisection to float precision. Where a ray starts on the surface
//! (a shadow or reflection ray leaves a hit offset by a hair) the side it starts on is
//! the side it moves to, by the gradient, so it does not re-hit its own surface. The
//! minimum step can step over a feature thinner than itself (a tenth of a finest cell,
//! below what the samples resolve); a ray still marching after [`MAX_MARCH_STEPS`] is a
//! miss.

use crate::{Adf, Search};
use dynray_geom::{Aabb, Hit, PreparedRay, Ray, Vec2, Vec3};
use dynray_render::{Geometry, GeometryRef, SurfaceHit};
use dynray_scene::{Color, Material};

/// Steps a ray may take through the cube before it counts as a miss.
pub const MAX_MARCH_STEPS: u32 = 4096;
/// The smallest step, in finest cells.
const MIN_STEP: f32 = 0.1;
/// Bisection steps refining a crossing (each halves the interval).
const REFINE_STEPS: u32 = 24;

impl Adf {
    /// The first crossing of the surface along `ray` within `[tmin, tmax]`: its `t`.
    pub fn march(&self, ray: &Ray) -> Option<f32> {
        let (t0, t1) = self.cube.bounds().clip(&PreparedRay::new(ray), ray.tmin, ray.tmax)?;
        let dl = ray.dir.length();
        if !(dl > 0.0 && dl.is_finite()) {
            return None;
        }
        let finest = self.cube.size / (1u32 << self.max_level) as f32;
        let min_step = MIN_STEP * finest / dl;
        let lip = self.lipschitz.max(1.0);
        let mut hint = 0;
        let mut f = |t: f32| self.distance_unit(self.unit(ray.at(t)), Search::CoherentLinear, &mut hint);
        let mut t = t0.max(ray.tmin);
        let mut d = f(t);
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
            let step = (d.abs() / lip / dl).max(min_step);
            let tn = (t + step).min(t1);
            let dn = f(tn);
            if crossed(dn) {
                let (mut lo, mut hi) = (t, tn);
                for _ in 0..REFINE_STEPS {
                    let mid = 0.5 * (lo + hi);
                    if crossed(f(mid)) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return Some(hi);
            }
            if tn >= t1 {
                return None;
            }
            (t, d) = (tn, dn);
        }
        None
    }
}

/// A distance field placed in a scene with one material (primitive 0, uv = 0).
pub struct AdfGeometry<'a> {
    adf: &'a Adf,
    material: Material,
}

impl<'a> AdfGeometry<'a> {
    /// The field `adf`, shaded with `material`.
    pub fn new(adf: &'a Adf, material: Material) -> Self {
        Self { adf, material }
    }
}

impl Geometry for AdfGeometry<'_> {
    fn intersect(&self, ray: &Ray) -> Hit {
        self.adf.march(ray).map_or(Hit::MISS, |t| Hit { t, u: 0.0, v: 0.0, prim: 0 })
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.adf.march(ray).is_some()
    }

    fn surface<'a>(&'a self, ray: &Ray, hit: &Hit, geometry: u32) -> Option<SurfaceHit<'a>> {
        if !hit.is_hit() {
            return None;
        }
        let p = ray.at(hit.t);
        let mut hint = 0;
        let mut n = self.adf.gradient(p, &mut hint).normalize_or_zero();
        if n == Vec3::ZERO || !n.is_finite() {
            // A flat spot of the field (a saddle of the samples): face the ray.
            n = -ray.dir.normalize_or_zero();
        }
        Some(SurfaceHit {
            t: hit.t,
            p,
            ng: n,
            ns: n,
            uv: Vec2::ZERO,
            material: &self.material,
            texel: Color::ONE,
            at: GeometryRef { geometry, instance: 0, prim: 0 },
        })
    }

    fn bounds(&self) -> Aabb {
        self.adf.cube.bounds()
    }
}
