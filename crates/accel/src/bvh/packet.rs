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

use super::kernel::{Nears, Scalar};
use super::node::WideNode;
use dynray_geom::{Hit, Ray, SLAB_MARGIN};

/// Rays per packet (the f32 lanes of one AVX2 register).
pub const PACKET: usize = 8;

/// Per-lane values of a packet, one `f32` per lane.
pub type Lanes = [f32; PACKET];

/// The rays of a packet in SoA order: what the box tests read.
#[derive(Clone, Copy, Debug)]
pub struct Packet {
    /// The origin every lane shares.
    pub org: [f32; 3],
    /// `1 / dir` per axis and lane, as `BoxRay::new` computes it; lanes outside
    /// [`Packet::active`] repeat the lowest active lane's.
    pub inv: [Lanes; 3],
    /// Interval start per lane; lanes outside [`Packet::active`] hold `+∞`.
    pub tmin: Lanes,
    /// Interval end per lane; lanes outside [`Packet::active`] hold `−∞`.
    pub tmax: Lanes,
    /// Lanes holding a ray.
    pub active: u32,
    /// Every active lane has `tmin >= 0` (the usual packet): the SIMD box tests then
    /// widen by `1 ∓ m` without the sign pick: a near distance `<= 0` becomes `tmin` and
    /// a far one `< 0` rejects the box either way.
    pub nonneg: bool,
}

impl Packet {
    /// The packet of the lanes of `rays` (at most 8) that can travel together: those whose
    /// origin has lane 0's bits (finite), with no NaN in direction or interval. The others
    /// stay out of [`Packet::active`] for the caller to trace alone.
    #[inline(always)]
    pub fn new(rays: &[Ray]) -> Self {
        assert!(rays.len() <= PACKET, "a packet holds at most {PACKET} rays, not {}", rays.len());
        let mut p = Packet {
            org: [0.0; 3],
            inv: [[1.0; PACKET]; 3],
            tmin: [f32::INFINITY; PACKET],
            tmax: [f32::NEG_INFINITY; PACKET],
            active: 0,
            nonneg: true,
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
                p.nonneg &= r.tmin >= 0.0;
            }
        }
        // Lanes out of the packet repeat an active lane's `1/d`, so the frustum may take
        // the range over all 8 lanes (their empty intervals keep them out of every test).
        if p.active != 0 {
            let f = p.active.trailing_zeros() as usize;
            for l in lanes(!p.active & 0xFF) {
                for a in 0..3 {
                    p.inv[a][l] = p.inv[a][f];
                }
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
    /// The frustum of `p`'s active lanes with per-lane limits `limit` (the scalar
    /// specification of [`Frustum::with`]).
    #[cfg(test)]
    pub fn new(p: &Packet, limit: &Lanes) -> Self {
        Self::with::<Scalar>(p, limit)
    }

    /// [`Frustum::new`] with kernel `P`'s per-axis range ([`PacketKernel::axis_range`]).
    #[inline(always)]
    pub fn with<P: PacketKernel>(p: &Packet, limit: &Lanes) -> Self {
        let mut f = Frustum {
            org: p.org,
            sign: [0; 3],
            inv_min: [0.0; 3],
            inv_max: [0.0; 3],
            tmin: f32::INFINITY,
            limit: f32::NEG_INFINITY,
        };
        if p.active == 0 {
            return f;
        }
        // Over all 8 lanes: those out of the packet repeat an active lane's `1/d`, and
        // hold `tmin = +∞` and `limit = −∞`, which change no minimum or maximum.
        for a in 0..3 {
            (f.sign[a], f.inv_min[a], f.inv_max[a]) = P::axis_range(&p.inv[a]);
        }
        for &t in &p.tmin {
            f.tmin = if t < f.tmin { t } else { f.tmin };
        }
        f.limit = max_limit(limit, p.active);
        f
    }
}

/// The frustum's bound on one axis from the lanes' `1/d` there (all 8 lanes): sign `1`
/// when every lane's is finite and positive, `-1` when finite and negative, with their
/// smallest and largest; `(0, 0, 0)` when the axis bounds nothing. With no NaN and no zero
/// in a bounded axis, the order of the `min`/`max` does not matter.
#[inline(always)]
fn axis_range(v: &Lanes) -> (i32, f32, f32) {
    // Branch-free (pairwise halving), which LLVM turns into vector compares and min/max:
    // the scalar loop was ~4 % of a packet on the BART kitchen.
    let pos = v.iter().fold(true, |all, &x| all & (x > 0.0) & (x < f32::INFINITY));
    let neg = v.iter().fold(true, |all, &x| all & (x < 0.0) & (x > f32::NEG_INFINITY));
    let (lo, hi) = min_max8(v);
    match (pos, neg) {
        (true, _) => (1, lo, hi),
        (_, true) => (-1, lo, hi),
        _ => (0, 0.0, 0.0),
    }
}

/// The smallest and largest of `v`, by pairwise halving (`<` and `>` picks, so with no
/// NaN the same values as a sequential scan, up to the sign of zeros).
#[inline(always)]
fn min_max8(v: &Lanes) -> (f32, f32) {
    let pick_lo = |x: f32, y: f32| if x < y { x } else { y };
    let pick_hi = |x: f32, y: f32| if x > y { x } else { y };
    let lo4: [f32; 4] = std::array::from_fn(|i| pick_lo(v[i], v[i + 4]));
    let hi4: [f32; 4] = std::array::from_fn(|i| pick_hi(v[i], v[i + 4]));
    let (lo2, hi2) =
        ([pick_lo(lo4[0], lo4[2]), pick_lo(lo4[1], lo4[3])], [pick_hi(hi4[0], hi4[2]), pick_hi(hi4[1], hi4[3])]);
    (pick_lo(lo2[0], lo2[1]), pick_hi(hi2[0], hi2[1]))
}

/// The largest `limit` over the lanes of `mask` (`−∞` for none). Limits are never NaN.
#[inline(always)]
pub fn max_limit(limit: &Lanes, mask: u32) -> f32 {
    let mut m = f32::NEG_INFINITY;
    for (l, &x) in limit.iter().enumerate() {
        let x = if mask >> l & 1 != 0 { x } else { f32::NEG_INFINITY };
        m = if x > m { x } else { m };
    }
    m
}

/// The lane indices of `mask`, lowest first.
#[inline(always)]
pub fn lanes(mask: u32) -> LaneBits {
    LaneBits(mask)
}

/// Iterator of [`lanes`].
pub struct LaneBits(u32);

impl Iterator for LaneBits {
    type Item = usize;

    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let l = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(l)
    }
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

    /// [`PacketKernel::lanes`] for a packet whose lanes all have a finite, non-zero `1/d`
    /// of sign `sign[a]` on every axis (a frustum bounded on all three): there a lane
    /// enters each slab through the plane that sign names (`lo <= hi`) and no NaN
    /// arises, so the entry and exit distances need no `min`/`max` of the two planes or
    /// NaN guard — the same numbers, fewer operations.
    fn lanes_ordered<N: WideNode>(
        node: &N,
        i: usize,
        p: &Packet,
        sign: &[i32; 3],
        limit: &Lanes,
        mask: u32,
        near: &mut Lanes,
    ) -> u32;

    /// [`Packet::new`], as this kernel computes it.
    #[inline(always)]
    fn packet(rays: &[Ray]) -> Packet {
        Packet::new(rays)
    }

    /// [`axis_range`] (the frustum's sign and `1/d` range on one axis), as this kernel
    /// computes it.
    #[inline(always)]
    fn axis_range(v: &Lanes) -> (i32, f32, f32) {
        axis_range(v)
    }

    /// Sets `limit[l] = min(best[l].t, tmax[l])` for the lanes of `mask` (after their leaf
    /// tests), the others unchanged.
    #[inline(always)]
    fn update_limits(limit: &mut Lanes, best: &[Hit; PACKET], tmax: &Lanes, mask: u32) {
        for l in lanes(mask) {
            limit[l] = best[l].t.min(tmax[l]);
        }
    }

    /// [`max_limit`], as this kernel computes it.
    #[inline(always)]
    fn max_limit(limit: &Lanes, mask: u32) -> f32 {
        max_limit(limit, mask)
    }

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

    #[allow(clippy::needless_range_loop)] // `a` indexes the node's, the packet's and `sign`'s arrays
    #[inline(always)]
    fn lanes_ordered<N: WideNode>(
        node: &N,
        i: usize,
        p: &Packet,
        sign: &[i32; 3],
        limit: &Lanes,
        mask: u32,
        near: &mut Lanes,
    ) -> u32 {
        let mut out = 0;
        for l in lanes(mask) {
            let (mut n, mut x) = (f32::NEG_INFINITY, f32::INFINITY);
            for a in 0..3 {
                let (enter, exit) =
                    if sign[a] > 0 { (node.lo(a)[i], node.hi(a)[i]) } else { (node.hi(a)[i], node.lo(a)[i]) };
                n = n.max((enter - p.org[a]) * p.inv[a][l]);
                x = x.min((exit - p.org[a]) * p.inv[a][l]);
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
