//! Packets: up to 8 rays with one origin (camera rays of neighbouring pixels) traced
//! together through the wide tree, after Embree's hybrid traversal
//! (`bvh_intersector_hybrid.cpp`, `node_intersector_frustum.h`).
//!
//! Per node, one conservative frustum test of all children against the whole packet
//! ([`PacketKernel::frustum`]); then, for each child the frustum accepts, the single-ray
//! box test lane by lane, each lane with its own closest `t` ([`PacketKernel::lanes`]).
//! A child is visited when a lane enters it, with the mask of those lanes, and a leaf
//! runs the single-ray block kernel for each of them.
//!
//! Why every lane's answer is its single-ray answer, bit for bit: the closest hit is the
//! smallest `(t, triangle)` among the triangles tested, whatever their order, and `u`, `v`
//! are those of that triangle for that ray. A lane tests the leaf of its true closest
//! triangle because it enters every box on the way there exactly as the single ray would
//! (the same operations on the same numbers, against a limit that is never below that
//! triangle's `t`), and the frustum test only ever accepts more than the lanes do (the
//! proof is at [`Frustum`]). Rays that are not packet material (another origin, a NaN, a
//! non-finite origin) are traced alone.
//!
//! The scalar implementation here is the specification; `packet_avx2.rs` computes the
//! same masks eight lanes at a time, and `packet_tests.rs` holds both to `Aabb::clip`
//! and to each other.

use super::kernel::{Kernel, Nears, Scalar};
use super::node::{is_leaf, leaf_blocks, ChildRef, WideNode};
use super::WideTree;
use dynray_geom::{Hit, PreparedRay, Ray, SLAB_MARGIN};

/// Rays per packet (the f32 lanes of one AVX2 register).
pub const PACKET: usize = 8;

/// Per-lane values of a packet, one `f32` per lane.
pub type Lanes = [f32; PACKET];

/// The rays of a packet in SoA order: what the box tests read.
#[derive(Clone, Copy, Debug)]
pub struct Packet {
    /// The origin every lane shares.
    pub org: [f32; 3],
    /// `1 / dir` per axis and lane, as `BoxRay::new` computes it.
    pub inv: [Lanes; 3],
    /// Interval start per lane; lanes outside [`Packet::active`] hold `+∞`.
    pub tmin: Lanes,
    /// Interval end per lane; lanes outside [`Packet::active`] hold `−∞`.
    pub tmax: Lanes,
    /// Lanes holding a ray.
    pub active: u32,
}

impl Packet {
    /// The packet of the lanes of `rays` (at most 8) that can travel together: those whose
    /// origin has lane 0's bits (finite), with no NaN in direction or interval. The others
    /// stay out of [`Packet::active`] for the caller to trace alone.
    pub fn new(rays: &[Ray]) -> Self {
        assert!(rays.len() <= PACKET, "a packet holds at most {PACKET} rays, not {}", rays.len());
        let mut p = Packet {
            org: [0.0; 3],
            inv: [[1.0; PACKET]; 3],
            tmin: [f32::INFINITY; PACKET],
            tmax: [f32::NEG_INFINITY; PACKET],
            active: 0,
        };
        let Some(first) = rays.first() else { return p };
        if !first.origin.is_finite() {
            return p;
        }
        p.org = first.origin.to_array();
        let bits = first.origin.to_array().map(f32::to_bits);
        for (l, r) in rays.iter().enumerate() {
            let fits = r.origin.to_array().map(f32::to_bits) == bits
                && !r.dir.is_nan()
                && !r.tmin.is_nan()
                && !r.tmax.is_nan();
            if fits {
                let inv = dynray_geom::Vec3::ONE / r.dir;
                for a in 0..3 {
                    p.inv[a][l] = inv[a];
                }
                p.tmin[l] = r.tmin;
                p.tmax[l] = r.tmax;
                p.active |= 1 << l;
            }
        }
        p
    }
}

/// The packet as one shape: the shared origin, per axis the range of the lanes'
/// reciprocal directions, the smallest `tmin` and the largest current limit.
///
/// Why it accepts every child a lane accepts. On an axis whose lanes all have a finite
/// `1/d` of one sign, a lane's entry distance into a slab is `fl(n − o) · inv` for the
/// plane `n` it enters through (the lower plane for `inv > 0`, the upper for `inv < 0`,
/// because `lo <= hi`), and rounded multiplication is monotonic in `inv`; so the
/// smallest over the lanes is `fl(n − o) · inv_min` or `fl(n − o) · inv_max`, whichever
/// is smaller, and likewise the largest exit distance. Other axes (mixed signs, a zero
/// or infinite `1/d`) bound nothing (`−∞ .. +∞`). The widening of `Aabb::clip` is
/// monotonic too, and the frustum's `[tmin, limit]` holds every lane's, so a lane with
/// `near <= far` makes the frustum's `near <= far` true. No NaN can arise: boxes are
/// finite (meshes are), the origin is finite, and a bounded axis has finite, non-zero
/// `inv`. `packet_tests.rs` checks the superset on adversarial packets.
#[derive(Clone, Copy, Debug)]
pub struct Frustum {
    /// The shared origin.
    pub org: [f32; 3],
    /// Per axis: `1` when every lane's `inv` is finite and positive, `-1` when finite and
    /// negative, `0` when the axis bounds nothing.
    pub sign: [i32; 3],
    /// Per axis, the smallest lane `inv` (bounded axes only).
    pub inv_min: [f32; 3],
    /// Per axis, the largest lane `inv` (bounded axes only).
    pub inv_max: [f32; 3],
    /// The smallest `tmin` of the active lanes.
    pub tmin: f32,
    /// The largest limit (`min(best t, tmax)`) of the lanes it is tested for.
    pub limit: f32,
}

impl Frustum {
    /// The frustum of `p`'s active lanes with per-lane limits `limit`.
    pub fn new(p: &Packet, limit: &Lanes) -> Self {
        let mut f = Frustum {
            org: p.org,
            sign: [0; 3],
            inv_min: [0.0; 3],
            inv_max: [0.0; 3],
            tmin: f32::INFINITY,
            limit: f32::NEG_INFINITY,
        };
        for a in 0..3 {
            let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
            let (mut pos, mut neg) = (true, true);
            for l in lanes(p.active) {
                let x = p.inv[a][l];
                pos &= x > 0.0 && x.is_finite();
                neg &= x < 0.0 && x.is_finite();
                lo = lo.min(x);
                hi = hi.max(x);
            }
            if p.active != 0 && (pos || neg) {
                f.sign[a] = if pos { 1 } else { -1 };
                (f.inv_min[a], f.inv_max[a]) = (lo, hi);
            }
        }
        for l in lanes(p.active) {
            f.tmin = f.tmin.min(p.tmin[l]);
        }
        f.limit = max_limit(limit, p.active);
        f
    }
}

/// The largest `limit` over the lanes of `mask` (`−∞` for none).
#[inline(always)]
pub fn max_limit(limit: &Lanes, mask: u32) -> f32 {
    lanes(mask).fold(f32::NEG_INFINITY, |m, l| m.max(limit[l]))
}

/// The lane indices of `mask`, lowest first.
#[inline(always)]
pub fn lanes(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let l = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            l
        })
    })
}

/// `x` widened outwards as `Aabb::clip` widens an entry (`near`) or exit distance.
#[inline(always)]
fn widen(x: f32, near: bool) -> f32 {
    let (shrink, grow) = (1.0 - SLAB_MARGIN, 1.0 + SLAB_MARGIN);
    x * if (x > 0.0) == near { shrink } else { grow }
}

/// `x`, or `other` when `x` is NaN (the scalar box test's NaN-slab rule).
#[inline(always)]
fn or_if_nan(x: f32, other: f32) -> f32 {
    if x.is_nan() {
        other
    } else {
        x
    }
}

/// The box tests of a packet, implemented once per instruction set.
pub trait PacketKernel {
    /// Children of `node` that the frustum `f` enters within `[f.tmin, f.limit]` (a
    /// superset of those any lane enters), as a mask over `0..node.count()`, with the
    /// frustum's entry distance into each in `near` (the visiting order).
    fn frustum<N: WideNode>(node: &N, f: &Frustum, near: &mut Nears) -> u32;

    /// Lanes of `mask` whose ray enters child `i` of `node` within `[tmin, limit]` of the
    /// lane: the single-ray box test (`Kernel::boxes`, `Aabb::clip`) lane by lane, with
    /// each lane's entry distance in `near` (lanes of the result only).
    fn lanes<N: WideNode>(node: &N, i: usize, p: &Packet, limit: &Lanes, mask: u32, near: &mut Lanes) -> u32;

    /// Lanes of `mask` whose `near <= limit`: those still entering a deferred child.
    fn entered(near: &Lanes, limit: &Lanes, mask: u32) -> u32;
}

impl PacketKernel for Scalar {
    #[inline(always)]
    fn frustum<N: WideNode>(node: &N, f: &Frustum, near: &mut Nears) -> u32 {
        let mut mask = 0;
        for (i, near_i) in near.iter_mut().enumerate().take(node.count()) {
            let (mut n, mut x) = (f32::NEG_INFINITY, f32::INFINITY);
            for a in 0..3 {
                let (enter, exit) = match f.sign[a] {
                    0 => continue,
                    1 => (node.lo(a)[i], node.hi(a)[i]),
                    _ => (node.hi(a)[i], node.lo(a)[i]),
                };
                let (de, dx) = (enter - f.org[a], exit - f.org[a]);
                n = n.max((de * f.inv_min[a]).min(de * f.inv_max[a]));
                x = x.min((dx * f.inv_min[a]).max(dx * f.inv_max[a]));
            }
            let n = widen(n, true).max(f.tmin);
            let x = widen(x, false).min(f.limit);
            *near_i = n;
            mask |= ((n <= x) as u32) << i;
        }
        mask
    }

    #[inline(always)]
    fn lanes<N: WideNode>(node: &N, i: usize, p: &Packet, limit: &Lanes, mask: u32, near: &mut Lanes) -> u32 {
        let mut out = 0;
        for l in lanes(mask) {
            // `Scalar::boxes` for one child and one lane: the same operations, same order.
            let (mut n, mut x) = (f32::NEG_INFINITY, f32::INFINITY);
            for a in 0..3 {
                let t0 = (node.lo(a)[i] - p.org[a]) * p.inv[a][l];
                let t1 = (node.hi(a)[i] - p.org[a]) * p.inv[a][l];
                let (n0, n1) = (or_if_nan(t0, f32::NEG_INFINITY), or_if_nan(t1, f32::NEG_INFINITY));
                let (x0, x1) = (or_if_nan(t0, f32::INFINITY), or_if_nan(t1, f32::INFINITY));
                n = n.max(n0.min(n1));
                x = x.min(x0.max(x1));
            }
            let (n, x) = (widen(n, true), widen(x, false));
            let n = if p.tmin[l] > n { p.tmin[l] } else { n };
            let x = if limit[l] < x { limit[l] } else { x };
            near[l] = n;
            out |= ((n <= x) as u32) << l;
        }
        out
    }

    #[inline(always)]
    fn entered(near: &Lanes, limit: &Lanes, mask: u32) -> u32 {
        lanes(mask).fold(0, |m, l| m | ((near[l] <= limit[l]) as u32) << l)
    }
}

/// A deferred child: which lanes enter it, where, and the frustum's entry distance.
#[derive(Clone, Copy, Default)]
struct Entry {
    node: ChildRef,
    mask: u32,
    key: f32,
    near: Lanes,
}

/// Stack entries of trees whose bound fits (`traverse::stack_need`); deeper trees use
/// `STACK_CAPACITY`, as the single-ray traversal does.
const SMALL_STACK: usize = 64;

impl<N: WideNode> WideTree<N> {
    /// Closest hits of the active lanes of `p` (built from `rays`) into `hits`, with the
    /// kernel chosen at build time. Lanes outside `p.active` are left untouched.
    #[allow(unsafe_code)]
    pub(super) fn closest_packet(&self, rays: &[Ray], p: &Packet, hits: &mut [Hit]) {
        #[cfg(target_arch = "x86_64")]
        if self.kernel == super::kernel::KernelChoice::Avx2 {
            // SAFETY: `KernelChoice::Avx2` is only chosen when AVX2 was detected.
            return unsafe { self.closest_packet_avx2(rays, p, hits) };
        }
        self.closest_packet_sized::<Scalar, Scalar>(rays, p, hits)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    unsafe fn closest_packet_avx2(&self, rays: &[Ray], p: &Packet, hits: &mut [Hit]) {
        use super::kernel_avx2::Avx2;
        self.closest_packet_sized::<Avx2, Avx2>(rays, p, hits)
    }

    #[inline(always)]
    fn closest_packet_sized<K: Kernel, P: PacketKernel>(&self, rays: &[Ray], p: &Packet, hits: &mut [Hit]) {
        if self.stack_need <= SMALL_STACK {
            self.closest_packet_with::<K, P, SMALL_STACK>(rays, p, hits)
        } else {
            self.closest_packet_with::<K, P, { super::traverse::STACK_CAPACITY }>(rays, p, hits)
        }
    }

    /// The packet traversal with an `S`-entry stack (`S >= self.stack_need`: each node
    /// pushes at most its `W` children and pops one, as in the single-ray traversal).
    #[inline(always)]
    fn closest_packet_with<K: Kernel, P: PacketKernel, const S: usize>(
        &self,
        rays: &[Ray],
        p: &Packet,
        hits: &mut [Hit],
    ) {
        let mut best = [Hit::MISS; PACKET];
        // A lane's limit is `min(best t, tmax)`, as the single-ray traversal culls.
        let mut limit: Lanes = [f32::NEG_INFINITY; PACKET];
        for l in lanes(p.active) {
            limit[l] = best[l].t.min(p.tmax[l]);
        }
        let mut frustum = Frustum::new(p, &limit);
        // The triangle test's constants, per lane, once it reaches a leaf.
        let mut pr: [Option<PreparedRay>; PACKET] = [None; PACKET];
        let mut stack = [Entry::default(); S];
        let mut sp = 0usize;
        let mut fnear: Nears = [0.0; 8];
        let (mut cur, mut mask): (ChildRef, u32) = (0, p.active);
        'walk: loop {
            if is_leaf(cur) {
                let (first, count) = leaf_blocks(cur);
                for b in &self.blocks[first..first + count] {
                    for l in lanes(mask) {
                        let r = pr[l].get_or_insert_with(|| PreparedRay::new(&rays[l]));
                        K::closest(b, r, &mut best[l]);
                    }
                }
                for l in lanes(mask) {
                    limit[l] = best[l].t.min(p.tmax[l]);
                }
                frustum.limit = max_limit(&limit, p.active);
            } else {
                let node = &self.nodes[cur as usize];
                let mut fm = P::frustum(node, &frustum, &mut fnear);
                let start = sp;
                while fm != 0 {
                    let i = fm.trailing_zeros() as usize;
                    fm &= fm - 1;
                    let mut e = Entry { node: node.child(i), mask: 0, key: fnear[i], near: [0.0; PACKET] };
                    e.mask = P::lanes(node, i, p, &limit, mask, &mut e.near);
                    if e.mask == 0 {
                        continue;
                    }
                    // Keep the pushed run sorted, nearest (by the frustum) on top.
                    let mut j = sp;
                    while j > start && stack[j - 1].key < e.key {
                        stack[j] = stack[j - 1];
                        j -= 1;
                    }
                    stack[j] = e;
                    sp += 1;
                }
                if sp > start {
                    sp -= 1;
                    (cur, mask) = (stack[sp].node, stack[sp].mask);
                    continue;
                }
            }
            // Pop the next child some lane still enters no later than its best hit.
            while sp > 0 {
                sp -= 1;
                let e = &stack[sp];
                let m = P::entered(&e.near, &limit, e.mask);
                if m != 0 {
                    (cur, mask) = (e.node, m);
                    continue 'walk;
                }
            }
            break;
        }
        for l in lanes(p.active) {
            hits[l] = best[l];
        }
    }
}
