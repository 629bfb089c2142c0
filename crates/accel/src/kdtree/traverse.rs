//! The standard traversal: recursive front-to-back descent with an explicit stack
//! (Havran's TA_rec_B, as in Wald's thesis), exact against brute force.
//!
//! Exactness. A straddling triangle is referenced from every leaf it touches, so a hit
//! found in one leaf may lie beyond that leaf, where another triangle, closer or equal
//! with a lower index, may still wait in a later leaf. So a hit never ends the walk by
//! itself: a node is skipped only when its conservative entry distance is strictly
//! greater than the best `t` (DESIGN rule 3). Equal `t` keeps the node, and the
//! tie-break of `Hit::is_closer` decides. Split distances are widened by [`T_MARGIN`]
//! in the direction that visits more, never fewer, nodes.
//!
//! Zero direction components: the sign of `inv_dir` (±∞ for ±0) picks near and far
//! consistently, `(split - o)·(±∞)` sends the ray to the side holding its origin, and a
//! NaN (origin exactly on the plane, ray inside it) visits both children.

use super::params::MAX_DEPTH_LIMIT;
use super::tree::Tree;
use crate::Counter;
use dynray_geom::{Hit, PreparedRay};

/// Relative widening of split distances: twice the box test's 1e-6 (`Aabb::clip`), because
/// a split distance and a triangle's `t` both carry rounding.
pub const T_MARGIN: f32 = 2.0e-6;

/// Stack entries the traversal reserves: one per level of the deepest tree the builder
/// may produce (the builder never exceeds [`MAX_DEPTH_LIMIT`]; validate() checks).
pub const STACK_SIZE: usize = MAX_DEPTH_LIMIT as usize + 1;

/// `x` moved up by the relative margin (±∞ and 0 stay).
#[inline(always)]
pub fn up(x: f32) -> f32 {
    x * if x > 0.0 { 1.0 + T_MARGIN } else { 1.0 - T_MARGIN }
}

/// `x` moved down by the relative margin (±∞ and 0 stay).
#[inline(always)]
pub fn down(x: f32) -> f32 {
    x * if x > 0.0 { 1.0 - T_MARGIN } else { 1.0 + T_MARGIN }
}

/// A deferred far child and the part of the ray that may meet it.
#[derive(Clone, Copy, Default)]
struct Entry {
    node: u32,
    t_near: f32,
    t_far: f32,
}

impl Tree {
    /// Closest hit among the leaves the ray meets within `[t_near, t_far]` (already
    /// clipped to the root box), improving on `best`.
    pub fn intersect_stack<C: Counter>(
        &self,
        r: &PreparedRay,
        t_near: f32,
        t_far: f32,
        mut best: Hit,
        c: &mut C,
    ) -> Hit {
        debug_assert!((self.depth as usize) < STACK_SIZE, "depth {} exceeds the stack", self.depth);
        let mut stack = [Entry::default(); STACK_SIZE];
        let mut sp = 0;
        let (o, inv) = (r.ray.origin, r.inv_dir);
        let (mut node, mut tn, mut tf) = (0u32, t_near, t_far.min(best.t));
        loop {
            let mut n = self.nodes[node as usize];
            while !n.is_leaf() {
                c.node();
                let a = n.axis();
                let ts = (n.split() - o[a]) * inv[a];
                let (near, far) = if inv[a] > 0.0 { (node + 1, n.right()) } else { (n.right(), node + 1) };
                if ts.is_nan() {
                    // The ray lies in the split plane: both sides, same interval.
                    stack[sp] = Entry { node: far, t_near: tn, t_far: tf };
                    sp += 1;
                    node = near;
                } else if down(ts) > tf {
                    node = near;
                } else if up(ts) < tn {
                    node = far;
                } else {
                    stack[sp] = Entry { node: far, t_near: tn.max(down(ts)), t_far: tf };
                    sp += 1;
                    node = near;
                    tf = tf.min(up(ts));
                }
                n = self.nodes[node as usize];
            }
            c.node();
            let prims = self.leaf_prims(n.leaf_index());
            c.triangles(prims.len() as u32);
            best.closest_of(r, prims.iter().map(|&id| (&self.tris[id as usize], id)));
            // Next deferred node that the ray can still meet before (or at) the best hit.
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                let e = stack[sp];
                if e.t_near <= best.t {
                    (node, tn, tf) = (e.node, e.t_near, e.t_far.min(best.t));
                    break;
                }
            }
        }
    }

    /// True when some triangle is hit within `[t_near, t_far]`, the part of the ray
    /// inside the root box. Any hit in range is a valid occluder, wherever it lies, so no
    /// leaf-interval rule is needed and the first hit ends the walk.
    pub fn occluded_stack(&self, r: &PreparedRay, t_near: f32, t_far: f32) -> bool {
        let mut stack = [Entry::default(); STACK_SIZE];
        let mut sp = 0;
        let (o, inv) = (r.ray.origin, r.inv_dir);
        let (mut node, mut tn, mut tf) = (0u32, t_near, t_far);
        loop {
            let mut n = self.nodes[node as usize];
            while !n.is_leaf() {
                let a = n.axis();
                let ts = (n.split() - o[a]) * inv[a];
                let (near, far) = if inv[a] > 0.0 { (node + 1, n.right()) } else { (n.right(), node + 1) };
                if ts.is_nan() {
                    stack[sp] = Entry { node: far, t_near: tn, t_far: tf };
                    sp += 1;
                    node = near;
                } else if down(ts) > tf {
                    node = near;
                } else if up(ts) < tn {
                    node = far;
                } else {
                    stack[sp] = Entry { node: far, t_near: tn.max(down(ts)), t_far: tf };
                    sp += 1;
                    node = near;
                    tf = tf.min(up(ts));
                }
                n = self.nodes[node as usize];
            }
            let tmax = r.ray.tmax;
            if self.leaf_prims(n.leaf_index()).iter().any(|&id| self.tris[id as usize].intersect(r, tmax).is_some()) {
                return true;
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            (node, tn, tf) = (stack[sp].node, stack[sp].t_near, stack[sp].t_far);
        }
    }
}
