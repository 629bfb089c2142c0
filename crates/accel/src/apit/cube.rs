//! The observer's cube: six faces of R×R pixels, each pixel an infinite pyramid (frustum)
//! from the observer, and the plane equations the rasteriser and the ray walk share.
//!
//! Face `f` looks down axis `a = f / 2` with sign `s = +1` (even `f`) or `-1` (odd). A
//! point `q` relative to the observer has face coordinates `(U, V, w)` =
//! `(q[a+1], q[a+2], s·q[a])`; it projects to `(u, v) = (U / w, V / w)` in `[-1, 1]²`.
//! The depth of a point is `w`, the distance along the face axis: linear along a ray, so
//! a ray's depth range over a `t` interval is given by its two ends.
//!
//! Every boundary is a plane through the observer, written as a linear form `n·(U, V, w)`
//! that is `>= 0` inside. Exactness comes from dilation, not from exact arithmetic: all
//! geometry here is in `f64` and every pixel (and face) is widened by [`DILATE`] on both
//! sides, both when triangles are rasterised and when rays walk. A point that truly lies
//! in a pixel's closed frustum is then inside the dilated one by a margin of `DILATE·w`,
//! far above the `f64` rounding of these few operations.

use dynray_geom::{Aabb, Vec3};
use glam::DVec3;

/// Widening of every pixel and face, in face-plane units (a face spans 2 units; a pixel of
/// the finest resolution 2/4096 ≈ 4.9e-4, so this is at most 2 % of a pixel).
pub const DILATE: f64 = 1e-5;

/// Half-size of the box around the observer that rays skip (its triangles are always
/// tested instead), relative to the scene's size. Projection is singular at the observer;
/// outside this box `w >= EPS / (1 + DILATE)` on the face a point belongs to.
const NEAR_REL: f64 = 1e-4;

/// Geometry of the cube of A-buffers.
#[derive(Clone, Copy, Debug)]
pub struct Cube {
    /// Centre of the cube (the apex of every frustum).
    pub observer: DVec3,
    /// The observer as given, in `f32`.
    pub observer_f32: Vec3,
    /// Pixels per face side.
    pub res: u32,
    /// Half-size of the near box around the observer: the walk skips the part of a ray
    /// inside it; triangles meeting twice that box are tested on every ray instead.
    pub eps: f64,
    /// The mesh's bounding box, padded: no hit lies outside it.
    pub bounds: Aabb,
    /// Largest distance from the observer to the padded bounds (for `t` slack).
    pub radius: f64,
}

impl Cube {
    /// The cube of `res`² pixels per face around `observer` for a mesh within `bounds`.
    pub fn new(observer: Vec3, res: u32, bounds: Aabb) -> Self {
        let o = observer.as_dvec3();
        let (lo, hi) = (bounds.min.as_dvec3(), bounds.max.as_dvec3());
        let size = (hi - lo).max_element().max((hi.max(o) - lo.min(o)).max_element());
        let mag = lo.abs().max(hi.abs()).max(o.abs()).max_element();
        // Pad by a relative margin so that Aabb::clip's answer cannot cut a hit off.
        let pad = (1e-5 * size + 1e-6 * mag + 1e-30) as f32;
        let bounds = Aabb::new(bounds.min - Vec3::splat(pad), bounds.max + Vec3::splat(pad));
        let (lo, hi) = (bounds.min.as_dvec3(), bounds.max.as_dvec3());
        let radius = (lo - o).abs().max((hi - o).abs()).length();
        let eps = (NEAR_REL * size).max(1e-6 * mag).max(1e-30);
        Self { observer: o, observer_f32: observer, res, eps, bounds, radius }
    }

    /// Number of pixels over all six faces.
    pub fn pixels(&self) -> usize {
        6 * self.res as usize * self.res as usize
    }

    /// Index of pixel column `i`, row `j` of face `f` in the pixel arrays.
    #[inline(always)]
    pub fn pixel(&self, f: usize, i: u32, j: u32) -> usize {
        (f * self.res as usize + j as usize) * self.res as usize + i as usize
    }

    /// `k`-th pixel boundary on a face axis: `-1 + 2k / R`.
    #[inline(always)]
    pub fn boundary(&self, k: u32) -> f64 {
        -1.0 + 2.0 * k as f64 / self.res as f64
    }

    /// Columns (or rows) whose dilated extent can hold a point of `[lo, hi]`, clamped to
    /// the face; all of them when `lo`/`hi` are not ordered numbers.
    #[inline]
    pub fn cell_range(&self, lo: f64, hi: f64) -> (u32, u32) {
        let last = self.res - 1;
        if !(lo <= hi) {
            return (0, last);
        }
        let r = self.res as f64 * 0.5;
        let cell = |x: f64| ((x + 1.0) * r).floor().clamp(0.0, last as f64) as u32;
        (cell(lo - DILATE), cell(hi + DILATE))
    }

    /// The two dilated planes bounding column `k` (`axis` 0) or row `k` (`axis` 1):
    /// `U >= (b_k - DILATE)·w` and `U <= (b_{k+1} + DILATE)·w` (`V` for rows).
    #[inline(always)]
    pub fn slab_planes(&self, axis: usize, k: u32) -> [DVec3; 2] {
        let lo = self.boundary(k) - DILATE;
        let hi = self.boundary(k + 1) + DILATE;
        if axis == 0 {
            [DVec3::new(1.0, 0.0, -lo), DVec3::new(-1.0, 0.0, hi)]
        } else {
            [DVec3::new(0.0, 1.0, -lo), DVec3::new(0.0, -1.0, hi)]
        }
    }
}

/// The four dilated planes of a face pyramid: `|U| <= (1 + DILATE)·w`, `|V| <= (1 + DILATE)·w`.
pub const FACE_PLANES: [DVec3; 4] = [
    DVec3::new(-1.0, 0.0, 1.0 + DILATE),
    DVec3::new(1.0, 0.0, 1.0 + DILATE),
    DVec3::new(0.0, -1.0, 1.0 + DILATE),
    DVec3::new(0.0, 1.0, 1.0 + DILATE),
];

/// Face coordinates `(U, V, w)` of a vector relative to the observer (module docs).
#[inline(always)]
pub fn to_face(f: usize, q: DVec3) -> DVec3 {
    let a = f / 2;
    let s = if f & 1 == 0 { 1.0 } else { -1.0 };
    DVec3::new(q[(a + 1) % 3], q[(a + 2) % 3], s * q[a])
}

/// The largest `f32` not above `x` (depth intervals are rounded outwards).
#[inline]
pub fn f32_down(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) <= x || f.is_nan() || f == f32::NEG_INFINITY {
        f
    } else if f == 0.0 {
        -f32::from_bits(1)
    } else if f > 0.0 {
        f32::from_bits(f.to_bits() - 1)
    } else {
        f32::from_bits(f.to_bits() + 1)
    }
}

/// The smallest `f32` not below `x`.
#[inline]
pub fn f32_up(x: f64) -> f32 {
    -f32_down(-x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outward_rounding_brackets() {
        for x in [0.0, 1e-40, -1e-40, 0.1, -0.1, 1.0 / 3.0, 1e30, -7.25, 3.0e38] {
            assert!((f32_down(x) as f64) <= x && (f32_up(x) as f64) >= x, "{x}");
        }
    }

    #[test]
    fn cell_range_covers_boundaries() {
        let c = Cube::new(Vec3::ZERO, 8, Aabb::new(-Vec3::ONE, Vec3::ONE));
        assert_eq!(c.cell_range(-1.0, -1.0), (0, 0));
        assert_eq!(c.cell_range(0.0, 0.0), (3, 4));
        assert_eq!(c.cell_range(0.1, 0.2), (4, 4));
        assert_eq!(c.cell_range(f64::NAN, 0.0), (0, 7));
    }
}
