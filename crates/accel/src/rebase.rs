//! Far rays for the cell walks (grid, octree walk and descent): a ray whose origin lies
//! thousands of box sizes away cannot be walked in f32 from that origin — entry points
//! `o + t·d` and plane crossings `(p − o)/d` then carry errors of `ulp(|o|)`, hundreds of
//! cells at 10^10, and the walk starts in, or steps to, the wrong cells. Brute force
//! never computes a point along the ray (the triangle test works relative to the origin
//! in f64), so it still finds the exact hit.
//!
//! [`Rebased`] re-expresses such a ray for the walk from a point just before the box:
//! `o' = o + t_s·d` computed with one rounding (fused multiply-add in f64, then f32), the
//! same direction, and walk distances `t' = t − t_s`. The walk runs on `o'` (every cell
//! computation is then as accurate as for a ray starting beside the model), while the
//! triangle tests keep the original ray, so hits stay bit for bit brute force's.
//! Distances crossing between the two (the best hit as a cull bound, the ray's interval)
//! are converted outward with a margin that covers the triangle test's rounding of `t`,
//! which is relative to `t`, not to `t'`.

use dynray_geom::{Aabb, Ray, Vec3, SLAB_MARGIN};

/// Origins farther than this many box sizes from the box are walked from a rebased
/// origin; nearer ones as they are (no cost for camera and secondary rays).
const FAR: f64 = 256.0;

/// Relative margin on hit distances converted into walk distances: the slab margin
/// (which covers the triangle test's rounding of `t`) twice over.
const T_MARGIN: f64 = 2.0 * SLAB_MARGIN as f64;

/// A far ray's stand-in for the cell walk.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rebased {
    /// The walk's ray: origin near the box, the same direction, the interval in walk
    /// distances (widened outward).
    pub(crate) ray: Ray,
    /// `t_s`: original distance = walk distance + `shift`.
    shift: f64,
}

impl Rebased {
    /// The walk's stand-in for `ray` against `bounds`, or `None` when the ray can be
    /// walked as it is (its origin near the box, or nothing finite to rebase).
    pub(crate) fn new(ray: &Ray, bounds: &Aabb) -> Option<Rebased> {
        let (o, d) = (ray.origin, ray.dir);
        let size = bounds.extent().max_element() as f64;
        if !(o.is_finite() && d.is_finite() && size.is_finite()) || d == Vec3::ZERO {
            return None;
        }
        let size = size.max(f32::MIN_POSITIVE as f64);
        let lo = bounds.min.as_dvec3();
        let hi = bounds.max.as_dvec3();
        let od = o.as_dvec3();
        let outside = (lo - od).max(od - hi).max_element();
        if outside <= FAR * size {
            return None;
        }
        // The box's entry distance in f64 (accurate to ~1e-16 relative); a ray parallel
        // to a slab it is outside of misses the box: nothing to walk.
        let dd = d.as_dvec3();
        let mut enter = f64::NEG_INFINITY;
        for a in 0..3 {
            if dd[a] == 0.0 {
                if od[a] < lo[a] || od[a] > hi[a] {
                    return None;
                }
            } else {
                let (t1, t2) = ((lo[a] - od[a]) / dd[a], (hi[a] - od[a]) / dd[a]);
                enter = enter.max(t1.min(t2));
            }
        }
        // Start half a box size before the entry: the walk's own clip finds the entry.
        let shift = enter - 0.5 * size / dd.length();
        let origin = Vec3::from_array(std::array::from_fn(|a| dd[a].mul_add(shift, od[a]) as f32));
        if !origin.is_finite() {
            return None;
        }
        let mut rebased = Rebased { ray: *ray, shift };
        rebased.ray = Ray::with_interval(origin, d, rebased.below(ray.tmin), rebased.above(ray.tmax));
        Some(rebased)
    }

    /// A walk distance no smaller than that of any point whose hit distance the triangle
    /// test can report as `t` or less: the cull bound for the best hit `t`.
    pub(crate) fn above(&self, t: f32) -> f32 {
        if !t.is_finite() {
            return t;
        }
        let t = t as f64;
        up(t + t.abs() * T_MARGIN - self.shift)
    }

    /// A walk distance no larger than that of any point whose hit distance the triangle
    /// test can report as `t` or more.
    pub(crate) fn below(&self, t: f32) -> f32 {
        if !t.is_finite() {
            return t;
        }
        let t = t as f64;
        -up(-(t - t.abs() * T_MARGIN - self.shift))
    }
}

/// The cull bound in walk distances for the best hit `t` (the ray's own `t` when the
/// ray is walked as it is).
#[inline(always)]
pub(crate) fn cull(rebased: &Option<Rebased>, t: f32) -> f32 {
    match rebased {
        Some(b) => b.above(t),
        None => t,
    }
}

/// `x` rounded up to an f32.
fn up(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) < x {
        y.next_up()
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::Rebased;
    use dynray_geom::{Aabb, Ray, Vec3};

    fn unit_box() -> Aabb {
        Aabb { min: Vec3::ZERO, max: Vec3::ONE }
    }

    #[test]
    fn near_rays_are_walked_as_they_are() {
        let r = Ray::new(Vec3::new(-100.0, 0.5, 0.5), Vec3::X);
        assert!(Rebased::new(&r, &unit_box()).is_none());
    }

    #[test]
    fn a_far_ray_starts_just_before_the_box_on_the_same_line() {
        let o = Vec3::new(-1.0e10, 3.0e9, 0.5);
        let target = Vec3::new(0.5, 0.5, 0.5);
        let r = Ray::new(o, target - o);
        let b = Rebased::new(&r, &unit_box()).expect("far");
        let p = b.ray.origin;
        assert!(p.x > -2.0 && p.x < 0.0, "{p}");
        // On the ray's own line (the f32 direction towards the target is itself rounded
        // at the origin's scale, so the line passes near the target, not through it):
        // the distance of the walk origin from the exact line, computed in f64.
        let (od, dd, pd) = (o.as_dvec3(), r.dir.as_dvec3(), p.as_dvec3());
        let off = (pd - od).cross(dd).length() / dd.length();
        assert!(off < 1e-6, "the walk origin is {off} off the ray's line");
        // Conversions go outward and bracket the shift.
        assert!(b.below(1.0) <= b.above(1.0));
        assert_eq!(b.above(f32::INFINITY), f32::INFINITY);
        assert_eq!(b.ray.tmax, f32::INFINITY);
        assert!(b.ray.tmin < 0.0);
    }

    #[test]
    fn rays_parallel_outside_a_slab_are_left_alone() {
        let r = Ray::new(Vec3::new(-1.0e10, 5.0, 0.5), Vec3::X);
        assert!(Rebased::new(&r, &unit_box()).is_none());
    }
}
