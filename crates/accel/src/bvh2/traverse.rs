//! Closest-hit and any-hit traversal: explicit stack, near child first, distance culling.

use super::{Bvh, BvhNode};
use crate::Counter;
use dynray_geom::{Hit, PreparedRay, Ray};
use glam::{Vec3A, Vec4};

/// The same slab widening as [`dynray_geom::Aabb::clip`] (the test
/// `box_test_matches_aabb_clip` checks both box tests agree).
use dynray_geom::SLAB_MARGIN;

/// Entries of the traversal stack. Near-first descent pushes at most one node per level,
/// so a tree of depth `d` needs `d` entries; builds never exceed
/// [`super::build::MAX_DEPTH`] and `validate` checks the measured depth against this.
pub(super) const STACK_CAPACITY: usize = 128;
const _: () = assert!((super::build::MAX_DEPTH as usize) < STACK_CAPACITY);
/// Stack of trees shallower than 32 (the bunny: 18, the 871k-triangle dragon: 25).
const SMALL_STACK: usize = 32;

/// A ray with what the box test needs, computed once: the origin and `1/dir` as SIMD
/// vectors (`Vec3A` is one SSE register; the scalar build of glam behaves the same).
struct BoxRay {
    org: Vec3A,
    inv: Vec3A,
}

impl BoxRay {
    fn new(r: &PreparedRay) -> Self {
        Self { org: r.ray.origin.into(), inv: r.inv_dir.into() }
    }

    /// The box test of [`dynray_geom::Aabb::clip`], with the same result (the test
    /// `box_test_matches_aabb_clip`; -0 and +0 may differ): whether the ray's `[tmin, limit]` meets the node's
    /// box, and the widened entry distance.
    ///
    /// Each half of the node (`min, index` and `max, count`) is one 16-byte load; the
    /// fourth lane is ignored by `max_element`/`min_element`. A slab distance that is NaN
    /// (origin on the slab's plane, ray parallel to it) must leave the ray unconstrained:
    /// `x.max(-∞)` turns NaN into -∞ (SSE `maxps` returns its second operand on NaN,
    /// `f32::max` the non-NaN one) and `x.min(∞)` into +∞, which the min/max then ignore.
    #[inline(always)]
    fn clip(&self, node: &BvhNode, tmin: f32, limit: f32) -> (bool, f32) {
        let f: &[f32; 8] = bytemuck::cast_ref(node);
        let lo = Vec3A::from_vec4(Vec4::from_slice(&f[0..4]));
        let hi = Vec3A::from_vec4(Vec4::from_slice(&f[4..8]));
        let t0 = (lo - self.org) * self.inv;
        let t1 = (hi - self.org) * self.inv;
        let (ninf, pinf) = (Vec3A::NEG_INFINITY, Vec3A::INFINITY);
        let near = t0.max(ninf).min(t1.max(ninf)).max_element();
        let far = t0.min(pinf).max(t1.min(pinf)).min_element();
        // Widen outwards exactly as `Aabb::clip` does, then clamp to the interval.
        let near = near * if near > 0.0 { 1.0 - SLAB_MARGIN } else { 1.0 + SLAB_MARGIN };
        let far = far * if far > 0.0 { 1.0 + SLAB_MARGIN } else { 1.0 - SLAB_MARGIN };
        // Written as selects (one maxss/minss each); a NaN `tmin`/`limit` is ignored, as
        // `f32::max`/`min` in `clip` ignore it.
        let near = if tmin > near { tmin } else { near };
        let far = if limit < far { limit } else { far };
        (near <= far, near)
    }
}

/// A deferred node and the entry distance it had when it was pushed.
#[derive(Clone, Copy, Default)]
struct Entry {
    node: u32,
    t: f32,
}

impl Bvh {
    /// Closest hit, counting work into `c`, with a stack sized for the tree's depth.
    #[inline]
    pub(super) fn traverse<C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        // A 32-entry stack is 256 bytes to clear per ray instead of 1 KiB.
        if (self.depth as usize) < SMALL_STACK {
            self.traverse_with::<C, SMALL_STACK>(ray, c)
        } else {
            self.traverse_with::<C, STACK_CAPACITY>(ray, c)
        }
    }

    /// Any hit in `[tmin, tmax]`, with a stack sized for the tree's depth.
    #[inline]
    pub(super) fn any_hit<C: Counter>(&self, ray: &Ray, c: &mut C) -> bool {
        if (self.depth as usize) < SMALL_STACK {
            self.any_hit_with::<C, SMALL_STACK>(ray, c)
        } else {
            self.any_hit_with::<C, STACK_CAPACITY>(ray, c)
        }
    }

    /// Closest hit with an `N`-entry stack (`N` > the tree's depth).
    #[inline(always)]
    fn traverse_with<C: Counter, const N: usize>(&self, ray: &Ray, c: &mut C) -> Hit {
        let pr = PreparedRay::new(ray);
        let br = BoxRay::new(&pr);
        let (tmin, tmax) = (ray.tmin, ray.tmax);
        let nodes = &self.nodes[..];
        let mut best = Hit::MISS;
        if !br.clip(&nodes[0], tmin, tmax).0 {
            return best;
        }
        let mut stack = [Entry::default(); N];
        let mut sp = 0usize;
        let mut node = &nodes[0];
        loop {
            c.node();
            if node.is_leaf() {
                let (first, count) = (node.index as usize, node.count as usize);
                c.triangles(count as u32);
                // `tmax` is `ray.tmax`, the helper's own bound.
                best.closest_of(
                    &pr,
                    self.tris[first..first + count].iter().zip(self.ids[first..first + count].iter().copied()),
                );
            } else {
                let l = node.index as usize;
                // Cull only boxes entered after the best hit: `limit` = best.t keeps a box
                // entered exactly at best.t (a lower-index triangle may tie there).
                let limit = best.t.min(tmax);
                let (hl, tl) = br.clip(&nodes[l], tmin, limit);
                let (hr, tr) = br.clip(&nodes[l + 1], tmin, limit);
                match (hl, hr) {
                    (true, true) => {
                        let (near, far, tfar) = if tr < tl { (l + 1, l, tl) } else { (l, l + 1, tr) };
                        stack[sp] = Entry { node: far as u32, t: tfar };
                        sp += 1;
                        node = &nodes[near];
                        continue;
                    }
                    (true, false) => {
                        node = &nodes[l];
                        continue;
                    }
                    (false, true) => {
                        node = &nodes[l + 1];
                        continue;
                    }
                    (false, false) => {}
                }
            }
            // Pop the next node still entered no later than the best hit.
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                let e = stack[sp];
                if e.t <= best.t {
                    node = &nodes[e.node as usize];
                    break;
                }
            }
        }
    }

    /// Any hit with an `N`-entry stack: returns at the first triangle accepted.
    #[inline(always)]
    fn any_hit_with<C: Counter, const N: usize>(&self, ray: &Ray, c: &mut C) -> bool {
        let pr = PreparedRay::new(ray);
        let br = BoxRay::new(&pr);
        let (tmin, tmax) = (ray.tmin, ray.tmax);
        let nodes = &self.nodes[..];
        if !br.clip(&nodes[0], tmin, tmax).0 {
            return false;
        }
        let mut stack = [0u32; N];
        let mut sp = 0usize;
        let mut node = &nodes[0];
        loop {
            c.node();
            if node.is_leaf() {
                let (first, count) = (node.index as usize, node.count as usize);
                c.triangles(count as u32);
                if self.tris[first..first + count].iter().any(|t| t.intersect(&pr, tmax).is_some()) {
                    return true;
                }
            } else {
                let l = node.index as usize;
                let (hl, tl) = br.clip(&nodes[l], tmin, tmax);
                let (hr, tr) = br.clip(&nodes[l + 1], tmin, tmax);
                match (hl, hr) {
                    (true, true) => {
                        let (near, far) = if tr < tl { (l + 1, l) } else { (l, l + 1) };
                        stack[sp] = far as u32;
                        sp += 1;
                        node = &nodes[near];
                        continue;
                    }
                    (true, false) => {
                        node = &nodes[l];
                        continue;
                    }
                    (false, true) => {
                        node = &nodes[l + 1];
                        continue;
                    }
                    (false, false) => {}
                }
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            node = &nodes[stack[sp] as usize];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_geom::{Aabb, Vec3};
    use rand::{rngs::SmallRng, Rng, SeedableRng};

    /// The fast box test is a re-statement of `Aabb::clip` (the specification): both must
    /// accept the same rays and give the same entry distance, including rays with zero
    /// direction components starting on a box plane.
    #[test]
    fn box_test_matches_aabb_clip() {
        let mut rng = SmallRng::seed_from_u64(5);
        let grid = |rng: &mut SmallRng| {
            Vec3::new(rng.gen_range(-3..=3) as f32, rng.gen_range(-3..=3) as f32, rng.gen_range(-3..=3) as f32)
        };
        for i in 0..200_000 {
            let (a, b) = (grid(&mut rng), grid(&mut rng));
            let bx = Aabb::new(a.min(b), a.max(b));
            let node = BvhNode::leaf(&bx, 0, 1);
            // Half the rays use grid points and axis directions, so NaN slabs occur.
            let (o, d) = if i % 2 == 0 {
                let mut d = grid(&mut rng);
                if d == Vec3::ZERO {
                    d = Vec3::X;
                }
                (grid(&mut rng), d)
            } else {
                let v = |rng: &mut SmallRng| {
                    Vec3::new(rng.gen_range(-4.0..4.0), rng.gen_range(-4.0..4.0), rng.gen_range(-4.0..4.0))
                };
                (v(&mut rng), v(&mut rng))
            };
            let tmin = [0.0, -1.0, f32::NEG_INFINITY, 0.5][i % 4];
            let tmax = [f32::INFINITY, 1.0, 3.0, 0.25][(i / 4) % 4];
            let pr = PreparedRay::new(&Ray::with_interval(o, d, tmin, tmax));
            let want = bx.clip(&pr, tmin, tmax);
            let (hit, near) = BoxRay::new(&pr).clip(&node, tmin, tmax);
            assert_eq!(hit, want.is_some(), "box {bx:?} ray {o} {d} [{tmin}, {tmax}]");
            if let Some((n, _)) = want {
                // Equal as numbers: the SSE max may return -0 where `f32::max` returns +0;
                // the entry distance is only ever compared, never reported.
                assert_eq!(near, n, "box {bx:?} ray {o} {d}");
            }
        }
    }
}
