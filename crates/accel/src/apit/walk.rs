//! The ray walk: the pixel frustums a ray crosses, face by face, column by column, row by
//! row, each with the ray's depth interval inside it.
//!
//! A ray is not assumed to start at the observer. Its part inside the (padded) mesh
//! bounds is cut into at most two pieces by the near box around the observer (skipped:
//! its triangles are tested directly), each piece is clipped against the six dilated face
//! pyramids, and on each face the ray is clipped against the dilated slab of every column
//! its projection can reach, then, within a column, against every row's slab. Because the
//! projection of a ray onto a face is monotone in `t` (the depth `w` keeps its sign on the
//! face), the columns come in the order the ray enters them and so do the rows within a
//! column: the walk may stop a column (or a face) as soon as an entry lies beyond the
//! current bound, i.e. beyond the best hit so far. Every pixel whose closed frustum holds
//! a point of the ray at a `t` up to that bound is visited (dilation absorbs rounding;
//! `slack` absorbs the difference between the triangle test's `t` and the exact one).
//! The walk is finite: at most 12 face pieces, each at most R columns × R rows.

use super::cube::{f32_down, f32_up, to_face, Cube, FACE_PLANES};
use dynray_geom::Ray;
use glam::DVec3;

/// What the walk reports to.
pub trait Visitor {
    /// The largest `t` still of interest (the best hit so far, or the ray's `tmax`).
    fn bound(&self) -> f32;
    /// A frustum crossed by the ray, with the ray's depth range `[qa, qb]` in it;
    /// returns true to stop the walk.
    fn visit(&mut self, pixel: usize, qa: f32, qb: f32) -> bool;
}

/// `[a, b]` clipped to where the linear form `g0 + g1·t` is `>= 0`.
#[inline(always)]
fn clip_t(a: f64, b: f64, g0: f64, g1: f64) -> (f64, f64) {
    if g1 > 0.0 {
        (a.max(-g0 / g1), b)
    } else if g1 < 0.0 {
        (a, b.min(-g0 / g1))
    } else if g0 >= 0.0 {
        (a, b)
    } else {
        (f64::INFINITY, f64::NEG_INFINITY)
    }
}

/// The ray in one face's coordinates: `p0 + t·pd`.
struct FaceRay {
    p0: DVec3,
    pd: DVec3,
}

impl FaceRay {
    #[inline(always)]
    fn clip(&self, a: f64, b: f64, plane: DVec3) -> (f64, f64) {
        clip_t(a, b, plane.dot(self.p0), plane.dot(self.pd))
    }

    #[inline(always)]
    fn at(&self, t: f64) -> DVec3 {
        self.p0 + self.pd * t
    }

    /// Cells (`axis` 0: columns, 1: rows) reached on `[a, b]`, in the order the ray enters
    /// them: (first, last, ascending, sure). `sure` is false when the projection moves so
    /// little that rounding could have flipped the order: then the caller must not stop
    /// early on an entry beyond its bound (the range is then a cell or two).
    #[inline(always)]
    fn cells(&self, cube: &Cube, axis: usize, a: f64, b: f64) -> (u32, u32, bool, bool) {
        let (pa, pb) = (self.at(a), self.at(b));
        if !(pa.z > 0.0 && pb.z > 0.0) {
            // Not possible outside the near box; stay conservative anyway.
            return (0, cube.res - 1, true, false);
        }
        let (xa, xb) = (pa[axis] / pa.z, pb[axis] / pb.z);
        let (lo, hi) = cube.cell_range(xa.min(xb), xa.max(xb));
        // Rounding of x = U / w: ~1e-16 of |p0| (cancellation) over w, plus a floor.
        let tol = 1e-6 + 1e-13 * self.p0.abs().max_element() / pa.z.min(pb.z);
        (lo, hi, xb >= xa, (xb - xa).abs() > tol)
    }
}

/// Walks the frustums `ray` crosses for `t` in `[t0, t1]` (already clipped to the mesh
/// bounds). Returns true when the visitor stopped the walk.
pub fn walk(cube: &Cube, ray: &Ray, t0: f32, t1: f32, v: &mut impl Visitor) -> bool {
    let q0 = ray.origin.as_dvec3() - cube.observer;
    let d = ray.dir.as_dvec3();
    let dlen = d.length();
    if !(dlen > 0.0) {
        return false;
    }
    // Generous allowance for the f32 triangle test's error on t (and for rounding here).
    let slack = 1e-5 * (q0.length() + cube.radius) / dlen;
    let (ta, tb) = (t0 as f64 - slack, t1 as f64 + slack);
    // Part of the ray inside the near box (max-norm <= eps), computed in f64: skipped.
    let (mut e0, mut e1) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        if d[k] == 0.0 {
            if q0[k].abs() > cube.eps {
                (e0, e1) = (f64::INFINITY, f64::NEG_INFINITY);
            }
        } else {
            let (x, y) = ((-cube.eps - q0[k]) / d[k], (cube.eps - q0[k]) / d[k]);
            e0 = e0.max(x.min(y));
            e1 = e1.min(x.max(y));
        }
    }
    let mut pieces = [(ta, tb), (f64::INFINITY, f64::NEG_INFINITY)];
    if e0 <= e1 {
        pieces = [(ta, tb.min(e0)), (ta.max(e1), tb)];
    }
    // Face segments: (entry, exit, face), at most 2 pieces × 6 faces, sorted by entry.
    let mut segs = [(0.0f64, 0.0f64, 0usize); 12];
    let mut n = 0;
    for &(a, b) in &pieces {
        if !(a <= b) {
            continue;
        }
        for f in 0..6 {
            let fr = FaceRay { p0: to_face(f, q0), pd: to_face(f, d) };
            let (mut fa, mut fb) = (a, b);
            for plane in FACE_PLANES {
                (fa, fb) = fr.clip(fa, fb, plane);
            }
            if fa <= fb {
                segs[n] = (fa, fb, f);
                n += 1;
            }
        }
    }
    let segs = &mut segs[..n];
    segs.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
    for &(fa, fb, f) in segs.iter() {
        if fa - slack > v.bound() as f64 {
            continue;
        }
        if walk_face(cube, f, &FaceRay { p0: to_face(f, q0), pd: to_face(f, d) }, fa, fb, slack, v) {
            return true;
        }
    }
    false
}

/// The columns, then rows, of face `f` the ray crosses on `[fa, fb]`.
fn walk_face(cube: &Cube, f: usize, fr: &FaceRay, fa: f64, fb: f64, slack: f64, v: &mut impl Visitor) -> bool {
    let (c0, c1, asc, sure) = fr.cells(cube, 0, fa, fb);
    for step in 0..=(c1 - c0) {
        let i = if asc { c0 + step } else { c1 - step };
        let [lo, hi] = cube.slab_planes(0, i);
        let (ca, cb) = fr.clip(fa, fb, lo);
        let (ca, cb) = fr.clip(ca, cb, hi);
        if !(ca <= cb) {
            continue;
        }
        // Columns are entered in order: none after this one starts before the bound.
        if ca - slack > v.bound() as f64 {
            if sure {
                break;
            }
            continue;
        }
        let (r0, r1, rasc, rsure) = fr.cells(cube, 1, ca, cb);
        for rstep in 0..=(r1 - r0) {
            let j = if rasc { r0 + rstep } else { r1 - rstep };
            let [lo, hi] = cube.slab_planes(1, j);
            let (ra, rb) = fr.clip(ca, cb, lo);
            let (ra, rb) = fr.clip(ra, rb, hi);
            if !(ra <= rb) {
                continue;
            }
            if ra - slack > v.bound() as f64 {
                if rsure {
                    break;
                }
                continue;
            }
            let (wa, wb) = (fr.at(ra - slack).z, fr.at(rb + slack).z);
            if v.visit(cube.pixel(f, i, j), f32_down(wa.min(wb)), f32_up(wa.max(wb))) {
                return true;
            }
        }
    }
    false
}
