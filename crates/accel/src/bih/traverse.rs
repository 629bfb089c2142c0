//! BIH traversal (seed 000 §2.4, Wächter & Keller §3.3): clip the ray to the scene box,
//! then walk down, narrowing the ray's interval at each pair of clip planes.
//!
//! At an interior node the ray's interval `[t0, t1]` is cut by the two planes: the near
//! child keeps `[t0, min(t1, exit)]`, the far child `[max(t0, entry), t1]`, where `exit`
//! is where the ray leaves the near child's half-space and `entry` where it enters the
//! far child's. An empty interval is the gap between the children and is skipped. One
//! child only: jump to it, no push. Both: push the far one, descend into the near one.
//! A popped entry is culled only when its start is *greater* than the best hit, so a
//! triangle at exactly `best.t` with a lower index still gets its chance.

use super::node::BihNode;
use super::params::MAX_DEPTH_LIMIT;
use super::Bih;
use crate::Counter;
use dynray_geom::{Hit, PreparedRay, Ray};

/// Relative widening of the plane distances, the slab test's: the clip planes are box
/// faces, and a plane distance must never exclude a `t` the watertight triangle test
/// returns for a triangle on its side. See `dynray_geom::Aabb::clip` for the derivation.
const PLANE_MARGIN: f32 = dynray_geom::SLAB_MARGIN;

/// Traversal stack capacity: one entry per level suffices (see [`MAX_DEPTH_LIMIT`]);
/// `validate` checks every built tree against it.
pub(super) const STACK: usize = MAX_DEPTH_LIMIT as usize;

/// A plane distance moved towards +∞ by the margin (upper ends of intervals). NaN (ray
/// in the plane, parallel to it) stays NaN, and `f32::min`/`max` then ignore it, which
/// counts the ray as inside the closed half-space, as `Aabb::clip` does.
#[inline(always)]
fn widen_up(t: f32) -> f32 {
    t * if t > 0.0 { 1.0 + PLANE_MARGIN } else { 1.0 - PLANE_MARGIN }
}

/// A plane distance moved towards −∞ by the margin (lower ends of intervals).
#[inline(always)]
fn widen_down(t: f32) -> f32 {
    t * if t > 0.0 { 1.0 - PLANE_MARGIN } else { 1.0 + PLANE_MARGIN }
}

#[derive(Clone, Copy, Default)]
struct Entry {
    node: u32,
    t0: f32,
    t1: f32,
}

impl Bih {
    /// Walks every leaf the ray's interval reaches, nearest first along each branch.
    /// `leaf(first, count)` tests a leaf's triangles and returns the cull distance (the
    /// best hit so far), or `None` to stop at once (any-hit found).
    #[inline(always)]
    fn walk<C: Counter>(&self, r: &PreparedRay, c: &mut C, mut leaf: impl FnMut(usize, usize) -> Option<f32>) {
        let ray = &r.ray;
        let Some((mut t0, mut t1)) = self.bounds.clip(r, ray.tmin, ray.tmax) else {
            return;
        };
        let nodes = &self.nodes[..];
        let mut stack = [Entry::default(); STACK];
        let mut sp = 0usize;
        let mut cull = f32::INFINITY;
        let mut node = 0u32;
        loop {
            c.node();
            let n: BihNode = nodes[node as usize];
            if n.is_leaf() {
                c.triangles(n.count);
                match leaf(n.index() as usize, n.count as usize) {
                    Some(t) => cull = t,
                    None => return,
                }
            } else {
                let a = n.axis();
                let (o, inv) = (ray.origin[a], r.inv_dir[a]);
                let dl = (n.clip[0] - o) * inv;
                let dr = (n.clip[1] - o) * inv;
                // The sign of 1/d, not of d, picks the order: d = -0 gives 1/d = -∞ and
                // must be walked as a negative direction for the infinities to be right.
                let (near, far, exit, entry) = if inv.is_sign_negative() {
                    (n.index(), node + 1, widen_up(dr), widen_down(dl))
                } else {
                    (node + 1, n.index(), widen_up(dl), widen_down(dr))
                };
                let near_t1 = t1.min(exit);
                let far_t0 = t0.max(entry);
                let go_near = t0 <= near_t1;
                let go_far = far_t0 <= t1 && far_t0 <= cull;
                if go_near {
                    if go_far {
                        debug_assert!(sp < STACK, "BIH stack overflow at depth > {STACK}");
                        stack[sp] = Entry { node: far, t0: far_t0, t1 };
                        sp += 1;
                    }
                    node = near;
                    t1 = near_t1;
                    continue;
                } else if go_far {
                    node = far;
                    t0 = far_t0;
                    continue;
                }
            }
            // Pop the next entry that could still hold something at or before `cull`.
            loop {
                if sp == 0 {
                    return;
                }
                sp -= 1;
                let e = stack[sp];
                if e.t0 <= cull {
                    (node, t0, t1) = (e.node, e.t0, e.t1);
                    break;
                }
            }
        }
    }

    /// Closest hit, identical to brute force.
    pub(super) fn closest<C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        let r = PreparedRay::new(ray);
        let mut best = Hit::MISS;
        self.walk(&r, c, |first, count| {
            let tris = &self.tris[first..first + count];
            let ids = &self.prim_ids[first..first + count];
            best.closest_of(&r, tris.iter().zip(ids.iter().copied()));
            Some(best.t)
        });
        best
    }

    /// Any hit in `[tmin, tmax]`, stopping at the first.
    pub(super) fn any<C: Counter>(&self, ray: &Ray, c: &mut C) -> bool {
        let r = PreparedRay::new(ray);
        let mut found = false;
        self.walk(&r, c, |first, count| {
            found = self.tris[first..first + count].iter().any(|t| t.intersect(&r, ray.tmax).is_some());
            if found {
                None
            } else {
                Some(f32::INFINITY)
            }
        });
        found
    }
}
