//! Axis-aligned boxes and the robust ray–box slab test.

use crate::PreparedRay;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// Relative widening of every slab interval, so that a box test never rejects a ray
/// the watertight triangle test would accept inside that box.
///
/// Ize (JCGT 2013) shows `2·γ(3) ≈ 3.6e-7` makes the slab test conservative against
/// exact arithmetic; the triangle test's own `t` carries a few more ulps of rounding, so
/// we widen by 1e-6 (≈ 8 ulps). The cost is a handful of extra box visits per million rays.
pub const SLAB_MARGIN: f32 = 1.0e-6;

/// An axis-aligned box; empty when `min > max` on some axis ([`Aabb::EMPTY`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

// Two Vec3 = 24 bytes; node layouts embed it and count on that size.
const _: () = assert!(std::mem::size_of::<Aabb>() == 24);

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The empty box: growing it by anything gives that thing's box.
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    /// Box with the given corners.
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// Smallest box holding all `points`.
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| b.grown(p))
    }

    /// True when the box holds no point.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// This box grown to hold `p`.
    #[inline]
    pub fn grown(&self, p: Vec3) -> Self {
        Self { min: self.min.min(p), max: self.max.max(p) }
    }

    /// Grows this box to hold `p`.
    #[inline]
    pub fn grow(&mut self, p: Vec3) {
        *self = self.grown(p);
    }

    /// Smallest box holding both.
    #[inline]
    pub fn union(&self, o: &Aabb) -> Self {
        Self { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// Overlap of both boxes (possibly empty).
    pub fn intersection(&self, o: &Aabb) -> Self {
        Self { min: self.min.max(o.min), max: self.max.min(o.max) }
    }

    /// `max - min` (negative on an empty box).
    #[inline]
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// Centre point.
    #[inline]
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Surface area; 0 for an empty box.
    #[inline]
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// Index of the longest axis (0 = x, 1 = y, 2 = z; ties go to the lower axis).
    pub fn largest_axis(&self) -> usize {
        let e = self.extent();
        if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        }
    }

    /// True when `p` lies inside or on the box.
    pub fn contains_point(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// True when `o` lies inside or on this box.
    pub fn contains(&self, o: &Aabb) -> bool {
        o.min.cmpge(self.min).all() && o.max.cmple(self.max).all()
    }

    /// The parametric interval `[t_enter, t_exit]` where the ray is inside the box,
    /// clipped to `[tmin, tmax]`, or `None` when it is empty.
    ///
    /// Conservative: widened by [`SLAB_MARGIN`], and a ray parallel to a slab whose origin
    /// lies exactly on that slab's plane (`0·∞ = NaN`) counts as inside it, because the
    /// closed box includes its faces and so does the triangle test.
    #[inline]
    pub fn clip(&self, r: &PreparedRay, tmin: f32, tmax: f32) -> Option<(f32, f32)> {
        let lo = (self.min - r.ray.origin) * r.inv_dir;
        let hi = (self.max - r.ray.origin) * r.inv_dir;
        let (n0, f0) = slab(lo.x, hi.x);
        let (n1, f1) = slab(lo.y, hi.y);
        let (n2, f2) = slab(lo.z, hi.z);
        let near = n0.max(n1).max(n2);
        let far = f0.min(f1).min(f2);
        // Widen outwards; multiplying keeps ±∞ intact (adding |∞|·m would give NaN).
        let near = (near * if near > 0.0 { 1.0 - SLAB_MARGIN } else { 1.0 + SLAB_MARGIN }).max(tmin);
        let far = (far * if far > 0.0 { 1.0 + SLAB_MARGIN } else { 1.0 - SLAB_MARGIN }).min(tmax);
        if near <= far && !self.is_empty() {
            Some((near, far))
        } else {
            None
        }
    }

    /// Entry distance of the ray into the box within `[ray.tmin, tmax]`, or `None`.
    #[inline]
    pub fn intersect(&self, r: &PreparedRay, tmax: f32) -> Option<f32> {
        self.clip(r, r.ray.tmin, tmax).map(|(n, _)| n)
    }
}

/// Near and far distance of one slab; a NaN (origin on the plane, direction parallel)
/// leaves the slab unconstrained.
#[inline(always)]
fn slab(a: f32, b: f32) -> (f32, f32) {
    if a.is_nan() || b.is_nan() {
        (f32::NEG_INFINITY, f32::INFINITY)
    } else if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Ray;

    fn unit() -> Aabb {
        Aabb::new(Vec3::ZERO, Vec3::ONE)
    }

    #[test]
    fn ray_through_box_enters_and_exits() {
        let r = PreparedRay::new(&Ray::new(Vec3::new(-1.0, 0.5, 0.5), Vec3::X));
        let (n, f) = unit().clip(&r, 0.0, f32::INFINITY).unwrap();
        assert!((n - 1.0).abs() < 1e-5 && (f - 2.0).abs() < 1e-5, "{n} {f}");
    }

    #[test]
    fn ray_missing_box_is_rejected() {
        let r = PreparedRay::new(&Ray::new(Vec3::new(-1.0, 2.0, 0.5), Vec3::X));
        assert!(unit().clip(&r, 0.0, f32::INFINITY).is_none());
    }

    #[test]
    fn parallel_ray_on_face_plane_is_inside() {
        // Origin on the y = 0 face, travelling along x: 0·∞ would poison a naive test.
        let r = PreparedRay::new(&Ray::new(Vec3::new(-1.0, 0.0, 0.5), Vec3::X));
        assert!(unit().clip(&r, 0.0, f32::INFINITY).is_some());
        let r = PreparedRay::new(&Ray::new(Vec3::new(-1.0, 1.0, 1.0), Vec3::X));
        assert!(unit().clip(&r, 0.0, f32::INFINITY).is_some());
    }

    #[test]
    fn interval_clipping_respects_tmax() {
        let r = PreparedRay::new(&Ray::new(Vec3::new(-1.0, 0.5, 0.5), Vec3::X));
        assert!(unit().clip(&r, 0.0, 0.5).is_none());
        assert!(unit().clip(&r, 2.5, 9.0).is_none());
    }

    #[test]
    fn empty_box_has_no_area_and_is_never_hit() {
        assert_eq!(Aabb::EMPTY.surface_area(), 0.0);
        let r = PreparedRay::new(&Ray::new(Vec3::ZERO, Vec3::X));
        assert!(Aabb::EMPTY.clip(&r, 0.0, f32::INFINITY).is_none());
    }
}
