//! The seed's traversal: enter through the cube map (or by point location when the ray
//! starts inside the root cube), then walk leaf to leaf along the neighbour links, the
//! exit face chosen by three Plücker tests at the exit vertex (Eq. 8) and, across a face
//! with four neighbours, the neighbour by two Plücker tests at the face centre (Eq. 9).
//!
//! What the seed leaves out and correctness needs:
//! - Triangles are listed in every leaf they touch, so a hit found in a leaf may lie
//!   beyond the leaf's exit. The walk keeps the closest hit and stops only once it is
//!   closer than the next leaf's entry (`limit < lower(t_exit)`), never on equality: a
//!   triangle in a later leaf at exactly the same `t` with a lower index must still win.
//! - Rays that start inside the root cube (every secondary ray) begin with point location.
//! - On an exact edge or corner the Plücker signs can be zero. The Plücker face is taken
//!   only when its slab distance is the leaf's exit distance; otherwise the slab decides.
//!   On the bunny about 1 % of leaf steps of camera rays fall back, all of them rays with
//!   a zero direction component whose origin lies exactly on a leaf plane (two of the
//!   three side values are exactly 0, giving the unreachable code 000).
//!   The Plücker neighbour slot is taken only when the exit point lies in that quarter of
//!   the face (within a 2^-12 leaf-size tolerance); otherwise the exit point decides.
//!   Either way a wrong choice can only happen within rounding of an edge, and the
//!   builder widens every leaf by far more than that rounding, so the leaf the walk
//!   enters lists every triangle the ray meets in the cell it skirted.
//! - The walk is bounded (`6·2^depth + 64` leaves; a monotone walk crosses at most
//!   `3·2^depth` fine planes); past the bound the top-down descent answers instead.
//! - Faces marked `LOCATE` (unbalanced trees, more than four neighbours) are crossed by
//!   point location of the exit point, clamped to the face so it lands in a real neighbour.

use super::node::{links_before, nibble, LeafBox, LEAF_BIT, LOCATE, REC_LEAF, REC_N_COUNT, REC_T_COUNT, REC_T_OFFSET};
use super::tables::{
    exit_vertex, in_face_axes, plucker_code, FACE_AXIS, FACE_OF, FACE_POSITIVE, FACE_TO_NEIGHBOR_INDEX,
    OUT_FACES_LOOKUP,
};
use super::Octree;
use crate::rebase::{cull, Rebased};
use crate::Counter;
use dynray_geom::{Hit, PreparedRay, Ray};
use glam::Vec3;

/// Relative margin on distances compared with hit `t`s: the value of `dynray_geom`'s
/// slab-test margin (≈ 8 ulps), which covers the rounding of the triangle test's `t`.
const MARGIN: f32 = 1.0e-6;

/// `x` lowered by the slab margin: a lower bound of every hit distance beyond `x`.
#[inline(always)]
pub(super) fn lower(x: f32) -> f32 {
    x * if x > 0.0 { 1.0 - MARGIN } else { 1.0 + MARGIN }
}

impl Octree {
    /// Tests the triangles of the leaf at record `addr`; with `ANY`, true on the first hit.
    #[inline(always)]
    pub(super) fn test_leaf<C: Counter, const ANY: bool>(
        &self,
        addr: usize,
        r: &PreparedRay,
        best: &mut Hit,
        c: &mut C,
    ) -> bool {
        let count = self.records[addr + REC_T_COUNT] as usize;
        let first = self.records[addr + REC_T_OFFSET] as usize;
        c.triangles(count as u32);
        for k in first..first + count {
            if let Some((t, u, v)) = self.tris[k].intersect(r, best.t.min(r.ray.tmax)) {
                let prim = self.prim_ids[k];
                if Hit::is_closer(t, prim, best) {
                    *best = Hit { t, u, v, prim };
                }
                if ANY {
                    return true;
                }
            }
        }
        false
    }

    /// Closest hit (or, with `ANY`, any hit) by the neighbour walk.
    pub(super) fn walk<C: Counter, const ANY: bool>(&self, ray: &Ray, c: &mut C) -> Hit {
        // A zero or NaN direction hits nothing (the triangle test divides by it).
        if ray.dir.is_nan() || ray.dir == Vec3::ZERO {
            return Hit::MISS;
        }
        let r = PreparedRay::new(ray);
        // Leaves are walked from near the root cube for a far origin (rebase.rs);
        // triangles are tested against the ray as given.
        let rebased = Rebased::new(ray, &self.root_box);
        let w = rebased.as_ref().map(|b| PreparedRay::new(&b.ray));
        let w = w.as_ref().unwrap_or(&r);
        let (o, d) = (w.ray.origin, w.ray.dir);
        if self.root_box.clip(w, w.ray.tmin, w.ray.tmax).is_none() {
            return Hit::MISS;
        }
        let mut addr = self.start(w);
        let v = exit_vertex(d);
        let mut best = Hit::MISS;
        let max_steps = 6usize << self.fine_depth;
        for _ in 0..max_steps + 64 {
            c.node();
            if self.test_leaf::<C, ANY>(addr, &r, &mut best, c) {
                return best;
            }
            let b = &self.boxes[self.records[addr + REC_LEAF] as usize];
            let far = Vec3::select(d.cmpgt(Vec3::ZERO), b.max, b.min);
            let ts = (far - o) * w.inv_dir;
            let ax_t = [0, 1, 2].map(|a| if d[a] != 0.0 { ts[a] } else { f32::INFINITY });
            let t_exit = ax_t[0].min(ax_t[1]).min(ax_t[2]);
            // Everything in later leaves lies at t >= t_exit (up to rounding).
            if cull(&rebased, best.t.min(ray.tmax)) < lower(t_exit) || !t_exit.is_finite() {
                return best;
            }
            let face = {
                let fp = OUT_FACES_LOOKUP[v][plucker_code(far, o, d)] as usize;
                if fp < 6 && ax_t[FACE_AXIS[fp]] == t_exit {
                    fp
                } else {
                    let a = if ax_t[0] == t_exit {
                        0
                    } else if ax_t[1] == t_exit {
                        1
                    } else {
                        2
                    };
                    FACE_OF[a][(d[a] > 0.0) as usize]
                }
            };
            let n_count = self.records[addr + REC_N_COUNT];
            let base = addr + 4 + links_before(n_count, face);
            addr = match nibble(n_count, face) {
                0 => return best,
                1 => self.records[base] as usize,
                LOCATE => self.locate_across(b, face, o + d * t_exit),
                _ => self.records[base + self.neighbor_slot(b, face, o, d, t_exit)] as usize,
            };
        }
        // Unreachable in practice (see the module note); answer correctly regardless.
        self.descend::<C, ANY>(ray, c)
    }

    /// Which of the four neighbours across `face` the ray enters (Eq. 9, checked).
    #[inline(always)]
    fn neighbor_slot(&self, b: &LeafBox, face: usize, o: Vec3, d: Vec3, t_exit: f32) -> usize {
        let a = FACE_AXIS[face];
        let mut centre = (b.min + b.max) * 0.5;
        centre[a] = if FACE_POSITIVE[face] { b.max[a] } else { b.min[a] };
        let j = FACE_TO_NEIGHBOR_INDEX[face][plucker_code(centre, o, d)] as usize;
        let p = o + d * t_exit;
        let (u, w) = in_face_axes(face);
        let tol = (b.max[u] - b.min[u]) * (1.0 / 4096.0);
        let agrees =
            |axis: usize, upper: bool| (p[axis] > centre[axis]) == upper || (p[axis] - centre[axis]).abs() <= tol;
        if agrees(u, j & 1 == 0) && agrees(w, j & 2 == 0) {
            j
        } else {
            (p[u] <= centre[u]) as usize + 2 * (p[w] <= centre[w]) as usize
        }
    }

    /// Record address of the first leaf: through the cube map when the ray enters the root
    /// cube after its start, else by point location of the start point.
    fn start(&self, r: &PreparedRay) -> usize {
        let (o, d, ray) = (r.ray.origin, r.ray.dir, &r.ray);
        let near = Vec3::select(d.cmpgt(Vec3::ZERO), self.root_box.min, self.root_box.max);
        let ts = (near - o) * r.inv_dir;
        let ax_t = [0, 1, 2].map(|a| if d[a] != 0.0 { ts[a] } else { f32::NEG_INFINITY });
        let t_enter = ax_t[0].max(ax_t[1]).max(ax_t[2]);
        if t_enter > ray.tmin {
            let a = if ax_t[0] == t_enter {
                0
            } else if ax_t[1] == t_enter {
                1
            } else {
                2
            };
            let face = FACE_OF[a][(d[a] < 0.0) as usize];
            let p = o + d * t_enter;
            let res = 1u32 << self.cube_depth;
            let (u, w) = in_face_axes(face);
            let scale = res as f32 / self.frame.size;
            let q = |axis: usize| texel((p[axis] - self.frame.min[axis]) * scale, 0, res - 1) as usize;
            let res = res as usize;
            self.cube_map[face * res * res + q(w) * res + q(u)] as usize
        } else {
            let p = o + d * ray.tmin;
            let res = 1u32 << self.fine_depth;
            let scale = res as f32 / self.frame.size;
            let q = |axis: usize| texel((p[axis] - self.frame.min[axis]) * scale, 0, res - 1);
            self.locate([q(0), q(1), q(2)])
        }
    }

    /// Record address of the leaf holding the finest-level cell `q`.
    #[inline]
    pub(super) fn locate(&self, q: [u32; 3]) -> usize {
        let mut node = self.root;
        let mut shift = self.fine_depth;
        while node & LEAF_BIT == 0 {
            shift -= 1;
            let o = (q[0] >> shift & 1) | (q[1] >> shift & 1) << 1 | (q[2] >> shift & 1) << 2;
            node = self.inner[node as usize].child[o as usize];
        }
        (node & !LEAF_BIT) as usize
    }

    /// The leaf across `face` of leaf `b` that holds the exit point `p`, with `p` clamped
    /// to the face so that rounding can never pick a leaf that is not adjacent.
    fn locate_across(&self, b: &LeafBox, face: usize, p: Vec3) -> usize {
        let shift = self.fine_depth - b.depth();
        let scale = (1u32 << self.fine_depth) as f32 / self.frame.size;
        let a = FACE_AXIS[face];
        let q = std::array::from_fn(|axis| {
            let lo = (b.cell[axis] as u32) << shift;
            let hi = lo + (1 << shift);
            if axis == a {
                if FACE_POSITIVE[face] {
                    hi
                } else {
                    lo - 1
                }
            } else {
                texel((p[axis] - self.frame.min[axis]) * scale, lo, hi - 1)
            }
        });
        self.locate(q)
    }
}

/// `floor(x)` clamped to `[lo, hi]`; NaN goes to `lo`.
#[inline(always)]
fn texel(x: f32, lo: u32, hi: u32) -> u32 {
    (x.floor() as i64).clamp(lo as i64, hi as i64) as u32
}
