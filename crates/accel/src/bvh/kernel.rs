//! The two inner loops of the wide BVH behind one trait: the box test of one node's
//! children and the triangle test of one leaf block. [`Scalar`] is the specification
//! (it calls `Triangle::intersect` lane by lane and restates `Aabb::clip` lane by lane);
//! the AVX2 kernel (`kernel_avx2.rs`) computes the same numbers four or eight at a time,
//! and the tests below hold both to the same bits.

use super::block::{TriBlock, LANES, PAD_ID};
use super::node::WideNode;
use super::packet::{lanes, PACKET};
use dynray_geom::{Hit, PreparedRay, Ray, SLAB_MARGIN};

/// What the box test needs of a ray: origin and `1 / dir` (as `PreparedRay::inv_dir`).
#[derive(Clone, Copy, Debug)]
pub struct BoxRay {
    /// Ray origin.
    pub org: [f32; 3],
    /// Reciprocal direction, ±∞ for a zero component.
    pub inv: [f32; 3],
    /// Per axis, `inv` is negative (−0 directions give −∞): the ray enters a slab
    /// through its upper plane, so the SIMD kernels read `hi` as the near plane.
    pub neg: [bool; 3],
    /// `inv × (1 − m)` and `inv × (1 + m)` ([`SLAB_MARGIN`] folded into the reciprocal):
    /// where `tmin >= 0` the kernels scale near distances by the first and far ones by
    /// the second, so the widening costs nothing per node.
    pub inv_near: [f32; 3],
    /// See `inv_near`.
    pub inv_far: [f32; 3],
}

impl BoxRay {
    /// The box constants of `ray`, computed as `PreparedRay::new` computes `inv_dir`.
    #[inline(always)]
    pub fn new(ray: &Ray) -> Self {
        let inv = dynray_geom::Vec3::ONE / ray.dir;
        Self::from_parts(ray.origin.to_array(), inv.to_array())
    }

    /// The box constants from an origin and reciprocal direction.
    #[inline(always)]
    pub fn from_parts(org: [f32; 3], inv: [f32; 3]) -> Self {
        Self {
            org,
            inv,
            neg: inv.map(|x| x.is_sign_negative()),
            inv_near: inv.map(|x| x * (1.0 - SLAB_MARGIN)),
            inv_far: inv.map(|x| x * (1.0 + SLAB_MARGIN)),
        }
    }
}

/// Near distances of a node's children, one lane per child.
pub type Nears = [f32; 8];

/// The box and block tests, implemented once per instruction set.
pub trait Kernel {
    /// Children of `node` whose widened box the ray enters within `[tmin, limit]`, as a
    /// bit mask over lanes `0..node.count()`, with their entry distances in `near`: the
    /// test [`Scalar::boxes`] specifies, which every kernel reproduces bit for bit.
    ///
    /// Where `tmin < 0` it is `Aabb::clip` lane by lane: slab distances `(p − o) × inv`,
    /// then near `× (1 ∓ m)` and far `× (1 ± m)` by their signs. Where `tmin >= 0` (nearly
    /// every ray) the margin is folded into the reciprocal instead, near distances
    /// `(p − o) × (inv × (1 − m))` and far ones `(p − o) × (inv × (1 + m))`, which takes
    /// two multiplies and the sign picks off each node's dependency chain. It is as
    /// conservative: the same four roundings (reciprocal, difference, product, margin
    /// factor) in another order, each within 2⁻²⁴, against Ize's bound that `m` exceeds;
    /// a near distance `≤ 0` is replaced by `tmin` either way, and a far distance `< 0`
    /// (its sign is exact) rejects the box either way since the near one is `≥ 0`. The
    /// test `box_test_is_conservative` holds both forms to exact arithmetic.
    fn boxes<N: WideNode>(node: &N, r: &BoxRay, tmin: f32, limit: f32, near: &mut Nears) -> u32;

    /// Keeps in `best` the closest hit of `best` and the block's triangles, as
    /// `Hit::closest_of` does over the same triangles.
    fn closest(b: &TriBlock, r: &PreparedRay, best: &mut Hit);

    /// True when a triangle of the block is hit within `[tmin, tmax]`.
    fn any(b: &TriBlock, r: &PreparedRay) -> bool;

    /// [`Kernel::closest`] over a leaf's blocks (a kernel may test several at once).
    #[inline(always)]
    fn closest_leaf(blocks: &[TriBlock], r: &PreparedRay, best: &mut Hit) {
        for b in blocks {
            Self::closest(b, r, best);
        }
    }

    /// [`Kernel::closest_leaf`] for the lanes `mask` of a packet, whose rays share one
    /// origin: lane `l` tests with `pr[l]` (set for every lane of `mask`) into `best[l]`.
    /// A kernel may compute what depends on the origin and the axis order only once for
    /// all lanes; each lane's answer is its own `closest_leaf`'s, bit for bit.
    #[inline(always)]
    fn closest_leaf_lanes(
        blocks: &[TriBlock],
        mask: u32,
        pr: &[Option<PreparedRay>; PACKET],
        best: &mut [Hit; PACKET],
    ) {
        for l in lanes(mask) {
            Self::closest_leaf(blocks, lane(pr, l), &mut best[l]);
        }
    }

    /// [`Kernel::any`] over a leaf's blocks.
    ///
    /// A plain loop, not `iter().any(closure)`: the closure is a function without the
    /// caller's target features, which LLVM left out of line with every intrinsic of the
    /// block test a call (shadow rays ran 3–7× slower until this was a loop).
    #[inline(always)]
    fn any_leaf(blocks: &[TriBlock], r: &PreparedRay) -> bool {
        for b in blocks {
            if Self::any(b, r) {
                return true;
            }
        }
        false
    }

    /// Starts loading the cache lines of `x` (a child the traversal will visit later);
    /// no effect on any answer.
    #[inline(always)]
    fn prefetch<T>(x: &T) {
        let _ = x;
    }

    /// Starts loading the cache lines holding these addresses (a hint: they need not be
    /// valid, nothing is read through them).
    #[inline(always)]
    fn prefetch_lines(at: [usize; 4]) {
        let _ = at;
    }
}

/// The test constants of packet lane `l`, which the caller has set.
#[inline(always)]
pub(super) fn lane(pr: &[Option<PreparedRay>; PACKET], l: usize) -> &PreparedRay {
    pr[l].as_ref().expect("packet lane prepared before its leaf test")
}

/// The lanes of `mask` (not empty) whose axis order is the lowest lane's: with the
/// packet's shared origin, they share each block's vertices relative to it. (The SIMD
/// kernels' helper: the scalar kernel tests each lane alone.)
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn same_axis_order(mask: u32, pr: &[Option<PreparedRay>; PACKET]) -> u32 {
    let k = lane(pr, mask.trailing_zeros() as usize).k;
    // A loop, not `fold(closure)`: see `Kernel::any_leaf`.
    let mut same = 0;
    for l in lanes(mask) {
        same |= ((lane(pr, l).k == k) as u32) << l;
    }
    same
}

/// The portable kernel and the specification: the scalar triangle test on every real lane,
/// the box test of `Aabb::clip` on every child.
#[derive(Clone, Copy, Debug)]
pub struct Scalar;

/// `x`, or `other` when `x` is NaN: the x86 `maxps(x, -∞)` / `minps(x, +∞)` idiom of
/// the binary BVH's box test, so a NaN slab (origin on the plane, direction parallel)
/// leaves the ray unconstrained as `Aabb::clip`'s `slab` does.
#[inline(always)]
fn or_if_nan(x: f32, other: f32) -> f32 {
    if x.is_nan() {
        other
    } else {
        x
    }
}

impl Kernel for Scalar {
    #[inline(always)]
    fn boxes<N: WideNode>(node: &N, r: &BoxRay, tmin: f32, limit: f32, near: &mut Nears) -> u32 {
        let mut mask = 0;
        if tmin >= 0.0 {
            // `x > y ? x : y` and `x < y ? x : y` are x86's `maxps`/`minps`, the SIMD
            // kernels' operations: a NaN slab (origin on the plane, direction parallel)
            // leaves the interval as it was, and a NaN `limit` is ignored.
            let limit = if limit.is_nan() { f32::INFINITY } else { limit };
            for (i, near_i) in near.iter_mut().enumerate().take(node.count()) {
                let (mut n, mut f) = (tmin, limit);
                for a in 0..3 {
                    let (near_plane, far_plane) =
                        if r.neg[a] { (node.hi(a)[i], node.lo(a)[i]) } else { (node.lo(a)[i], node.hi(a)[i]) };
                    let tn = (near_plane - r.org[a]) * r.inv_near[a];
                    let tf = (far_plane - r.org[a]) * r.inv_far[a];
                    n = if tn > n { tn } else { n };
                    f = if tf < f { tf } else { f };
                }
                *near_i = n;
                mask |= ((n <= f) as u32) << i;
            }
            return mask;
        }
        for (i, near_i) in near.iter_mut().enumerate().take(node.count()) {
            let (mut n, mut f) = (f32::NEG_INFINITY, f32::INFINITY);
            for a in 0..3 {
                let t0 = (node.lo(a)[i] - r.org[a]) * r.inv[a];
                let t1 = (node.hi(a)[i] - r.org[a]) * r.inv[a];
                let (n0, n1) = (or_if_nan(t0, f32::NEG_INFINITY), or_if_nan(t1, f32::NEG_INFINITY));
                let (f0, f1) = (or_if_nan(t0, f32::INFINITY), or_if_nan(t1, f32::INFINITY));
                n = n.max(n0.min(n1));
                f = f.min(f0.max(f1));
            }
            // Widen outwards as `Aabb::clip` does, then clamp to the interval (a NaN
            // `tmin` or `limit` is ignored, as `f32::max`/`min` ignore it there).
            let n = n * if n > 0.0 { 1.0 - SLAB_MARGIN } else { 1.0 + SLAB_MARGIN };
            let f = f * if f > 0.0 { 1.0 + SLAB_MARGIN } else { 1.0 - SLAB_MARGIN };
            let n = if tmin > n { tmin } else { n };
            let f = if limit < f { limit } else { f };
            *near_i = n;
            mask |= ((n <= f) as u32) << i;
        }
        mask
    }

    #[inline(always)]
    fn closest(b: &TriBlock, r: &PreparedRay, best: &mut Hit) {
        let tris: [_; LANES] = std::array::from_fn(|l| b.triangle(l));
        best.closest_of(r, tris.iter().zip(b.ids).filter(|&(_, id)| id != PAD_ID));
    }

    #[inline(always)]
    fn any(b: &TriBlock, r: &PreparedRay) -> bool {
        (0..LANES).any(|l| !b.is_pad(l) && b.triangle(l).intersect(r, r.ray.tmax).is_some())
    }
}

/// Which kernel a tree traverses with, chosen once at build time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KernelChoice {
    /// [`Scalar`]: any CPU.
    Scalar,
    /// AVX2 (x86-64 with AVX2 detected at run time; never chosen elsewhere).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    Avx2,
    /// AVX-512 F and VL, with AVX2 (detected at run time; never chosen elsewhere).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    Avx512,
}

/// The kernel a build asks for (`kernel=` of `--accel bvh`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum KernelRequest {
    /// The fastest this CPU runs (AVX-512, else AVX2, else scalar), or scalar when
    /// [`FORCE_SCALAR_ENV`] is set.
    #[default]
    Auto,
    /// The scalar kernel everywhere.
    Scalar,
    /// AVX2; a build fails on a CPU without it.
    Avx2,
    /// AVX-512; a build fails on a CPU without it.
    Avx512,
}

impl KernelRequest {
    /// Names as `kernel=` spells them, in the enum's order.
    pub const NAMES: [&'static str; 4] = ["auto", "scalar", "avx2", "avx512"];

    /// The request named `NAMES[i]`.
    pub fn from_index(i: usize) -> Self {
        [KernelRequest::Auto, KernelRequest::Scalar, KernelRequest::Avx2, KernelRequest::Avx512][i]
    }

    /// As `kernel=` spells it.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The named kernels this CPU runs (scalar everywhere), for the tests and benches that
    /// cover each one.
    pub fn runnable() -> Vec<KernelRequest> {
        [KernelRequest::Scalar, KernelRequest::Avx2, KernelRequest::Avx512]
            .into_iter()
            .filter(|&k| KernelChoice::resolve(k).is_ok())
            .collect()
    }
}

/// True when this CPU runs the AVX-512 kernel: AVX2, AVX-512 F (the 512-bit f64 lanes) and
/// AVX-512 VL (mask compares on 256-bit registers).
#[cfg(target_arch = "x86_64")]
pub(super) fn avx512_available() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
        && std::arch::is_x86_feature_detected!("avx512f")
        && std::arch::is_x86_feature_detected!("avx512vl")
}

/// The environment variable that forces the scalar kernel on `kernel=auto` builds
/// (`DYNRAY_FORCE_SCALAR=1`), so a CI run on an AVX2 machine tests the fallback too.
pub const FORCE_SCALAR_ENV: &str = "DYNRAY_FORCE_SCALAR";

impl KernelChoice {
    /// The fastest kernel this CPU runs, unless [`FORCE_SCALAR_ENV`] says scalar.
    pub fn detect() -> Self {
        let forced = std::env::var_os(FORCE_SCALAR_ENV).is_some_and(|v| v != "0" && !v.is_empty());
        if forced {
            return KernelChoice::Scalar;
        }
        #[cfg(target_arch = "x86_64")]
        {
            if avx512_available() {
                return KernelChoice::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return KernelChoice::Avx2;
            }
        }
        KernelChoice::Scalar
    }

    /// The kernel `req` names, or why this CPU cannot run it.
    pub fn resolve(req: KernelRequest) -> Result<Self, String> {
        #[cfg(target_arch = "x86_64")]
        let (avx2, avx512) = (std::arch::is_x86_feature_detected!("avx2"), avx512_available());
        #[cfg(not(target_arch = "x86_64"))]
        let (avx2, avx512) = (false, false);
        match req {
            KernelRequest::Auto => Ok(Self::detect()),
            KernelRequest::Scalar => Ok(KernelChoice::Scalar),
            KernelRequest::Avx2 if avx2 => Ok(KernelChoice::Avx2),
            KernelRequest::Avx512 if avx512 => Ok(KernelChoice::Avx512),
            KernelRequest::Avx2 => Err("this CPU has no AVX2 (use auto or scalar)".into()),
            KernelRequest::Avx512 => Err("this CPU lacks AVX-512 F and VL (use auto, avx2 or scalar)".into()),
        }
    }

    /// As `stats` prints it.
    pub fn name(self) -> &'static str {
        match self {
            KernelChoice::Scalar => "scalar",
            KernelChoice::Avx2 => "avx2",
            KernelChoice::Avx512 => "avx512",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::node::{Node4, Node8};
    use dynray_geom::{Aabb, Triangle, Vec3};
    use rand::{rngs::SmallRng, Rng, SeedableRng};

    /// A triangle from a mix of random, shared and degenerate vertices, so ties, shared
    /// edges, zero-area and huge triangles all occur.
    fn adversarial_triangle(rng: &mut SmallRng, shared: &[Vec3]) -> Triangle {
        let pick = |rng: &mut SmallRng| match rng.gen_range(0..6) {
            0..=2 => shared[rng.gen_range(0..shared.len())],
            3 => Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)),
            4 => Vec3::new(rng.gen_range(-1e6..1e6), rng.gen_range(-1.0..1.0), rng.gen_range(-1e-6..1e-6)),
            _ => Vec3::splat(rng.gen_range(-1i32..=1) as f32),
        };
        let p0 = pick(rng);
        let p1 = if rng.gen_bool(0.1) { p0 } else { pick(rng) };
        Triangle::new(p0, p1, pick(rng))
    }

    fn ray(rng: &mut SmallRng, shared: &[Vec3]) -> Ray {
        let o = Vec3::new(rng.gen_range(-3.0..3.0), rng.gen_range(-3.0..3.0), rng.gen_range(-3.0..3.0));
        // Aim at a shared vertex (edge and vertex hits, ties) or along an axis.
        let d = match rng.gen_range(0..4) {
            0 | 1 => shared[rng.gen_range(0..shared.len())] - o,
            2 => [Vec3::X, Vec3::NEG_Y, Vec3::Z][rng.gen_range(0..3)],
            _ => Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)),
        };
        let tmin = [0.0, -1.0, f32::NEG_INFINITY, 0.5, -0.0, 1e-40][rng.gen_range(0..6)];
        let tmax = [f32::INFINITY, 1.0, 2.0, 0.0, f32::MIN_POSITIVE, 1e-40][rng.gen_range(0..6)];
        Ray::with_interval(o, d, tmin, tmax)
    }

    /// Runs `check` on blocks of random and adversarial triangles (some blocks padded)
    /// and rays aimed at their shared vertices.
    fn for_blocks(mut check: impl FnMut(&TriBlock, &[Triangle], &[u32], &Ray)) {
        let mut rng = SmallRng::seed_from_u64(41);
        let shared: Vec<Vec3> = (0..6)
            .map(|_| Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)))
            .chain([Vec3::ZERO, Vec3::X, Vec3::Y])
            .collect();
        for i in 0..40_000 {
            let n = 1 + i % LANES;
            let mut tris: Vec<Triangle> = (0..n).map(|_| adversarial_triangle(&mut rng, &shared)).collect();
            if i % 7 == 0 && n > 1 {
                // The same triangle twice: equal `t`, the lower id must win.
                tris[n - 1] = tris[0];
            }
            let ids: Vec<u32> = (0..n as u32).map(|k| [k * 3, 100 - k, 7 + k][i % 3]).collect();
            let mut blocks = Vec::new();
            TriBlock::pack(&tris, &ids, &mut blocks);
            for _ in 0..4 {
                let ray = ray(&mut rng, &shared);
                check(&blocks[0], &tris, &ids, &ray);
                for pinned in pinned_to_hit(&tris, &ids, &ray) {
                    check(&blocks[0], &tris, &ids, &pinned);
                }
            }
        }
    }

    /// `ray` with its interval shrunk to the closest hit's `t` at one end or both (none
    /// when it misses): the bounds of `tmin <= t <= tmax` are then met with equality,
    /// which random intervals almost never do.
    fn pinned_to_hit(tris: &[Triangle], ids: &[u32], ray: &Ray) -> Vec<Ray> {
        let h = spec_closest(tris, ids, &PreparedRay::new(ray), Hit::MISS);
        if !h.is_hit() {
            return Vec::new();
        }
        let at = |tmin, tmax| Ray::with_interval(ray.origin, ray.dir, tmin, tmax);
        // One f32 either side of the hit too: one end just excludes it, one just admits it.
        vec![
            at(h.t, h.t),
            at(h.t, ray.tmax),
            at(ray.tmin, h.t),
            at(ray.tmin, h.t.next_down()),
            at(ray.tmin, h.t.next_up()),
            at(h.t.next_down(), ray.tmax),
            at(h.t.next_up(), ray.tmax),
        ]
    }

    /// The spec: `Hit::closest_of` over the triangles in order, starting from `start`.
    fn spec_closest(tris: &[Triangle], ids: &[u32], r: &PreparedRay, start: Hit) -> Hit {
        let mut h = start;
        h.closest_of(r, tris.iter().zip(ids.iter().copied()));
        h
    }

    fn starts(r: &Ray) -> [Hit; 3] {
        [Hit::MISS, Hit { t: 1.0, u: 0.5, v: 0.25, prim: 50 }, Hit { t: r.tmax.min(3.0), u: 0.0, v: 0.0, prim: 0 }]
    }

    fn same(a: &Hit, b: &Hit) -> bool {
        a.same_as(b) && a.u.to_bits() == b.u.to_bits() && a.v.to_bits() == b.v.to_bits()
    }

    #[test]
    fn scalar_block_is_the_scalar_test() {
        let mut hits = 0;
        for_blocks(|b, tris, ids, ray| {
            let r = PreparedRay::new(ray);
            for start in starts(ray) {
                let mut got = start;
                Scalar::closest(b, &r, &mut got);
                let want = spec_closest(tris, ids, &r, start);
                assert!(same(&got, &want), "{tris:?} {ray:?}: {got:?} vs {want:?}");
                hits += (want.prim != start.prim) as u32;
            }
            let any = tris.iter().any(|t| t.intersect(&r, ray.tmax).is_some());
            assert_eq!(Scalar::any(b, &r), any, "{tris:?} {ray:?}");
        });
        // The sets must exercise hits, not only misses.
        assert!(hits > 10_000, "{hits} hits");
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_block_is_bit_identical_to_the_scalar_test() {
        use super::super::kernel_avx2::Avx2;
        if !std::arch::is_x86_feature_detected!("avx2") {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        let mut hits = 0;
        for_blocks(|b, tris, ids, ray| {
            let r = PreparedRay::new(ray);
            for start in starts(ray) {
                let got = Avx2::closest_checked(b, &r, start);
                let want = spec_closest(tris, ids, &r, start);
                assert!(same(&got, &want), "{tris:?} {ray:?}: {got:?} vs {want:?}");
                hits += (want.prim != start.prim) as u32;
            }
            let any = tris.iter().any(|t| t.intersect(&r, ray.tmax).is_some());
            assert_eq!(Avx2::any_checked(b, &r), any, "{tris:?} {ray:?}");
        });
        assert!(hits > 10_000, "{hits} hits");
    }

    /// Leaves of 1..=8 blocks (the AVX-512 kernel tests blocks in pairs, the last one of
    /// an odd count alone) through `closest_leaf` and `any_leaf`, against the scalar test
    /// over the leaf's triangles.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx512_leaves_are_bit_identical_to_the_scalar_test() {
        use super::super::kernel_avx512::Avx512;
        if !avx512_available() {
            eprintln!("skipped: this CPU lacks AVX-512 F and VL");
            return;
        }
        let mut rng = SmallRng::seed_from_u64(43);
        let shared: Vec<Vec3> = (0..6)
            .map(|_| Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)))
            .chain([Vec3::ZERO, Vec3::X, Vec3::Y])
            .collect();
        let mut hits = 0;
        for i in 0..20_000 {
            // 1..=32 triangles: every block count, full and padded last blocks.
            let n = 1 + i % 32;
            let mut tris: Vec<Triangle> = (0..n).map(|_| adversarial_triangle(&mut rng, &shared)).collect();
            if i % 5 == 0 && n > 4 {
                // A tie across the two blocks of a pair: the lower id must win.
                tris[n - 1] = tris[0];
            }
            let ids: Vec<u32> = (0..n as u32).map(|k| [k * 3, 1000 - k, 7 + k][i % 3]).collect();
            let mut blocks = Vec::new();
            TriBlock::pack(&tris, &ids, &mut blocks);
            let first = ray(&mut rng, &shared);
            for ray in std::iter::once(first).chain(pinned_to_hit(&tris, &ids, &first)) {
                let r = PreparedRay::new(&ray);
                for start in starts(&ray) {
                    let got = Avx512::closest_leaf_checked(&blocks, &r, start);
                    let want = spec_closest(&tris, &ids, &r, start);
                    assert!(same(&got, &want), "{n} triangles, {ray:?}: {got:?} vs {want:?}");
                    hits += (want.prim != start.prim) as u32;
                }
                let any = tris.iter().any(|t| t.intersect(&r, ray.tmax).is_some());
                assert_eq!(Avx512::any_leaf_checked(&blocks, &r), any, "{n} triangles, {ray:?}");
            }
        }
        assert!(hits > 10_000, "{hits} hits");
    }

    #[test]
    fn pad_lanes_never_hit() {
        let mut rng = SmallRng::seed_from_u64(3);
        let shared = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let pad = TriBlock::PAD;
        for _ in 0..20_000 {
            let mut ray = ray(&mut rng, &shared);
            ray.tmin = f32::NEG_INFINITY;
            ray.tmax = f32::INFINITY;
            let r = PreparedRay::new(&ray);
            // The scalar test on the NaN triangle itself: what the SIMD lanes compute.
            assert_eq!(pad.triangle(0).intersect(&r, f32::INFINITY), None);
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                use super::super::kernel_avx2::Avx2;
                assert!(!Avx2::any_checked(&pad, &r));
                assert!(!Avx2::closest_checked(&pad, &r, Hit::MISS).is_hit());
            }
            #[cfg(target_arch = "x86_64")]
            if avx512_available() {
                use super::super::kernel_avx512::Avx512;
                let pair = [pad, pad];
                assert!(!Avx512::any_leaf_checked(&pair, &r));
                assert!(!Avx512::closest_leaf_checked(&pair, &r, Hit::MISS).is_hit());
            }
        }
    }

    /// Random boxes on a small integer grid (so rays start on box planes and run parallel
    /// to them, where slabs are NaN), then random boxes and rays, with intervals on both
    /// sides of the kernels' `tmin >= 0` branch: `check(node, boxes, ray)`.
    fn box_cases<N: WideNode>(mut check: impl FnMut(&N, &[Aabb], &Ray)) {
        let mut rng = SmallRng::seed_from_u64(5);
        let grid = |rng: &mut SmallRng| {
            Vec3::new(rng.gen_range(-3..=3) as f32, rng.gen_range(-3..=3) as f32, rng.gen_range(-3..=3) as f32)
        };
        for i in 0..30_000 {
            let mut node = N::empty();
            let mut boxes = Vec::new();
            for _ in 0..(1 + i % N::W) {
                let (a, b) = (grid(&mut rng), grid(&mut rng));
                let bx = Aabb::new(a.min(b), a.max(b));
                node.push(boxes.len() as u32, &bx);
                boxes.push(bx);
            }
            let (o, d) = if i % 2 == 0 {
                let d = grid(&mut rng);
                (grid(&mut rng), if d == Vec3::ZERO { Vec3::X } else { d })
            } else {
                let v = |rng: &mut SmallRng| {
                    Vec3::new(rng.gen_range(-4.0..4.0), rng.gen_range(-4.0..4.0), rng.gen_range(-4.0..4.0))
                };
                (v(&mut rng), v(&mut rng))
            };
            // `tmin >= 0` (the first, fourth and fifth) and not.
            let tmin = [0.0, -1.0, f32::NEG_INFINITY, 0.5, -0.0, f32::NAN][i % 6];
            let limit = [f32::INFINITY, 1.0, 3.0, 0.25][(i / 6) % 4];
            check(&node, &boxes, &Ray::with_interval(o, d, tmin, limit));
        }
    }

    /// Every kernel computes the specification's mask and near distances.
    #[cfg(target_arch = "x86_64")]
    fn check_boxes<N: WideNode>(kernel_boxes: impl Fn(&N, &BoxRay, f32, f32, &mut Nears) -> u32) {
        box_cases::<N>(|node, boxes, ray| {
            let (mut near, mut want_near) = ([0.0; 8], [0.0; 8]);
            let br = BoxRay::new(ray);
            let mask = kernel_boxes(node, &br, ray.tmin, ray.tmax, &mut near);
            let want = Scalar::boxes(node, &br, ray.tmin, ray.tmax, &mut want_near);
            assert_eq!(mask, want, "boxes {boxes:?} ray {ray:?}");
            for k in (0..boxes.len()).filter(|&k| want >> k & 1 == 1) {
                // Equal as numbers (-0 and +0 may differ; entry distances are only compared).
                assert_eq!(near[k], want_near[k], "box {:?} ray {ray:?}", boxes[k]);
            }
        });
    }

    /// Where `tmin < 0` (or NaN) the specification is `Aabb::clip` lane by lane.
    #[test]
    fn below_zero_tmin_box_test_is_aabb_clip() {
        fn check<N: WideNode>() {
            box_cases::<N>(|node, boxes, ray| {
                if ray.tmin >= 0.0 {
                    return;
                }
                let mut near = [0.0; 8];
                let mask = Scalar::boxes(node, &BoxRay::new(ray), ray.tmin, ray.tmax, &mut near);
                let pr = PreparedRay::new(ray);
                for (k, bx) in boxes.iter().enumerate() {
                    let want = bx.clip(&pr, ray.tmin, ray.tmax);
                    assert_eq!(mask >> k & 1 == 1, want.is_some(), "box {bx:?} ray {ray:?}");
                    if let Some((n, _)) = want {
                        assert_eq!(near[k], n, "box {bx:?} ray {ray:?}");
                    }
                }
                assert_eq!(mask >> boxes.len(), 0, "unused lanes must never be entered");
            });
        }
        check::<Node4>();
        check::<Node8>();
    }

    /// Both forms of the box test against exact arithmetic: every box whose exact slab
    /// interval, widened by half the margin, meets `[tmin, limit]` is entered, no later
    /// than that widened entry. Half the margin is what stays for the triangle test's
    /// own rounding once the box test's four roundings are paid.
    #[test]
    fn box_test_is_conservative() {
        const HALF: f64 = SLAB_MARGIN as f64 / 2.0;
        let widen = |x: f64, up: bool| if x.is_finite() { x + if up { HALF } else { -HALF } * x.abs() } else { x };
        fn check<N: WideNode>(widen: impl Fn(f64, bool) -> f64) {
            let mut entered_by_margin = 0;
            box_cases::<N>(|node, boxes, ray| {
                if ray.tmin.is_nan() {
                    return;
                }
                let mut near = [0.0; 8];
                let mask = Scalar::boxes(node, &BoxRay::new(ray), ray.tmin, ray.tmax, &mut near);
                let (o, d) = (ray.origin.to_array(), ray.dir.to_array());
                for (k, bx) in boxes.iter().enumerate() {
                    let (lo, hi) = (bx.min.to_array(), bx.max.to_array());
                    let (mut n, mut f) = (f64::NEG_INFINITY, f64::INFINITY);
                    for a in 0..3 {
                        if d[a] == 0.0 {
                            if o[a] < lo[a] || o[a] > hi[a] {
                                f = f64::NEG_INFINITY;
                            }
                            continue;
                        }
                        // f32 differences are exact in f64 here; the quotient is within 2⁻⁵³.
                        let t0 = (lo[a] as f64 - o[a] as f64) / d[a] as f64;
                        let t1 = (hi[a] as f64 - o[a] as f64) / d[a] as f64;
                        n = n.max(t0.min(t1));
                        f = f.min(t0.max(t1));
                    }
                    let n = widen(n, false).max(ray.tmin as f64);
                    let f = widen(f, true).min(ray.tmax as f64);
                    if n <= f {
                        assert_eq!(mask >> k & 1, 1, "box {bx:?} ray {ray:?}: exact [{n}, {f}]");
                        assert!(near[k] as f64 <= n, "box {bx:?} ray {ray:?}: near {} after {n}", near[k]);
                    } else if mask >> k & 1 == 1 {
                        entered_by_margin += 1;
                    }
                }
            });
            // The margin admits a few boxes exact arithmetic would not, not many.
            assert!(entered_by_margin < 300, "{entered_by_margin} boxes entered only by the margin");
        }
        check::<Node4>(widen);
        check::<Node8>(widen);
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_box_test_is_the_scalar_test() {
        use super::super::kernel_avx2::Avx2;
        if !std::arch::is_x86_feature_detected!("avx2") {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        check_boxes::<Node4>(Avx2::boxes_checked);
        check_boxes::<Node8>(Avx2::boxes_checked);
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx512_box_test_is_the_scalar_test() {
        use super::super::kernel_avx512::Avx512;
        if !avx512_available() {
            eprintln!("skipped: this CPU lacks AVX-512 F and VL");
            return;
        }
        check_boxes::<Node4>(Avx512::boxes_checked);
        check_boxes::<Node8>(Avx512::boxes_checked);
    }
}
