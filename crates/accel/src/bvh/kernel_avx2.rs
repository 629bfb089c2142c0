//! The AVX2 kernel: the f64 watertight test on the 4 triangles of a block at once
//! (`__m256d`), and the box test of 4 (`__m128`) or 8 (`__m256`) children at once.
//!
//! Bit-identical to [`super::kernel::Scalar`] by construction: every lane performs the
//! scalar test's IEEE operations in the scalar test's order (`sub`, `mul`, `add`, `div`,
//! correctly rounded in both; Rust never contracts `a * b - c` into an FMA, and this file
//! uses no FMA intrinsic), the f64 → f32 conversion rounds to nearest as `as f32` does,
//! and the comparisons are the ordered (`_OQ`) ones, false on NaN like Rust's `<`.
//! `maxps(x, -∞)` / `minps(x, +∞)` return the second operand on NaN, which is the scalar
//! kernel's `or_if_nan`. The tests in kernel.rs compare both on adversarial inputs.
//!
//! Safety: the functions here are `#[inline(always)]` bodies that only the
//! `#[target_feature(enable = "avx2")]` entry points of traverse.rs inline, and those are
//! only called when `is_x86_feature_detected!("avx2")` held ([`super::kernel::KernelChoice`]).
//! Loads and stores go through `bytemuck::cast` of `[f32; N]` arrays, never raw pointers.
#![allow(unsafe_code)]

use super::block::TriBlock;
use super::kernel::{lane, same_axis_order, BoxRay, Kernel, Nears};
use super::node::WideNode;
use super::packet::{lanes, PACKET};
use bytemuck::cast;
use dynray_geom::{Hit, PreparedRay, SLAB_MARGIN};
use std::arch::x86_64::*;

/// The AVX2 kernel.
#[derive(Clone, Copy, Debug)]
pub struct Avx2;

/// Lane results of one block test (`L` = 4) or block-pair test (`L` = 8, kernel_avx512.rs):
/// lanes that hit within `[tmin, tmax]`, and their `t`, `u`, `v`.
pub(super) struct Hits<const L: usize> {
    pub mask: u32,
    pub t: [f32; L],
    pub u: [f32; L],
    pub v: [f32; L],
}

// The helpers below are `#[inline(always)]` functions, not closures: a closure is a
// function of its own without AVX2 enabled, which LLVM left out of line (three calls per
// block, measured in the disassembly), and then the intrinsics inside it are calls too.

/// Vertex `vert` of the 4 lanes relative to the origin, in the ray's axis order:
/// `p[k] as f64 - o` (f32 → f64 is exact).
#[inline(always)]
fn rel(b: &TriBlock, vert: usize, k: [usize; 3], o: [__m256d; 3]) -> [__m256d; 3] {
    // SAFETY: see the file's header (AVX2 is present wherever this is inlined).
    unsafe {
        let c = &b.v[vert];
        let coord = [k[0], k[1], k[2]].map(|axis| cast::<[f32; 4], __m128>(c[axis]));
        [
            _mm256_sub_pd(_mm256_cvtps_pd(coord[0]), o[0]),
            _mm256_sub_pd(_mm256_cvtps_pd(coord[1]), o[1]),
            _mm256_sub_pd(_mm256_cvtps_pd(coord[2]), o[2]),
        ]
    }
}

/// `x - s * z` (the shear into ray space).
#[inline(always)]
fn shear(x: __m256d, s: __m256d, z: __m256d) -> __m256d {
    // SAFETY: see the file's header.
    unsafe { _mm256_sub_pd(x, _mm256_mul_pd(s, z)) }
}

/// `p * q - r * s` (a 2-D edge function, in the scalar test's operand order).
#[inline(always)]
fn edge(p: __m256d, q: __m256d, r: __m256d, s: __m256d) -> __m256d {
    // SAFETY: see the file's header.
    unsafe { _mm256_sub_pd(_mm256_mul_pd(p, q), _mm256_mul_pd(r, s)) }
}

/// Lanes where `x < 0` (ordered: false on NaN, like Rust's `<`).
#[inline(always)]
fn negative(x: __m256d) -> __m256d {
    // SAFETY: see the file's header.
    unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(x, _mm256_setzero_pd()) }
}

/// Lanes where `x > 0` (ordered).
#[inline(always)]
fn positive(x: __m256d) -> __m256d {
    // SAFETY: see the file's header.
    unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(x, _mm256_setzero_pd()) }
}

/// The three vertices of the block's 4 lanes relative to `r`'s origin, in its axis order:
/// all of the test that rays with one origin and axis order share.
#[inline(always)]
fn block_rel(b: &TriBlock, r: &PreparedRay) -> [[__m256d; 3]; 3] {
    // SAFETY: see the file's header (AVX2 is present wherever this is inlined).
    let o = unsafe { [_mm256_set1_pd(r.origin64[0]), _mm256_set1_pd(r.origin64[1]), _mm256_set1_pd(r.origin64[2])] };
    [rel(b, 0, r.k, o), rel(b, 1, r.k, o), rel(b, 2, r.k, o)]
}

/// The scalar test of `Triangle::intersect` on the block's 4 lanes.
#[inline(always)]
fn block_test(b: &TriBlock, r: &PreparedRay, tmax: f32) -> Option<Hits<4>> {
    block_test_rel(&block_rel(b, r), r, tmax)
}

/// [`block_test`] from the vertices relative to the origin ([`block_rel`]).
#[inline(always)]
fn block_test_rel(rel: &[[__m256d; 3]; 3], r: &PreparedRay, tmax: f32) -> Option<Hits<4>> {
    // SAFETY: see the file's header (AVX2 is present wherever this is inlined).
    unsafe {
        let (sx, sy, sz) = (_mm256_set1_pd(r.shear[0]), _mm256_set1_pd(r.shear[1]), _mm256_set1_pd(r.shear[2]));
        let [[a0, a1, a2], [b0, b1, b2], [c0, c1, c2]] = *rel;
        let (ax, ay) = (shear(a0, sx, a2), shear(a1, sy, a2));
        let (bx, by) = (shear(b0, sx, b2), shear(b1, sy, b2));
        let (cx, cy) = (shear(c0, sx, c2), shear(c1, sy, c2));
        let eu = edge(cx, by, cy, bx);
        let ev = edge(ax, cy, ay, cx);
        let ew = edge(bx, ay, by, ax);
        let any_neg = _mm256_or_pd(_mm256_or_pd(negative(eu), negative(ev)), negative(ew));
        let any_pos = _mm256_or_pd(_mm256_or_pd(positive(eu), positive(ev)), positive(ew));
        let det = _mm256_add_pd(_mm256_add_pd(eu, ev), ew);
        let reject =
            _mm256_or_pd(_mm256_and_pd(any_neg, any_pos), _mm256_cmp_pd::<_CMP_EQ_OQ>(det, _mm256_setzero_pd()));
        // Most blocks a ray reaches miss all 4 triangles: stop before the divide.
        if _mm256_movemask_pd(reject) == 0xF {
            return None;
        }
        let tt = _mm256_mul_pd(
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(eu, a2), _mm256_mul_pd(ev, b2)), _mm256_mul_pd(ew, c2)),
            sz,
        );
        let rcp = _mm256_div_pd(_mm256_set1_pd(1.0), det);
        let t = _mm256_cvtpd_ps(_mm256_mul_pd(tt, rcp));
        let inside = _mm_and_ps(
            _mm_cmp_ps::<_CMP_GE_OQ>(t, _mm_set1_ps(r.ray.tmin)),
            _mm_cmp_ps::<_CMP_LE_OQ>(t, _mm_set1_ps(tmax)),
        );
        let mask = (_mm_movemask_ps(inside) as u32) & !(_mm256_movemask_pd(reject) as u32);
        if mask == 0 {
            return None;
        }
        let u = _mm256_cvtpd_ps(_mm256_mul_pd(ev, rcp));
        let v = _mm256_cvtpd_ps(_mm256_mul_pd(ew, rcp));
        Some(Hits { mask, t: cast(t), u: cast(u), v: cast(v) })
    }
}

/// Keeps in `best` the hits of `h` (lane `l` has mesh id `ids[l]`) closer than it.
#[inline(always)]
pub(super) fn keep_closest<const L: usize>(h: &Hits<L>, ids: &[u32; L], best: &mut Hit) {
    let mut m = h.mask;
    while m != 0 {
        let l = m.trailing_zeros() as usize;
        m &= m - 1;
        // `is_closer` is a strict order on (t, id), so lane order does not matter.
        if Hit::is_closer(h.t[l], ids[l], best) {
            *best = Hit { t: h.t[l], u: h.u[l], v: h.v[l], prim: ids[l] };
        }
    }
}

impl Avx2 {
    /// [`Kernel::closest`] on block `b` for packet lanes `together`, which share their
    /// origin and axis order: the vertices relative to the origin once, the rest per lane
    /// (the numbers each lane computes alone, bit for bit).
    #[inline(always)]
    pub(super) fn closest_block_lanes(
        b: &TriBlock,
        together: u32,
        pr: &[Option<PreparedRay>; PACKET],
        best: &mut [Hit; PACKET],
    ) {
        if together == 0 {
            return;
        }
        let rel = block_rel(b, lane(pr, together.trailing_zeros() as usize));
        for l in lanes(together) {
            let r = lane(pr, l);
            if let Some(h) = block_test_rel(&rel, r, best[l].t.min(r.ray.tmax)) {
                keep_closest(&h, &b.ids, &mut best[l]);
            }
        }
    }
}

/// The planes through which the ray enters and leaves the children's slabs along `axis`:
/// `lo` then `hi`, or `hi` then `lo` where the ray runs towards −axis.
///
/// Why this equals the scalar kernel's `min`/`max` of the two plane distances: for a
/// child box (`lo <= hi`), `(lo − o)` and `(hi − o)` round in the same order, and
/// multiplying by `inv` keeps it (`inv >= 0`) or reverses it (`inv < 0`), so the near
/// distance is the one from the plane chosen here. A distance is NaN only as `0 × ∞` (the
/// origin on a plane, the direction parallel to it), where the other plane's distance is
/// ±∞ or NaN too, and the NaN-ignoring `max`/`min` of the caller then leave the
/// interval as `or_if_nan`'s ±∞ does. (A non-finite origin can differ, but no triangle
/// test accepts such a ray: every value it computes is NaN.)
#[inline(always)]
fn near_far<'n, N: WideNode>(node: &'n N, r: &BoxRay, axis: usize) -> (&'n [f32], &'n [f32]) {
    if r.neg[axis] {
        (node.hi(axis), node.lo(axis))
    } else {
        (node.lo(axis), node.hi(axis))
    }
}

/// Widens near (`far == false`) or far distances outwards by [`SLAB_MARGIN`], as
/// `Aabb::clip`: `x * (1 ∓ m)` by the sign of `x`.
macro_rules! widen {
    ($cmp:ident, $blend:ident, $set1:ident, $mul:ident, $zero:expr, $x:expr, $pos:expr, $neg:expr) => {{
        let x = $x;
        let positive = $cmp::<_CMP_GT_OQ>(x, $zero);
        $mul(x, $blend($set1($neg), $set1($pos), positive))
    }};
}

/// The box test of `Kernel::boxes` on one register of children (`$ty`: `__m256` for 8,
/// `__m128` for 4; `$arr` the matching array), written once for both widths as the
/// packet kernel's `frustum!` is. Each axis reads its near and far planes by the sign of
/// the ray's direction; `maxps(x, n)` is `n` when `x` is NaN, so a NaN slab leaves the
/// interval as it was, as the scalar kernel's `or_if_nan` does.
macro_rules! boxes {
    ($node:expr, $r:expr, $tmin:expr, $limit:expr, $near:expr, $ty:ty, $set1:ident, $sub:ident, $mul:ident,
     $min:ident, $max:ident, $cmp:ident, $blend:ident, $zero:ident, $movemask:ident, $arr:ty) => {{
        let (node, r, tmin, limit): (&_, &BoxRay, f32, f32) = ($node, $r, $tmin, $limit);
        let load = |s: &[f32]| cast::<$arr, $ty>(s.try_into().expect("node lanes"));
        let (n, f) = if tmin >= 0.0 {
            // The margin folded into the reciprocal (see `Kernel::boxes`); the start
            // values, off the dependency chain, ignore a NaN `limit`.
            let (mut n, mut f) = ($set1(tmin), $min($set1(limit), $set1(f32::INFINITY)));
            for a in 0..3 {
                let o = $set1(r.org[a]);
                let (near_plane, far_plane) = near_far(node, r, a);
                n = $max($mul($sub(load(near_plane), o), $set1(r.inv_near[a])), n);
                f = $min($mul($sub(load(far_plane), o), $set1(r.inv_far[a])), f);
            }
            (n, f)
        } else {
            let (mut n, mut f) = ($set1(f32::NEG_INFINITY), $set1(f32::INFINITY));
            for a in 0..3 {
                let (o, inv) = ($set1(r.org[a]), $set1(r.inv[a]));
                let (near_plane, far_plane) = near_far(node, r, a);
                n = $max($mul($sub(load(near_plane), o), inv), n);
                f = $min($mul($sub(load(far_plane), o), inv), f);
            }
            let (lo_m, hi_m) = (1.0 - SLAB_MARGIN, 1.0 + SLAB_MARGIN);
            let zero = $zero();
            let n = widen!($cmp, $blend, $set1, $mul, zero, n, lo_m, hi_m);
            let f = widen!($cmp, $blend, $set1, $mul, zero, f, hi_m, lo_m);
            // `maxps(tmin, n)` = `tmin > n ? tmin : n`; `minps(limit, f)` = `limit < f ? limit : f`.
            ($max($set1(tmin), n), $min($set1(limit), f))
        };
        let out: $arr = cast(n);
        $near[..out.len()].copy_from_slice(&out);
        let valid = (1u32 << node.count()) - 1;
        ($movemask($cmp::<_CMP_LE_OQ>(n, f)) as u32) & valid
    }};
}

impl Kernel for Avx2 {
    #[inline(always)]
    fn boxes<N: WideNode>(node: &N, r: &BoxRay, tmin: f32, limit: f32, near: &mut Nears) -> u32 {
        // SAFETY: see the file's header.
        unsafe {
            if N::W == 8 {
                boxes!(
                    node,
                    r,
                    tmin,
                    limit,
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
                boxes!(
                    node,
                    r,
                    tmin,
                    limit,
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
    fn closest(b: &TriBlock, r: &PreparedRay, best: &mut Hit) {
        if let Some(h) = block_test(b, r, best.t.min(r.ray.tmax)) {
            keep_closest(&h, &b.ids, best);
        }
    }

    /// Each block's vertices made relative to the shared origin once for every lane with
    /// the first lane's axis order (`Avx2::closest_block_lanes`); the others test alone.
    #[inline(always)]
    fn closest_leaf_lanes(
        blocks: &[TriBlock],
        mask: u32,
        pr: &[Option<PreparedRay>; PACKET],
        best: &mut [Hit; PACKET],
    ) {
        let together = same_axis_order(mask, pr);
        for b in blocks {
            Avx2::closest_block_lanes(b, together, pr, best);
        }
        for l in lanes(mask & !together) {
            Self::closest_leaf(blocks, lane(pr, l), &mut best[l]);
        }
    }

    #[inline(always)]
    fn any(b: &TriBlock, r: &PreparedRay) -> bool {
        block_test(b, r, r.ray.tmax).is_some()
    }

    #[inline(always)]
    fn prefetch_lines(at: [usize; 4]) {
        for a in at {
            // SAFETY: a prefetch never faults, whatever the address.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(a as *const i8) }
        }
    }

    #[inline(always)]
    fn prefetch<T>(x: &T) {
        let p = x as *const T as *const i8;
        for line in (0..std::mem::size_of::<T>()).step_by(64) {
            // SAFETY: a prefetch never faults, and the address is inside `x`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(line)) }
        }
    }
}

/// Entry points for the tests, compiled with AVX2 so the kernels inline as they do in
/// traversal. Callers check `is_x86_feature_detected!("avx2")` first.
#[cfg(test)]
impl Avx2 {
    pub(super) fn closest_checked(b: &TriBlock, r: &PreparedRay, start: Hit) -> Hit {
        #[target_feature(enable = "avx2")]
        fn go(b: &TriBlock, r: &PreparedRay, mut h: Hit) -> Hit {
            Avx2::closest(b, r, &mut h);
            h
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(b, r, start) }
    }

    pub(super) fn any_checked(b: &TriBlock, r: &PreparedRay) -> bool {
        #[target_feature(enable = "avx2")]
        fn go(b: &TriBlock, r: &PreparedRay) -> bool {
            Avx2::any(b, r)
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(b, r) }
    }

    pub(super) fn boxes_checked<N: WideNode>(node: &N, r: &BoxRay, tmin: f32, limit: f32, near: &mut Nears) -> u32 {
        #[target_feature(enable = "avx2")]
        fn go<N: WideNode>(node: &N, r: &BoxRay, tmin: f32, limit: f32, near: &mut Nears) -> u32 {
            Avx2::boxes(node, r, tmin, limit, near)
        }
        assert!(std::arch::is_x86_feature_detected!("avx2"));
        // SAFETY: AVX2 checked on the line above.
        unsafe { go(node, r, tmin, limit, near) }
    }
}
