//! The AVX2 packet kernel: the frustum test of 8 (`__m256`) or 4 (`__m128`) children at
//! once, and the single-ray box test of one child for the 8 lanes of a packet at once.
//!
//! Bit-identical to the scalar specification in packet.rs for the same reasons as
//! kernel_avx2.rs: each lane performs the scalar operations in the same order (`sub`,
//! `mul`, correctly rounded, no FMA), `maxps(x, −∞)` / `minps(x, +∞)` return the second
//! operand on NaN as `or_if_nan` does, and the comparisons are the ordered ones.
//! The lane test subtracts the origin from the child's plane once, in a broadcast register:
//! every lane shares the origin, so every lane gets the scalar test's `lo - org` bits.
//!
//! Safety: as kernel_avx2.rs, these `#[inline(always)]` bodies are only inlined into
//! packet.rs's `#[target_feature(enable = "avx2")]` entry point, called only when AVX2
//! was detected; loads and stores go through `bytemuck::cast` of arrays.
#![allow(unsafe_code)]

use super::kernel::Nears;
use super::kernel_avx2::Avx2;
use super::node::WideNode;
use super::packet::{Frustum, Lanes, Packet, PacketKernel, PACKET};
use bytemuck::cast;
use dynray_geom::{Hit, Ray, SLAB_MARGIN};
use std::arch::x86_64::*;

/// `x · (1 ∓ m)`: widened outwards by [`SLAB_MARGIN`] as `Aabb::clip` does (`near`:
/// shrink positive values; far: grow them).
macro_rules! widen {
    ($cmp:ident, $blend:ident, $set1:ident, $mul:ident, $zero:expr, $x:expr, $near:expr) => {{
        let x = $x;
        let positive = $cmp::<_CMP_GT_OQ>(x, $zero);
        let (pos, neg) =
            if $near { (1.0 - SLAB_MARGIN, 1.0 + SLAB_MARGIN) } else { (1.0 + SLAB_MARGIN, 1.0 - SLAB_MARGIN) };
        $mul(x, $blend($set1(neg), $set1(pos), positive))
    }};
}

/// The frustum test at one width: `$load` reads `W` lanes of a node array.
macro_rules! frustum {
    ($node:expr, $f:expr, $near:expr, $ty:ty, $set1:ident, $sub:ident, $mul:ident, $min:ident, $max:ident,
     $cmp:ident, $blend:ident, $zero:ident, $movemask:ident, $arr:ty) => {{
        let node = $node;
        let f: &Frustum = $f;
        let load = |s: &[f32]| cast::<$arr, $ty>(s.try_into().expect("node lanes"));
        let (mut n, mut x) = ($set1(f32::NEG_INFINITY), $set1(f32::INFINITY));
        for a in 0..3 {
            let (enter, exit) = match f.sign[a] {
                0 => continue,
                1 => (node.lo(a), node.hi(a)),
                _ => (node.hi(a), node.lo(a)),
            };
            let o = $set1(f.org[a]);
            let (imin, imax) = ($set1(f.inv_min[a]), $set1(f.inv_max[a]));
            let de = $sub(load(enter), o);
            let dx = $sub(load(exit), o);
            n = $max(n, $min($mul(de, imin), $mul(de, imax)));
            x = $min(x, $max($mul(dx, imin), $mul(dx, imax)));
        }
        // Every lane starts at `tmin >= 0`: no sign pick (see `Packet::nonneg`).
        let (n, x) = if f.tmin >= 0.0 {
            ($mul(n, $set1(1.0 - SLAB_MARGIN)), $mul(x, $set1(1.0 + SLAB_MARGIN)))
        } else {
            let zero = $zero();
            (widen!($cmp, $blend, $set1, $mul, zero, n, true), widen!($cmp, $blend, $set1, $mul, zero, x, false))
        };
        let n = $max(n, $set1(f.tmin));
        let x = $min(x, $set1(f.limit));
        let valid = (1u32 << node.count()) - 1;
        let out: $arr = cast(n);
        $near[..out.len()].copy_from_slice(&out);
        ($movemask($cmp::<_CMP_LE_OQ>(n, x)) as u32) & valid
    }};
}

/// The lanes' entry and exit distances widened outwards as `Aabb::clip` widens them; a
/// packet whose lanes all start at `tmin >= 0` needs no sign pick (see `Packet::nonneg`).
#[inline(always)]
fn widen_lanes(p: &Packet, n: __m256, x: __m256) -> (__m256, __m256) {
    // SAFETY: see the file's header.
    unsafe {
        if p.nonneg {
            (_mm256_mul_ps(n, _mm256_set1_ps(1.0 - SLAB_MARGIN)), _mm256_mul_ps(x, _mm256_set1_ps(1.0 + SLAB_MARGIN)))
        } else {
            let zero = _mm256_setzero_ps();
            (
                widen!(_mm256_cmp_ps, _mm256_blendv_ps, _mm256_set1_ps, _mm256_mul_ps, zero, n, true),
                widen!(_mm256_cmp_ps, _mm256_blendv_ps, _mm256_set1_ps, _mm256_mul_ps, zero, x, false),
            )
        }
    }
}

/// The lanes of `mask` as a blend mask: all ones in lane `l` when bit `l` is set.
#[inline(always)]
fn lane_mask(mask: u32) -> __m256 {
    // SAFETY: see the file's header.
    unsafe {
        let bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
        _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(mask as i32), bits), bits))
    }
}

impl PacketKernel for Avx2 {
    #[inline(always)]
    fn frustum<N: WideNode>(node: &N, f: &Frustum, near: &mut Nears) -> u32 {
        // SAFETY: see the file's header.
        unsafe {
            if N::W == 8 {
                frustum!(
                    node,
                    f,
                    near,
                    __m256,
                    _mm256_set1_ps,
                    _mm256_sub_ps,
                    _mm256_mul_ps,
                    _mm256_min_ps,
                    _mm256_max_ps,
                    _mm256_cmp_ps,
                    _mm256_blendv_ps,
                    _mm256_setzero_ps,
                    _mm256_movemask_ps,
                    [f32; 8]
                )
            } else {
                debug_assert_eq!(N::W, 4);
                frustum!(
                    node,
                    f,
                    near,
                    __m128,
                    _mm_set1_ps,
                    _mm_sub_ps,
                    _mm_mul_ps,
                    _mm_min_ps,
                    _mm_max_ps,
                    _mm_cmp_ps,
                    _mm_blendv_ps,
                    _mm_setzero_ps,
                    _mm_movemask_ps,
                    [f32; 4]
                )
            }
        }
    }

    #[inline(always)]
    fn lanes<N: WideNode>(node: &N, i: usize, p: &Packet, limit: &Lanes, mask: u32, near: &mut Lanes) -> u32 {
        // SAFETY: see the file's header.
        unsafe {
            let (ninf, pinf) = (_mm256_set1_ps(f32::NEG_INFINITY), _mm256_set1_ps(f32::INFINITY));
            let (mut n, mut x) = (ninf, pinf);
            for a in 0..3 {
                let o = _mm256_set1_ps(p.org[a]);
                let inv = cast::<Lanes, __m256>(p.inv[a]);
                let t0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(node.lo(a)[i]), o), inv);
                let t1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(node.hi(a)[i]), o), inv);
                let near_a = _mm256_min_ps(_mm256_max_ps(t0, ninf), _mm256_max_ps(t1, ninf));
                let far_a = _mm256_max_ps(_mm256_min_ps(t0, pinf), _mm256_min_ps(t1, pinf));
                n = _mm256_max_ps(n, near_a);
                x = _mm256_min_ps(x, far_a);
            }
            let (n, x) = widen_lanes(p, n, x);
            // `maxps(tmin, n)` = `tmin > n ? tmin : n`; `minps(limit, x)` = `limit < x ? limit : x`.
            let n = _mm256_max_ps(cast::<Lanes, __m256>(p.tmin), n);
            let x = _mm256_min_ps(cast::<Lanes, __m256>(*limit), x);
            *near = cast(n);
            (_mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(n, x)) as u32) & mask
        }
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
        // SAFETY: see the file's header.
        unsafe {
            let (mut n, mut x) = (_mm256_set1_ps(f32::NEG_INFINITY), _mm256_set1_ps(f32::INFINITY));
            for a in 0..3 {
                let (enter, exit) =
                    if sign[a] > 0 { (node.lo(a)[i], node.hi(a)[i]) } else { (node.hi(a)[i], node.lo(a)[i]) };
                let o = _mm256_set1_ps(p.org[a]);
                let inv = cast::<Lanes, __m256>(p.inv[a]);
                n = _mm256_max_ps(n, _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(enter), o), inv));
                x = _mm256_min_ps(x, _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(exit), o), inv));
            }
            let (n, x) = widen_lanes(p, n, x);
            let n = _mm256_max_ps(cast::<Lanes, __m256>(p.tmin), n);
            let x = _mm256_min_ps(cast::<Lanes, __m256>(*limit), x);
            *near = cast(n);
            (_mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(n, x)) as u32) & mask
        }
    }

    /// Eight rays (32 bytes each: origin, direction, `tmin`, `tmax`) loaded as eight
    /// registers and transposed in registers into the packet's SoA rows, the reciprocals
    /// three divides for all lanes: the scalar set-up wrote the rows one float at a time,
    /// and its per-lane divides and NaN tests were ~7 % of a bunny packet. Same IEEE
    /// divisions and bit compares as [`Packet::new`], which shorter or non-finite-origin
    /// packets still take.
    #[inline(always)]
    fn packet(rays: &[Ray]) -> Packet {
        let Ok(rays) = <&[Ray; 8]>::try_from(rays) else { return Packet::new(rays) };
        if !rays[0].origin.is_finite() {
            return Packet::new(rays);
        }
        // SAFETY: see the file's header.
        unsafe {
            let r = rays.map(cast::<Ray, __m256>);
            // 8×8 transpose into rows: row k holds field k (ox oy oz dx dy dz tmin tmax)
            // of every ray. Pairs interleaved, then quads, then the 128-bit halves.
            let t = [
                _mm256_unpacklo_ps(r[0], r[1]),
                _mm256_unpackhi_ps(r[0], r[1]),
                _mm256_unpacklo_ps(r[2], r[3]),
                _mm256_unpackhi_ps(r[2], r[3]),
                _mm256_unpacklo_ps(r[4], r[5]),
                _mm256_unpackhi_ps(r[4], r[5]),
                _mm256_unpacklo_ps(r[6], r[7]),
                _mm256_unpackhi_ps(r[6], r[7]),
            ];
            let q = [
                _mm256_shuffle_ps::<0x44>(t[0], t[2]),
                _mm256_shuffle_ps::<0xEE>(t[0], t[2]),
                _mm256_shuffle_ps::<0x44>(t[1], t[3]),
                _mm256_shuffle_ps::<0xEE>(t[1], t[3]),
                _mm256_shuffle_ps::<0x44>(t[4], t[6]),
                _mm256_shuffle_ps::<0xEE>(t[4], t[6]),
                _mm256_shuffle_ps::<0x44>(t[5], t[7]),
                _mm256_shuffle_ps::<0xEE>(t[5], t[7]),
            ];
            let row = [
                _mm256_permute2f128_ps::<0x20>(q[0], q[4]),
                _mm256_permute2f128_ps::<0x20>(q[1], q[5]),
                _mm256_permute2f128_ps::<0x20>(q[2], q[6]),
                _mm256_permute2f128_ps::<0x20>(q[3], q[7]),
                _mm256_permute2f128_ps::<0x31>(q[0], q[4]),
                _mm256_permute2f128_ps::<0x31>(q[1], q[5]),
                _mm256_permute2f128_ps::<0x31>(q[2], q[6]),
                _mm256_permute2f128_ps::<0x31>(q[3], q[7]),
            ];
            // Same origin bits as ray 0, and no NaN in direction or interval.
            let o = rays[0].origin;
            let mut fits = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
            for (k, v) in o.to_array().into_iter().enumerate() {
                let bits = _mm256_cmpeq_epi32(_mm256_castps_si256(row[k]), _mm256_set1_epi32(v.to_bits() as i32));
                fits = _mm256_and_ps(fits, _mm256_castsi256_ps(bits));
            }
            for x in &row[3..] {
                fits = _mm256_and_ps(fits, _mm256_cmp_ps::<_CMP_ORD_Q>(*x, *x));
            }
            let active = _mm256_movemask_ps(fits) as u32;
            let mut p = Packet::new(&[]);
            p.org = o.to_array();
            if active == 0 {
                return p;
            }
            // Lanes out of the packet repeat the lowest active lane's `1/d`.
            let first = _mm256_set1_epi32(active.trailing_zeros() as i32);
            let one = _mm256_set1_ps(1.0);
            for a in 0..3 {
                let inv = _mm256_div_ps(one, row[3 + a]);
                p.inv[a] = cast(_mm256_blendv_ps(_mm256_permutevar8x32_ps(inv, first), inv, fits));
            }
            p.tmin = cast(_mm256_blendv_ps(_mm256_set1_ps(f32::INFINITY), row[6], fits));
            p.tmax = cast(_mm256_blendv_ps(_mm256_set1_ps(f32::NEG_INFINITY), row[7], fits));
            p.active = active;
            let nonneg = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GE_OQ>(row[6], _mm256_setzero_ps())) as u32;
            p.nonneg = nonneg & active == active;
            p
        }
    }

    /// The scalar fold's all-lanes tests as two compares and a `movemask` each, the range
    /// by halving: LLVM had left the fold as 8 scalar bit tests per axis (~9 % of a bunny
    /// packet).
    #[inline(always)]
    fn axis_range(v: &Lanes) -> (i32, f32, f32) {
        // SAFETY: see the file's header.
        unsafe {
            let x = cast::<Lanes, __m256>(*v);
            let (zero, inf) = (_mm256_setzero_ps(), _mm256_set1_ps(f32::INFINITY));
            let pos = _mm256_and_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(x, zero), _mm256_cmp_ps::<_CMP_LT_OQ>(x, inf));
            let neg_inf = _mm256_set1_ps(f32::NEG_INFINITY);
            let neg = _mm256_and_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(x, zero), _mm256_cmp_ps::<_CMP_GT_OQ>(x, neg_inf));
            let (pos, neg) = (_mm256_movemask_ps(pos) == 0xFF, _mm256_movemask_ps(neg) == 0xFF);
            if !(pos || neg) {
                return (0, 0.0, 0.0);
            }
            // Bounded: no NaN and no zero, so any order of the `min`/`max` gives the scan's.
            let (lo, hi) = (_mm256_castps256_ps128(x), _mm256_extractf128_ps::<1>(x));
            let (lo, hi) = (_mm_min_ps(lo, hi), _mm_max_ps(lo, hi));
            let (lo, hi) = (_mm_min_ps(lo, _mm_movehl_ps(lo, lo)), _mm_max_ps(hi, _mm_movehl_ps(hi, hi)));
            let lo = _mm_min_ss(lo, _mm_shuffle_ps::<0b01>(lo, lo));
            let hi = _mm_max_ss(hi, _mm_shuffle_ps::<0b01>(hi, hi));
            (if pos { 1 } else { -1 }, _mm_cvtss_f32(lo), _mm_cvtss_f32(hi))
        }
    }

    /// The lanes' `t` gathered into a register and the limits written with one store:
    /// the scalar loop's eight stores, read back at once by the next node's tests, could
    /// not be forwarded to that load.
    #[inline(always)]
    fn update_limits(limit: &mut Lanes, best: &[Hit; PACKET], tmax: &Lanes, mask: u32) {
        // SAFETY: see the file's header.
        unsafe {
            let t =
                _mm256_setr_ps(best[0].t, best[1].t, best[2].t, best[3].t, best[4].t, best[5].t, best[6].t, best[7].t);
            // `minps(t, tmax)` is `t < tmax ? t : tmax`; neither is NaN for a packet lane.
            let new = _mm256_min_ps(t, cast::<Lanes, __m256>(*tmax));
            *limit = cast(_mm256_blendv_ps(cast::<Lanes, __m256>(*limit), new, lane_mask(mask)));
        }
    }

    #[inline(always)]
    fn max_limit(limit: &Lanes, mask: u32) -> f32 {
        // SAFETY: see the file's header.
        unsafe {
            let v = _mm256_blendv_ps(_mm256_set1_ps(f32::NEG_INFINITY), cast::<Lanes, __m256>(*limit), lane_mask(mask));
            // Limits are never NaN, so the order of the `max`es does not matter.
            let h = _mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps::<1>(v));
            let h = _mm_max_ps(h, _mm_movehl_ps(h, h));
            let h = _mm_max_ss(h, _mm_shuffle_ps::<0b01>(h, h));
            _mm_cvtss_f32(h)
        }
    }

    #[inline(always)]
    fn entered(near: &Lanes, limit: &Lanes, mask: u32) -> u32 {
        // SAFETY: see the file's header.
        unsafe {
            let le = _mm256_cmp_ps::<_CMP_LE_OQ>(cast::<Lanes, __m256>(*near), cast::<Lanes, __m256>(*limit));
            (_mm256_movemask_ps(le) as u32) & mask
        }
    }
}

/// Entry points for the tests, compiled with AVX2 as traversal compiles the kernel.
/// Callers check `is_x86_feature_detected!("avx2")` first.
#[cfg(test)]
impl Avx2 {
    pub(super) fn frustum_checked<N: WideNode>(node: &N, f: &Frustum, near: &mut Nears) -> u32 {
        #[target_feature(enable = "avx2")]
        fn go<N: WideNode>(node: &N, f: &Frustum, near: &mut Nears) -> u32 {
            <Avx2 as PacketKernel>::frustum(node, f, near)
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(node, f, near) }
    }

    pub(super) fn lanes_checked<N: WideNode>(
        node: &N,
        i: usize,
        p: &Packet,
        limit: &Lanes,
        mask: u32,
        near: &mut Lanes,
    ) -> u32 {
        #[target_feature(enable = "avx2")]
        fn go<N: WideNode>(node: &N, i: usize, p: &Packet, limit: &Lanes, mask: u32, near: &mut Lanes) -> u32 {
            <Avx2 as PacketKernel>::lanes(node, i, p, limit, mask, near)
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(node, i, p, limit, mask, near) }
    }

    pub(super) fn lanes_ordered_checked<N: WideNode>(
        node: &N,
        i: usize,
        p: &Packet,
        sign: &[i32; 3],
        limit: &Lanes,
        mask: u32,
        near: &mut Lanes,
    ) -> u32 {
        #[target_feature(enable = "avx2")]
        fn go<N: WideNode>(
            node: &N,
            i: usize,
            p: &Packet,
            sign: &[i32; 3],
            limit: &Lanes,
            mask: u32,
            near: &mut Lanes,
        ) -> u32 {
            <Avx2 as PacketKernel>::lanes_ordered(node, i, p, sign, limit, mask, near)
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(node, i, p, sign, limit, mask, near) }
    }

    pub(super) fn packet_checked(rays: &[Ray]) -> Packet {
        #[target_feature(enable = "avx2")]
        fn go(rays: &[Ray]) -> Packet {
            <Avx2 as PacketKernel>::packet(rays)
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(rays) }
    }

    pub(super) fn frustum_with_checked(p: &Packet, limit: &Lanes) -> Frustum {
        #[target_feature(enable = "avx2")]
        fn go(p: &Packet, limit: &Lanes) -> Frustum {
            Frustum::with::<Avx2>(p, limit)
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(p, limit) }
    }

    pub(super) fn update_limits_checked(limit: &mut Lanes, best: &[Hit; PACKET], tmax: &Lanes, mask: u32) {
        #[target_feature(enable = "avx2")]
        fn go(limit: &mut Lanes, best: &[Hit; PACKET], tmax: &Lanes, mask: u32) {
            <Avx2 as PacketKernel>::update_limits(limit, best, tmax, mask)
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(limit, best, tmax, mask) }
    }

    pub(super) fn max_limit_checked(limit: &Lanes, mask: u32) -> f32 {
        #[target_feature(enable = "avx2")]
        fn go(limit: &Lanes, mask: u32) -> f32 {
            <Avx2 as PacketKernel>::max_limit(limit, mask)
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(limit, mask) }
    }

    pub(super) fn entered_checked(near: &Lanes, limit: &Lanes, mask: u32) -> u32 {
        #[target_feature(enable = "avx2")]
        fn go(near: &Lanes, limit: &Lanes, mask: u32) -> u32 {
            <Avx2 as PacketKernel>::entered(near, limit, mask)
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(near, limit, mask) }
    }
}
