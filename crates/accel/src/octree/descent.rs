//! The classic top-down octree walk (Revelles, Ureña, Lastra, WSCG 2000), over the same
//! leaves as the neighbour walk, through the internal-node array.
//!
//! Each internal node on the stack holds the ray's interval `[t0, t1]` inside it and the
//! distances where the ray crosses the node's three mid-planes. Sorting the crossings that
//! fall inside `(t0, t1)` gives the children in ray order with their sub-intervals, the
//! same sequence Revelles' state table produces, but without the table's mirroring trick
//! and with zero direction components handled directly (no crossing; the side is the
//! origin's). Children are visited front to back and the walk stops as soon as the best
//! hit is closer than the next child's entry.

use super::node::LEAF_BIT;
use super::params::MAX_DEPTH_LIMIT;
use super::walk::lower;
use super::Octree;
use crate::rebase::{cull, Rebased};
use crate::Counter;
use dynray_geom::{Hit, PreparedRay, Ray};
use glam::Vec3;

/// One internal node being walked.
#[derive(Clone, Copy, Default)]
struct Frame {
    node: u32,
    lo: Vec3,
    hi: Vec3,
    /// Interval of the ray inside the node.
    t0: f32,
    t1: f32,
    /// Mid-plane crossings inside `(t0, t1)`, ascending, and the axis each one flips.
    ev: [f32; 3],
    ax: [u8; 3],
    n_ev: u8,
    /// Index of the next child segment (0..=n_ev).
    next: u8,
    /// Octant of the next child segment.
    bits: u8,
}

impl Frame {
    fn new(node: u32, lo: Vec3, hi: Vec3, t0: f32, t1: f32, r: &PreparedRay) -> Self {
        let (o, d) = (r.ray.origin, r.ray.dir);
        let mid = (lo + hi) * 0.5;
        let mut f = Frame { node, lo, hi, t0, t1, ..Default::default() };
        for a in 0..3 {
            let upper = if d[a] == 0.0 {
                o[a] >= mid[a]
            } else {
                let tm = (mid[a] - o[a]) * r.inv_dir[a];
                if t0 < tm && tm < t1 {
                    f.ev[f.n_ev as usize] = tm;
                    f.ax[f.n_ev as usize] = a as u8;
                    f.n_ev += 1;
                }
                // Which side the ray is on at t0: past the mid-plane iff it crossed it.
                (tm <= t0) == (d[a] > 0.0)
            };
            f.bits |= (upper as u8) << a;
        }
        // Insertion sort of at most three crossings.
        for i in 1..f.n_ev as usize {
            let mut j = i;
            while j > 0 && f.ev[j - 1] > f.ev[j] {
                f.ev.swap(j - 1, j);
                f.ax.swap(j - 1, j);
                j -= 1;
            }
        }
        f
    }
}

impl Octree {
    /// Closest hit (or, with `ANY`, any hit) by top-down descent.
    pub(super) fn descend<C: Counter, const ANY: bool>(&self, ray: &Ray, c: &mut C) -> Hit {
        // A zero or NaN direction hits nothing (the triangle test divides by it).
        if ray.dir.is_nan() || ray.dir == Vec3::ZERO {
            return Hit::MISS;
        }
        let r = PreparedRay::new(ray);
        // Nodes are split from near the root cube for a far origin (rebase.rs);
        // triangles are tested against the ray as given.
        let rebased = Rebased::new(ray, &self.root_box);
        let w = rebased.as_ref().map(|b| PreparedRay::new(&b.ray));
        let w = w.as_ref().unwrap_or(&r);
        let Some((t0, t1)) = self.root_box.clip(w, w.ray.tmin, w.ray.tmax) else { return Hit::MISS };
        let mut best = Hit::MISS;
        if self.root & LEAF_BIT != 0 {
            c.node();
            self.test_leaf::<C, ANY>((self.root & !LEAF_BIT) as usize, &r, &mut best, c);
            return best;
        }
        // Internal nodes are at depths 0..fine_depth, at most MAX_DEPTH_LIMIT of them on a
        // path (validate() checks the tree's depth against the same limit).
        let mut stack = [Frame::default(); MAX_DEPTH_LIMIT as usize];
        stack[0] = Frame::new(self.root, self.root_box.min, self.root_box.max, t0, t1, w);
        let mut sp = 1;
        c.node();
        while sp > 0 {
            let f = &mut stack[sp - 1];
            if f.next > f.n_ev {
                sp -= 1;
                continue;
            }
            let i = f.next as usize;
            let a = if i == 0 { f.t0 } else { f.ev[i - 1] };
            let b = if i == f.n_ev as usize { f.t1 } else { f.ev[i] };
            let oct = f.bits as usize;
            if i < f.n_ev as usize {
                f.bits ^= 1 << f.ax[i];
            }
            f.next += 1;
            // Children come in ray order: nothing from here on can beat the best hit.
            if cull(&rebased, best.t.min(ray.tmax)) < lower(a) {
                break;
            }
            let child = self.inner[f.node as usize].child[oct];
            c.node();
            if child & LEAF_BIT != 0 {
                if self.test_leaf::<C, ANY>((child & !LEAF_BIT) as usize, &r, &mut best, c) {
                    return best;
                }
            } else {
                let mid = (f.lo + f.hi) * 0.5;
                let up = glam::BVec3::new(oct & 1 != 0, oct & 2 != 0, oct & 4 != 0);
                let lo = Vec3::select(up, mid, f.lo);
                let hi = Vec3::select(up, f.hi, mid);
                debug_assert!(sp < stack.len(), "tree deeper than MAX_DEPTH_LIMIT");
                stack[sp] = Frame::new(child, lo, hi, a, b, w);
                sp += 1;
            }
        }
        best
    }
}
