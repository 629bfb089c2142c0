//! The engine's only ray–triangle test: the watertight test of Woop, Benthin and Wald,
//! "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013.
//!
//! Watertight: a ray through a shared edge or vertex of a closed mesh hits at least one
//! of the triangles that share it, because the 2-D edge functions are evaluated with the
//! same operands for both triangles.
//! Every structure calls this function with the same [`PreparedRay`] and the same
//! vertex order, so all of them agree with brute force bit for bit.

use crate::{Aabb, PreparedRay};
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// One triangle's three vertices, in the mesh's winding.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Triangle {
    /// First vertex.
    pub p0: Vec3,
    /// Second vertex (barycentric `u`).
    pub p1: Vec3,
    /// Third vertex (barycentric `v`).
    pub p2: Vec3,
}

// 9 floats, no padding: structures store these in leaf order and upload them as is.
const _: () = assert!(std::mem::size_of::<Triangle>() == 36);

impl Triangle {
    /// Triangle from its vertices.
    pub fn new(p0: Vec3, p1: Vec3, p2: Vec3) -> Self {
        Self { p0, p1, p2 }
    }

    /// Bounding box.
    pub fn bounds(&self) -> Aabb {
        Aabb { min: self.p0.min(self.p1).min(self.p2), max: self.p0.max(self.p1).max(self.p2) }
    }

    /// Centroid.
    pub fn centroid(&self) -> Vec3 {
        (self.p0 + self.p1 + self.p2) * (1.0 / 3.0)
    }

    /// Unnormalised geometric normal `(p1-p0)×(p2-p0)`.
    pub fn normal(&self) -> Vec3 {
        (self.p1 - self.p0).cross(self.p2 - self.p0)
    }

    /// Intersects the ray, two-sided, accepting `r.ray.tmin <= t <= tmax`.
    ///
    /// Returns `(t, u, v)` with the hit point `(1-u-v)·p0 + u·p1 + v·p2`.
    ///
    /// The test runs in f64 on the f32 inputs: differences of f32 values are exact in f64
    /// and products nearly so, so edge functions and `t` carry ~1e-16 relative error
    /// before `t` is rounded once to f32. In f32 (as in the paper), a scene with 1e6
    /// coordinates gave hits outside the triangle's own bounding box, so structures that
    /// cull by boxes disagreed with brute force. Cost: about 20 % more per test, measured
    /// on random triangles. Shared edges see identical operands (negated) in both
    /// triangles, so the test stays watertight without the paper's f64 fallback.
    #[inline]
    pub fn intersect(&self, r: &PreparedRay, tmax: f32) -> Option<(f32, f32, f32)> {
        let [kx, ky, kz] = r.k;
        let [sx, sy, sz] = r.shear;
        let o = r.origin64;
        let rel = |p: Vec3| [p[kx] as f64 - o[0], p[ky] as f64 - o[1], p[kz] as f64 - o[2]];
        let a = rel(self.p0);
        let b = rel(self.p1);
        let c = rel(self.p2);
        // Shear into the ray's space, where the ray is the +z axis through the origin.
        let ax = a[0] - sx * a[2];
        let ay = a[1] - sy * a[2];
        let bx = b[0] - sx * b[2];
        let by = b[1] - sy * b[2];
        let cx = c[0] - sx * c[2];
        let cy = c[1] - sy * c[2];
        // Scaled barycentrics: the 2-D edge function opposite each vertex.
        let eu = cx * by - cy * bx;
        let ev = ax * cy - ay * cx;
        let ew = bx * ay - by * ax;
        if (eu < 0.0 || ev < 0.0 || ew < 0.0) && (eu > 0.0 || ev > 0.0 || ew > 0.0) {
            return None;
        }
        let det = eu + ev + ew;
        if det == 0.0 {
            return None;
        }
        let tt = (eu * a[2] + ev * b[2] + ew * c[2]) * sz;
        let rcp = 1.0 / det;
        let t = (tt * rcp) as f32;
        // NaN (degenerate ray) fails both comparisons and misses.
        if t >= r.ray.tmin && t <= tmax {
            Some((t, (ev * rcp) as f32, (ew * rcp) as f32))
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Ray;

    fn tri() -> Triangle {
        Triangle::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0))
    }

    fn cast(o: Vec3, d: Vec3) -> Option<(f32, f32, f32)> {
        tri().intersect(&PreparedRay::new(&Ray::new(o, d)), f32::INFINITY)
    }

    #[test]
    fn hits_inside_with_barycentrics() {
        let (t, u, v) = cast(Vec3::new(0.25, 0.5, 2.0), -Vec3::Z).unwrap();
        assert_eq!(t, 2.0);
        assert!((u - 0.25).abs() < 1e-6 && (v - 0.5).abs() < 1e-6, "{u} {v}");
    }

    #[test]
    fn is_two_sided() {
        assert!(cast(Vec3::new(0.25, 0.25, -2.0), Vec3::Z).is_some());
    }

    #[test]
    fn misses_outside() {
        assert!(cast(Vec3::new(0.75, 0.75, 2.0), -Vec3::Z).is_none());
        assert!(cast(Vec3::new(-0.1, 0.5, 2.0), -Vec3::Z).is_none());
    }

    #[test]
    fn respects_interval() {
        let r = PreparedRay::new(&Ray::with_interval(Vec3::new(0.2, 0.2, 2.0), -Vec3::Z, 2.5, 9.0));
        assert!(tri().intersect(&r, 9.0).is_none());
        let r = PreparedRay::new(&Ray::with_interval(Vec3::new(0.2, 0.2, 2.0), -Vec3::Z, 0.0, 1.5));
        assert!(tri().intersect(&r, 1.5).is_none());
        // Inclusive bounds.
        let r = PreparedRay::new(&Ray::with_interval(Vec3::new(0.2, 0.2, 2.0), -Vec3::Z, 2.0, 2.0));
        assert_eq!(tri().intersect(&r, 2.0).unwrap().0, 2.0);
    }

    #[test]
    fn edge_and_vertex_hits_count() {
        assert!(cast(Vec3::new(0.5, 0.0, 1.0), -Vec3::Z).is_some());
        assert!(cast(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z).is_some());
        assert!(cast(Vec3::new(0.5, 0.5, 1.0), -Vec3::Z).is_some());
    }

    #[test]
    fn ray_in_the_triangle_plane_misses() {
        assert!(cast(Vec3::new(-1.0, 0.25, 0.0), Vec3::X).is_none());
    }

    #[test]
    fn zero_direction_never_hits_or_panics() {
        assert!(cast(Vec3::new(0.25, 0.25, 0.0), Vec3::ZERO).is_none());
    }

    #[test]
    fn hits_stay_inside_the_triangle_box_at_large_coordinates() {
        // Regression: evaluated in f32, this ray (moving away from the triangle's plane)
        // reported a hit at positive t far outside the triangle's bounding box.
        let tri = Triangle::new(Vec3::new(0.0, 0.5, -1.0), Vec3::new(1.0e6, 0.5, -1.0), Vec3::new(0.0, 0.5, 2.0));
        let ray = Ray::new(Vec3::new(295380.4, 0.6703102, -0.22290957), Vec3::new(0.8600666, 0.22906902, 0.45586503));
        assert_eq!(tri.intersect(&PreparedRay::new(&ray), f32::INFINITY), None);
        let back = Ray::new(ray.origin, -ray.dir);
        let (t, _, _) = tri.intersect(&PreparedRay::new(&back), f32::INFINITY).expect("hit behind");
        assert!((back.at(t).y - 0.5).abs() < 1e-6, "{}", back.at(t));
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Two triangles sharing the diagonal of a skewed quad; rays along the diagonal.
        let p =
            [Vec3::new(0.1, 0.3, 0.7), Vec3::new(3.3, 0.2, 0.1), Vec3::new(2.9, 3.1, -0.4), Vec3::new(-0.2, 2.7, 0.3)];
        let t0 = Triangle::new(p[0], p[1], p[2]);
        let t1 = Triangle::new(p[0], p[2], p[3]);
        // Interior points of the diagonal only: at its ends (the quad's corners) a target
        // rounded an ulp outwards legitimately misses both triangles.
        for i in 1..1000 {
            let f = i as f32 / 1000.0;
            let target = p[0] + (p[2] - p[0]) * f;
            let o = Vec3::new(0.37, 1.1, 5.0);
            let r = PreparedRay::new(&Ray::new(o, target - o));
            let h0 = t0.intersect(&r, f32::INFINITY);
            let h1 = t1.intersect(&r, f32::INFINITY);
            assert!(h0.is_some() || h1.is_some(), "leak at f = {f}");
        }
    }
}
