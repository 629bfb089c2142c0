//! "Perfect splits": the box of the part of a triangle inside a node's box, found by
//! clipping the triangle polygon against the box's six planes (Sutherland–Hodgman).
//!
//! The triangle's own box clipped to the node box would overstate a straddling
//! triangle's extent and make the SAH see phantom overlap; Havran and Wald & Havran (2006)
//! clip the polygon instead.

use dynray_geom::{Aabb, Triangle, Vec3};

/// A triangle clipped by six planes has at most 3 + 6 vertices.
const MAX_VERTS: usize = 9;

/// Box of `tri ∩ node`, made conservative, or `None` when they do not meet.
///
/// Intersection points are interpolated in `f32`, so their coordinates other than the
/// clipping plane's may be a few ulps off; the box is therefore widened by a few ulps of
/// the node's scale and then cut back to `node` and to the triangle's own (exact) box. A
/// triangle is thus never reported smaller than it is, and an axis-aligned triangle keeps
/// its exact, flat extent, which the planar-event logic of the builder relies on.
pub fn clipped_bounds(tri: &Triangle, node: &Aabb) -> Option<Aabb> {
    let mut poly = [Vec3::ZERO; MAX_VERTS];
    let mut tmp = [Vec3::ZERO; MAX_VERTS];
    poly[..3].copy_from_slice(&[tri.p0, tri.p1, tri.p2]);
    let mut n = 3;
    for axis in 0..3 {
        n = clip_plane(&poly[..n], &mut tmp, axis, node.min[axis], true);
        n = clip_plane(&tmp[..n], &mut poly, axis, node.max[axis], false);
        if n == 0 {
            return None;
        }
    }
    let b = Aabb::from_points(poly[..n].iter().copied());
    if !(b.min.is_finite() && b.max.is_finite()) {
        // Coordinates near f32::MAX overflow the interpolation; the caller then falls back
        // to the triangle's current box, which is conservative.
        return None;
    }
    let scale = node.min.abs().max(node.max.abs()) + node.extent();
    let pad = scale * (4.0 * f32::EPSILON);
    let b = Aabb::new(b.min - pad, b.max + pad).intersection(node).intersection(&tri.bounds());
    (!b.is_empty()).then_some(b)
}

/// Keeps the part of the convex polygon `src` with `p[axis] >= plane` (`keep_above`) or
/// `<= plane`, writing it to `dst`; returns its vertex count. New vertices lie exactly on
/// the plane in `axis`.
fn clip_plane(src: &[Vec3], dst: &mut [Vec3; MAX_VERTS], axis: usize, plane: f32, keep_above: bool) -> usize {
    let inside = |p: Vec3| if keep_above { p[axis] >= plane } else { p[axis] <= plane };
    let mut n = 0;
    for (i, &a) in src.iter().enumerate() {
        let b = src[(i + 1) % src.len()];
        let (ia, ib) = (inside(a), inside(b));
        if ia {
            n = push(dst, n, a);
        }
        if ia != ib {
            // a and b lie strictly on opposite sides, so the denominator is not zero.
            let s = (plane - a[axis]) / (b[axis] - a[axis]);
            let mut p = a + (b - a) * s.clamp(0.0, 1.0);
            p[axis] = plane;
            n = push(dst, n, p);
        }
    }
    n
}

#[inline]
fn push(dst: &mut [Vec3; MAX_VERTS], n: usize, p: Vec3) -> usize {
    // A convex polygon clipped by one plane gains at most one vertex; the 3 + 6 bound holds.
    debug_assert!(n < MAX_VERTS, "clipped polygon exceeds {MAX_VERTS} vertices");
    if n < MAX_VERTS {
        dst[n] = p;
        n + 1
    } else {
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straddling_triangle_gets_its_true_extent() {
        // Diagonal triangle: its box is [0,2]², but inside x <= 1 it only reaches y <= 1.
        let tri = Triangle::new(Vec3::ZERO, Vec3::new(2.0, 2.0, 0.0), Vec3::new(2.0, 0.0, 0.0));
        let node = Aabb::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, 5.0, 1.0));
        let b = clipped_bounds(&tri, &node).unwrap();
        assert!(b.max.x == 1.0 && b.max.y < 1.0 + 1e-5 && b.max.y >= 1.0, "{b:?}");
        assert_eq!(b.min.z, 0.0);
        assert_eq!(b.max.z, 0.0);
    }

    #[test]
    fn disjoint_triangle_is_none() {
        let tri = Triangle::new(Vec3::ZERO, Vec3::new(2.0, 2.0, 0.0), Vec3::new(2.0, 0.0, 0.0));
        let node = Aabb::new(Vec3::new(-1.0, 1.5, -1.0), Vec3::new(0.5, 5.0, 1.0));
        assert!(clipped_bounds(&tri, &node).is_none());
    }
}
