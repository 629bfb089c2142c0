//! Conservative rasterisation: every triangle into every (dilated) pixel frustum it
//! touches, with the depth interval of the part of the triangle inside that frustum.
//!
//! The triangle is clipped, in face coordinates and `f64`, against the face pyramid, then
//! against each pixel row's slab and each pixel's column slab (all planes through the
//! observer, dilated by `DILATE`). A pixel gets a fragment when the clipped polygon is not
//! empty; the polygon's vertices bound its depth exactly (depth is linear), rounded
//! outwards to `f32`. A zero-area triangle (or one seen edge-on, in a plane through the
//! observer) clips to a segment or a point, which the same code handles.

use super::cube::{f32_down, f32_up, to_face, Cube, FACE_PLANES};
use dynray_geom::Triangle;
use glam::DVec3;

/// A fragment before it is filed under its pixel.
#[derive(Clone, Copy, Debug)]
pub struct RawFrag {
    /// Pixel index (`Cube::pixel`).
    pub pixel: u32,
    /// Depth interval, rounded outwards.
    pub zmin: f32,
    /// See `zmin`.
    pub zmax: f32,
    /// Triangle index.
    pub tri: u32,
}

/// Room for a triangle clipped by 8 planes (3 + 8 = 11 vertices) with spare.
const CAP: usize = 16;

/// A convex polygon in face coordinates.
#[derive(Clone, Copy)]
struct Poly {
    v: [DVec3; CAP],
    n: usize,
}

impl Poly {
    fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Sutherland–Hodgman: the part with `plane·p >= 0`. Should rounding ever produce
    /// more vertices than fit, the input is returned unclipped (a superset: conservative).
    fn clip(&self, plane: DVec3) -> Poly {
        let mut out = Poly { v: [DVec3::ZERO; CAP], n: 0 };
        if self.n == 0 {
            return out;
        }
        for k in 0..self.n {
            let a = self.v[k];
            let b = self.v[(k + 1) % self.n];
            let (da, db) = (plane.dot(a), plane.dot(b));
            let mut push = |p: DVec3| {
                if out.n < CAP {
                    out.v[out.n] = p;
                }
                out.n += 1;
            };
            if da >= 0.0 {
                push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                push(a + (b - a) * (da / (da - db)));
            }
        }
        if out.n > CAP {
            return *self;
        }
        out
    }

    /// Range of `component / w` over the vertices, or `None` when some `w <= 0` (only
    /// possible for triangles near the observer, which are not rasterised).
    fn projected_range(&self, component: usize) -> Option<(f64, f64)> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for p in &self.v[..self.n] {
            if !(p.z > 0.0) {
                return None;
            }
            let x = p[component] / p.z;
            lo = lo.min(x);
            hi = hi.max(x);
        }
        Some((lo, hi))
    }

    fn depth_range(&self) -> (f64, f64) {
        self.v[..self.n].iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.z), hi.max(p.z)))
    }
}

/// The triangle clipped to face `f`'s dilated pyramid, in face coordinates.
fn on_face(rel: &[DVec3; 3], f: usize) -> Poly {
    let mut poly = Poly { v: [DVec3::ZERO; CAP], n: 3 };
    for (k, q) in rel.iter().enumerate() {
        poly.v[k] = to_face(f, *q);
    }
    for plane in FACE_PLANES {
        poly = poly.clip(plane);
    }
    poly
}

/// An upper bound on the number of fragments [`rasterize`] makes of the triangle: the
/// pixels of its projected bounding rectangle on each face. Cheap (no per-pixel work), so
/// the build can keep the widest triangles out of the A-buffers before rasterising.
pub fn coverage_bound(cube: &Cube, tri: &Triangle) -> u64 {
    let rel = [tri.p0, tri.p1, tri.p2].map(|p| p.as_dvec3() - cube.observer);
    let full = (0, cube.res - 1);
    (0..6)
        .map(|f| {
            let poly = on_face(&rel, f);
            if poly.is_empty() {
                return 0;
            }
            let (i0, i1) = poly.projected_range(0).map_or(full, |(lo, hi)| cube.cell_range(lo, hi));
            let (j0, j1) = poly.projected_range(1).map_or(full, |(lo, hi)| cube.cell_range(lo, hi));
            (i1 - i0 + 1) as u64 * (j1 - j0 + 1) as u64
        })
        .sum()
}

/// Appends the fragments of triangle `index` (which must not meet the near box) to `out`.
pub fn rasterize(cube: &Cube, tri: &Triangle, index: u32, out: &mut Vec<RawFrag>) {
    let rel = [tri.p0, tri.p1, tri.p2].map(|p| p.as_dvec3() - cube.observer);
    for f in 0..6 {
        let poly = on_face(&rel, f);
        if poly.is_empty() {
            continue;
        }
        let (j0, j1) = match poly.projected_range(1) {
            Some((lo, hi)) => cube.cell_range(lo, hi),
            None => (0, cube.res - 1),
        };
        for j in j0..=j1 {
            let [lo, hi] = cube.slab_planes(1, j);
            let row = poly.clip(lo).clip(hi);
            if row.is_empty() {
                continue;
            }
            let (i0, i1) = match row.projected_range(0) {
                Some((lo, hi)) => cube.cell_range(lo, hi),
                None => (0, cube.res - 1),
            };
            for i in i0..=i1 {
                let [lo, hi] = cube.slab_planes(0, i);
                let cell = row.clip(lo).clip(hi);
                if cell.is_empty() {
                    continue;
                }
                let (zmin, zmax) = cell.depth_range();
                out.push(RawFrag {
                    pixel: cube.pixel(f, i, j) as u32,
                    zmin: f32_down(zmin),
                    zmax: f32_up(zmax),
                    tri: index,
                });
            }
        }
    }
}

/// True when the triangle may meet the box of half-size `2·eps` around the observer:
/// such triangles are tested on every ray instead of being rasterised (the walk skips
/// the part of a ray within `eps` of the observer, where projection is singular).
/// Conservative: a box-overlap test on the triangle's bounds, refined by the distance of
/// the triangle's plane to the observer when the triangle has a usable normal.
pub fn is_near(cube: &Cube, tri: &Triangle) -> bool {
    let rel = [tri.p0, tri.p1, tri.p2].map(|p| p.as_dvec3() - cube.observer);
    let r = 4.0 * cube.eps;
    let lo = rel[0].min(rel[1]).min(rel[2]);
    let hi = rel[0].max(rel[1]).max(rel[2]);
    if lo.max_element() > r || hi.min_element() < -r {
        return false;
    }
    let n = (rel[1] - rel[0]).cross(rel[2] - rel[0]);
    let len = n.length();
    if len > 0.0 && len.is_finite() {
        // Distance from the observer to the plane, against the half-diagonal of the 2·eps
        // box (√3·2·eps < 4·eps) with a relative allowance for rounding.
        let dist = (n.dot(rel[0]) / len).abs();
        if dist > r * (1.0 + 1e-6) + 1e-9 * rel[0].abs().max_element() {
            return false;
        }
    }
    true
}
