//! The AVX-512 kernel: the f64 watertight test on two leaf blocks at once (8 triangles in
//! one `__m512d`), the AVX2 block test where a leaf has an odd count, and the box test of
//! the AVX2 kernel with its compares written straight into mask registers (AVX-512 VL),
//! so no `movemask` and no blend through a vector register.
//!
//! Tried and dropped: pushing a node's hit children with a 19-comparator sorting network
//! over all 8 lanes (integer keys from the distances, two vector stores) instead of the
//! insertion sort. Two alternated `dynray bench` runs (bunny, dragon, BART kitchen, 2
//! threads): primary rays 0.62–0.72× Embree with the network against 0.60–0.85× without
//! (dragon 10.5 / 11.6 against 13.5 / 14.8 Mrays/s), incoherent kinds equal within noise.
//!
//! Also dropped: rejecting a pair before its divide when every lane's `t` is outside
//! `[tmin, tmax]` (comparing `tt` with the widened bounds times `det`, as Embree's tests
//! do): 93 % of the pairs a ray tests have a lane whose edges contain it, and only 1.5–4 %
//! of those lie wholly outside the interval, so the extra compares cost shadow and diffuse
//! rays 3–4 % on the BART kitchen (docs/structures.md, "Where it stands").
//!
//! Also dropped (round 6, docs/structures.md "Packets"): a scalar divide for a pair's one
//! lane left after the edge tests (the usual case; `vdivpd zmm` issues once per 16
//! cycles): −2 % on kitchen packets, shadow and diffuse rays, so the divide is not the
//! bound; and a packet leaf's odd block tested one triangle at a time across 8 lanes
//! instead of a block test per lane: kitchen packets −2 %, bunny −9 %. Round 10 measured
//! that idea again on Zen 4, for whole leaves (one triangle against up to 8 lanes in a
//! `__m512d`, each lane's shear constants in a vector): every leaf, kitchen packets −11 %;
//! only leaves shared by 6 or more lanes, kitchen −6 %, bunny −5 %, dragon −2 % (a
//! triangle pays its divide once any lane passes its edge tests).
//!
//! Bit-identical to [`super::kernel::Scalar`] for the reasons kernel_avx2.rs gives: every
//! lane performs the scalar test's IEEE operations in its order (no FMA intrinsic; Rust
//! never contracts), conversions round to nearest, compares are ordered (`_OQ`). The tests
//! in kernel.rs hold it to the scalar kernel on the same adversarial inputs as AVX2.
//!
//! Safety: the functions here are `#[inline(always)]` bodies that only the
//! `#[target_feature(enable = "avx2,avx512f,avx512vl")]` entry points (traverse.rs,
//! packet_traverse.rs, scan.rs) inline, and those are only called when
//! [`super::kernel::KernelChoice::Avx512`] was chosen, which needs AVX2, AVX-512 F and
//! AVX-512 VL detected at run time. Loads go through `bytemuck::cast` of `[f32; N]` arrays,
//! never raw pointers.
#![allow(unsafe_code)]

use super::block::TriBlock;
use super::kernel::{lane, same_axis_order, BoxRay, Kernel, Nears};
use super::kernel_avx2::{keep_closest, Avx2, Hits};
use super::node::WideNode;
use super::packet::{lanes, PACKET};
use bytemuck::cast;
use dynray_geom::{Hit, PreparedRay, SLAB_MARGIN};
use std::arch::x86_64::*;

/// The AVX-512 kernel.
#[derive(Clone, Copy, Debug)]
pub struct Avx512;

/// The ray's triangle-test constants broadcast to 8 f64 lanes.
struct Ray8 {
    o: [__m512d; 3],
    s: [__m512d; 3],
    k: [usize; 3],
}

impl Ray8 {
    #[inline(always)]
    fn new(r: &PreparedRay) -> Self {
        // SAFETY: see the file's header.
        unsafe {
            let (o, s) = (r.origin64, r.shear);
            Ray8 {
                o: [_mm512_set1_pd(o[0]), _mm512_set1_pd(o[1]), _mm512_set1_pd(o[2])],
                s: [_mm512_set1_pd(s[0]), _mm512_set1_pd(s[1]), _mm512_set1_pd(s[2])],
                k: r.k,
            }
        }
    }
}

/// Vertex `vert` of the 8 lanes (block `a`'s 4, then block `b`'s), relative to the origin,
/// in the ray's axis order: `p as f64 - o`.
#[inline(always)]
fn rel8(a: &TriBlock, b: &TriBlock, vert: usize, r: &Ray8) -> [__m512d; 3] {
    // SAFETY: see the file's header.
    unsafe {
        [
            _mm512_sub_pd(row(a, b, vert, r.k[0]), r.o[0]),
            _mm512_sub_pd(row(a, b, vert, r.k[1]), r.o[1]),
            _mm512_sub_pd(row(a, b, vert, r.k[2]), r.o[2]),
        ]
    }
}

/// Coordinate `axis` of vertex `vert` of the 8 lanes, widened to f64 (exact).
#[inline(always)]
fn row(a: &TriBlock, b: &TriBlock, vert: usize, axis: usize) -> __m512d {
    // SAFETY: see the file's header.
    unsafe {
        let lo = cast::<[f32; 4], __m128>(a.v[vert][axis]);
        let hi = cast::<[f32; 4], __m128>(b.v[vert][axis]);
        _mm512_cvtps_pd(_mm256_set_m128(hi, lo))
    }
}

// Helpers are `#[inline(always)]` functions, not closures: a closure is a function of its
// own without the target features, which LLVM may leave out of line (kernel_avx2.rs).

/// `x - s * z` (the shear into ray space).
#[inline(always)]
fn shear(x: __m512d, s: __m512d, z: __m512d) -> __m512d {
    // SAFETY: see the file's header.
    unsafe { _mm512_sub_pd(x, _mm512_mul_pd(s, z)) }
}

/// `p * q - r * s` (a 2-D edge function, in the scalar test's operand order).
#[inline(always)]
fn edge(p: __m512d, q: __m512d, r: __m512d, s: __m512d) -> __m512d {
    // SAFETY: see the file's header.
    unsafe { _mm512_sub_pd(_mm512_mul_pd(p, q), _mm512_mul_pd(r, s)) }
}

/// Lanes where `x < 0` (ordered: false on NaN, like Rust's `<`).
#[inline(always)]
fn negative(x: __m512d) -> __mmask8 {
    // SAFETY: see the file's header.
    unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(x, _mm512_setzero_pd()) }
}

/// Lanes where `x > 0` (ordered).
#[inline(always)]
fn positive(x: __m512d) -> __mmask8 {
    // SAFETY: see the file's header.
    unsafe { _mm512_cmp_pd_mask::<_CMP_GT_OQ>(x, _mm512_setzero_pd()) }
}

/// The three vertices of the 8 lanes of blocks `a` and `b` relative to the origin, in
/// the ray's axis order: all of the test that rays with one origin and axis order share.
#[inline(always)]
fn pair_rel(a: &TriBlock, b: &TriBlock, r8: &Ray8) -> [[__m512d; 3]; 3] {
    [rel8(a, b, 0, r8), rel8(a, b, 1, r8), rel8(a, b, 2, r8)]
}

/// The scalar test of `Triangle::intersect` on the 8 lanes of blocks `a` and `b`.
#[inline(always)]
fn pair_test(a: &TriBlock, b: &TriBlock, r: &PreparedRay, r8: &Ray8, tmax: f32) -> Option<Hits<8>> {
    pair_test_rel(&pair_rel(a, b, r8), r, &[r8.s[0], r8.s[1]], tmax)
}

/// [`pair_test`] from the vertices relative to the origin ([`pair_rel`]) and the ray's
/// first two shear constants `s`, broadcast.
#[inline(always)]
fn pair_test_rel(rel: &[[__m512d; 3]; 3], r: &PreparedRay, s: &[__m512d; 2], tmax: f32) -> Option<Hits<8>> {
    // SAFETY: see the file's header.
    unsafe {
        let [[a0, a1, a2], [b0, b1, b2], [c0, c1, c2]] = *rel;
        let (ax, ay) = (shear(a0, s[0], a2), shear(a1, s[1], a2));
        let (bx, by) = (shear(b0, s[0], b2), shear(b1, s[1], b2));
        let (cx, cy) = (shear(c0, s[0], c2), shear(c1, s[1], c2));
        let eu = edge(cx, by, cy, bx);
        let ev = edge(ax, cy, ay, cx);
        let ew = edge(bx, ay, by, ax);
        let det = _mm512_add_pd(_mm512_add_pd(eu, ev), ew);
        let reject = ((negative(eu) | negative(ev) | negative(ew)) & (positive(eu) | positive(ev) | positive(ew)))
            | _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(det, _mm512_setzero_pd());
        // Most block pairs a ray reaches miss all 8 triangles: stop before the divide.
        if reject == 0xFF {
            return None;
        }
        let tt = _mm512_mul_pd(
            _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(eu, a2), _mm512_mul_pd(ev, b2)), _mm512_mul_pd(ew, c2)),
            _mm512_set1_pd(r.shear[2]),
        );
        let rcp = _mm512_div_pd(_mm512_set1_pd(1.0), det);
        let t = _mm512_cvtpd_ps(_mm512_mul_pd(tt, rcp));
        let inside = _mm256_cmp_ps_mask::<_CMP_GE_OQ>(t, _mm256_set1_ps(r.ray.tmin))
            & _mm256_cmp_ps_mask::<_CMP_LE_OQ>(t, _mm256_set1_ps(tmax));
        let mask = (inside & !reject) as u32;
        if mask == 0 {
            return None;
        }
        let u = _mm512_cvtpd_ps(_mm512_mul_pd(ev, rcp));
        let v = _mm512_cvtpd_ps(_mm512_mul_pd(ew, rcp));
        Some(Hits { mask, t: cast(t), u: cast(u), v: cast(v) })
    }
}

/// The mesh ids of the 8 lanes of blocks `a` and `b`.
#[inline(always)]
fn pair_ids(a: &TriBlock, b: &TriBlock) -> [u32; 8] {
    [a.ids[0], a.ids[1], a.ids[2], a.ids[3], b.ids[0], b.ids[1], b.ids[2], b.ids[3]]
}

impl Kernel for Avx512 {
    #[inline(always)]
    fn boxes<N: WideNode>(node: &N, r: &BoxRay, tmin: f32, limit: f32, near: &mut Nears) -> u32 {
        let valid = (1u32 << node.count()) - 1;
        if N::W != 8 {
            // Four children fill half a register: the AVX2 body is as short.
            return Avx2::boxes(node, r, tmin, limit, near);
        }
        // SAFETY: see the file's header.
        unsafe {
            let load = |s: &[f32]| cast::<[f32; 8], __m256>(s.try_into().expect("8 lanes"));
            let (n, f) = if tmin >= 0.0 {
                // The margin folded into the reciprocal (see `Kernel::boxes`); the start
                // values, off the dependency chain, ignore a NaN `limit`.
                let mut n = _mm256_set1_ps(tmin);
                let mut f = _mm256_min_ps(_mm256_set1_ps(limit), _mm256_set1_ps(f32::INFINITY));
                for a in 0..3 {
                    let o = _mm256_set1_ps(r.org[a]);
                    let (near_plane, far_plane) =
                        if r.neg[a] { (node.hi(a), node.lo(a)) } else { (node.lo(a), node.hi(a)) };
                    let tn = _mm256_mul_ps(_mm256_sub_ps(load(near_plane), o), _mm256_set1_ps(r.inv_near[a]));
                    let tf = _mm256_mul_ps(_mm256_sub_ps(load(far_plane), o), _mm256_set1_ps(r.inv_far[a]));
                    // NaN-ignoring as in the AVX2 kernel: `maxps(x, n)` is `n` for a NaN `x`.
                    n = _mm256_max_ps(tn, n);
                    f = _mm256_min_ps(tf, f);
                }
                (n, f)
            } else {
                let (mut n, mut f) = (_mm256_set1_ps(f32::NEG_INFINITY), _mm256_set1_ps(f32::INFINITY));
                for a in 0..3 {
                    let (o, inv) = (_mm256_set1_ps(r.org[a]), _mm256_set1_ps(r.inv[a]));
                    let (near_plane, far_plane) =
                        if r.neg[a] { (node.hi(a), node.lo(a)) } else { (node.lo(a), node.hi(a)) };
                    let tn = _mm256_mul_ps(_mm256_sub_ps(load(near_plane), o), inv);
                    let tf = _mm256_mul_ps(_mm256_sub_ps(load(far_plane), o), inv);
                    n = _mm256_max_ps(tn, n);
                    f = _mm256_min_ps(tf, f);
                }
                // Widen outwards: `x * (1 ∓ m)` by the sign of `x`, the factor picked by mask.
                let (lo_m, hi_m) = (_mm256_set1_ps(1.0 - SLAB_MARGIN), _mm256_set1_ps(1.0 + SLAB_MARGIN));
                let zero = _mm256_setzero_ps();
                let n_pos = _mm256_cmp_ps_mask::<_CMP_GT_OQ>(n, zero);
                let f_pos = _mm256_cmp_ps_mask::<_CMP_GT_OQ>(f, zero);
                let n = _mm256_mul_ps(n, _mm256_mask_blend_ps(n_pos, hi_m, lo_m));
                let f = _mm256_mul_ps(f, _mm256_mask_blend_ps(f_pos, lo_m, hi_m));
                (_mm256_max_ps(_mm256_set1_ps(tmin), n), _mm256_min_ps(_mm256_set1_ps(limit), f))
            };
            *near = cast(n);
            (_mm256_cmp_ps_mask::<_CMP_LE_OQ>(n, f) as u32) & valid
        }
    }

    #[inline(always)]
    fn closest(b: &TriBlock, r: &PreparedRay, best: &mut Hit) {
        Avx2::closest(b, r, best)
    }

    #[inline(always)]
    fn any(b: &TriBlock, r: &PreparedRay) -> bool {
        Avx2::any(b, r)
    }

    /// Blocks two at a time (8 f64 lanes), the odd one through the 4-lane test.
    #[inline(always)]
    fn closest_leaf(blocks: &[TriBlock], r: &PreparedRay, best: &mut Hit) {
        let r8 = Ray8::new(r);
        let mut pairs = blocks.chunks_exact(2);
        for p in &mut pairs {
            let (a, b) = (&p[0], &p[1]);
            if let Some(h) = pair_test(a, b, r, &r8, best.t.min(r.ray.tmax)) {
                keep_closest(&h, &pair_ids(a, b), best);
            }
        }
        if let [last] = pairs.remainder() {
            Avx2::closest(last, r, best);
        }
    }

    /// Block pairs as in `closest_leaf`, each pair's vertices made relative to the shared
    /// origin once for every lane with the first lane's axis order (the same numbers each
    /// lane computes alone: the origin's bits are the same), the odd block likewise through
    /// `Avx2::closest_block_lanes`; lanes with another axis order test alone.
    #[inline(always)]
    fn closest_leaf_lanes(
        blocks: &[TriBlock],
        mask: u32,
        pr: &[Option<PreparedRay>; PACKET],
        best: &mut [Hit; PACKET],
    ) {
        let first = lane(pr, mask.trailing_zeros() as usize);
        let shared = Ray8::new(first);
        let together = same_axis_order(mask, pr);
        let mut pairs = blocks.chunks_exact(2);
        for p in &mut pairs {
            let (a, b) = (&p[0], &p[1]);
            let rel = pair_rel(a, b, &shared);
            for l in lanes(together) {
                let r = lane(pr, l);
                // SAFETY: see the file's header.
                let s = unsafe { [_mm512_set1_pd(r.shear[0]), _mm512_set1_pd(r.shear[1])] };
                if let Some(h) = pair_test_rel(&rel, r, &s, best[l].t.min(r.ray.tmax)) {
                    keep_closest(&h, &pair_ids(a, b), &mut best[l]);
                }
            }
        }
        if let [last] = pairs.remainder() {
            Avx2::closest_block_lanes(last, together, pr, best);
        }
        for l in lanes(mask & !together) {
            Self::closest_leaf(blocks, lane(pr, l), &mut best[l]);
        }
    }

    #[inline(always)]
    fn any_leaf(blocks: &[TriBlock], r: &PreparedRay) -> bool {
        let r8 = Ray8::new(r);
        let mut pairs = blocks.chunks_exact(2);
        for p in &mut pairs {
            if pair_test(&p[0], &p[1], r, &r8, r.ray.tmax).is_some() {
                return true;
            }
        }
        // A loop, not `any(closure)`: see `Kernel::any_leaf`.
        for b in pairs.remainder() {
            if Avx2::any(b, r) {
                return true;
            }
        }
        false
    }

    #[inline(always)]
    fn prefetch<T>(x: &T) {
        Avx2::prefetch(x)
    }

    #[inline(always)]
    fn prefetch_lines(at: [usize; 4]) {
        Avx2::prefetch_lines(at)
    }
}

/// Entry points for the tests, compiled with AVX-512 so the kernels inline as they do in
/// traversal. Callers check `kernel::avx512_available` first.
#[cfg(test)]
impl Avx512 {
    pub(super) fn closest_leaf_checked(blocks: &[TriBlock], r: &PreparedRay, start: Hit) -> Hit {
        #[target_feature(enable = "avx2,avx512f,avx512vl")]
        fn go(blocks: &[TriBlock], r: &PreparedRay, mut h: Hit) -> Hit {
            Avx512::closest_leaf(blocks, r, &mut h);
            h
        }
        assert!(super::kernel::avx512_available());
        // SAFETY: the features were checked on the line above.
        unsafe { go(blocks, r, start) }
    }

    pub(super) fn any_leaf_checked(blocks: &[TriBlock], r: &PreparedRay) -> bool {
        #[target_feature(enable = "avx2,avx512f,avx512vl")]
        fn go(blocks: &[TriBlock], r: &PreparedRay) -> bool {
            Avx512::any_leaf(blocks, r)
        }
        assert!(super::kernel::avx512_available());
        // SAFETY: the features were checked on the line above.
        unsafe { go(blocks, r) }
    }

    pub(super) fn boxes_checked<N: WideNode>(node: &N, r: &BoxRay, tmin: f32, limit: f32, near: &mut Nears) -> u32 {
        #[target_feature(enable = "avx2,avx512f,avx512vl")]
        fn go<N: WideNode>(node: &N, r: &BoxRay, tmin: f32, limit: f32, near: &mut Nears) -> u32 {
            Avx512::boxes(node, r, tmin, limit, near)
        }
        assert!(super::kernel::avx512_available());
        // SAFETY: the features were checked on the line above.
        unsafe { go(node, r, tmin, limit, near) }
    }
}
