//! Many independent rays on one thread with several in flight: the single-ray walk cut
//! into steps (one node or one leaf each), taken round-robin over `N` rays, each step
//! ending with a prefetch of what its ray visits next.
//!
//! Why: a single ray's walk is a chain of dependent loads (a node's box test decides the
//! next address), so one ray keeps the core waiting on L2/L3 most of the time. While one
//! ray's next node is on its way, the other rays' steps run. Each ray takes exactly the
//! steps `traverse.rs` takes for it alone, in the same order, so every answer is
//! [`super::WideTree::closest`]'s / `any`'s bit for bit; only the interleaving differs.
//!
//! Batches that are not interleaved (coherent ones under `interleave=auto`, or `off`) run
//! the single-ray walk one ray after the other on one stack for the whole batch, which
//! spares the per-ray stack set-up of `closest`; coherent any-hit batches walked that way
//! test the last occluder's leaf first (`occluder_cache`, [`WideTree::any_each`]).

#[cfg(target_arch = "x86_64")]
use super::kernel::KernelChoice;
use super::kernel::{BoxRay, Kernel, Nears, Scalar};
use super::node::{is_leaf, leaf_blocks, ChildRef, WideNode};
use super::traverse::{next_of_one_or_two, prepared, push_hits, Below, Entry, SMALL_STACK, STACK_CAPACITY};
use super::WideTree;
use crate::NoCount;
use dynray_geom::{Hit, PreparedRay, Ray};

/// One ray's walk in progress, what the single-ray loop keeps in registers.
struct Walk<T, const S: usize> {
    /// Index of the ray in the batch.
    ray: usize,
    br: BoxRay,
    /// The triangle test's constants, made at the ray's first leaf.
    pr: Option<PreparedRay>,
    best: Hit,
    /// The node or leaf the next step visits.
    cur: ChildRef,
    sp: usize,
    stack: [T; S],
    /// `false` once its ray is done and no ray is left to start.
    live: bool,
}

impl<T: Copy + Default, const S: usize> Walk<T, S> {
    fn idle() -> Self {
        Self {
            ray: 0,
            br: BoxRay::from_parts([0.0; 3], [0.0; 3]),
            pr: None,
            best: Hit::MISS,
            cur: 0,
            sp: 0,
            stack: [T::default(); S],
            live: false,
        }
    }

    /// Starts ray `i` at the root (the stack's old entries lie above `sp` and are never read).
    #[inline(always)]
    fn start(&mut self, i: usize, ray: &Ray) {
        self.ray = i;
        self.br = BoxRay::new(ray);
        self.pr = None;
        self.best = Hit::MISS;
        self.cur = 0;
        self.sp = 0;
        self.live = true;
    }
}

/// How [`WideTree::any_stream`] walks a batch of any-hit queries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum AnyBatch {
    /// [`IN_FLIGHT`] rays interleaved.
    Interleaved,
    /// One ray after the other.
    Each,
    /// One ray after the other, each testing the last occluder's leaf first.
    EachCached,
}

/// Rays in flight per thread. Measured in docs/structures.md ("Streams").
pub const IN_FLIGHT: usize = 2;

/// When a batch of independent rays is interleaved (`interleave=` of [`super::WbvhParams`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interleave {
    /// Interleave batches that do not look coherent ([`looks_coherent`]) on trees of at
    /// least [`INTERLEAVE_MIN_BYTES`].
    Auto,
    /// Always.
    On,
    /// Never: one ray after the other.
    Off,
}

impl Interleave {
    /// The values `interleave=` takes, in declaration order.
    pub const NAMES: [&'static str; 3] = ["auto", "on", "off"];

    /// The policy named `NAMES[i]`.
    pub fn from_index(i: usize) -> Self {
        [Interleave::Auto, Interleave::On, Interleave::Off][i]
    }

    /// Whether `rays` are traced interleaved under this policy, on a tree of `tree_bytes`.
    pub fn applies(self, rays: &[Ray], tree_bytes: usize) -> bool {
        match self {
            Interleave::Auto => tree_bytes >= INTERLEAVE_MIN_BYTES && !looks_coherent(rays),
            Interleave::On => true,
            Interleave::Off => false,
        }
    }
}

/// Trees below this size are not interleaved under `auto`: interleaving hides the wait for
/// nodes and blocks that come from L3 or memory, and where the tree sits mostly in a
/// core's L2 its bookkeeping costs more than it hides. Measured (docs/structures.md,
/// "Streams"): on the 47 MiB dragon, random rays +11–47 % and diffuse +4–15 %; on the
/// 6.1 MiB BART kitchen, random −6 to −16 % and diffuse −15 to −37 %; on the 3.8 MiB
/// bunny, random +0–32 % but diffuse −6 to +16 %.
pub const INTERLEAVE_MIN_BYTES: usize = 16 << 20;

/// Consecutive directions within this cosine (about 8°) count as coherent.
const COHERENT_COS: f32 = 0.99;

/// Consecutive pairs [`looks_coherent`] looks at, spread over the batch (a few ns each).
const SAMPLED_PAIRS: usize = 32;

/// True when at least half of up to `SAMPLED_PAIRS` (32) consecutive ray pairs spread over
/// `rays` point the same way within about 8° (camera rays of neighbouring pixels, shadow
/// rays of neighbouring points towards one light). Such rays find their nodes in cache and
/// their branches predicted, and interleaving them only adds its bookkeeping; incoherent
/// rays (random, diffuse bounces) wait on memory, which interleaving overlaps. Either way
/// the answers are the same.
pub fn looks_coherent(rays: &[Ray]) -> bool {
    let pairs = rays.len().saturating_sub(1);
    let sampled = pairs.min(SAMPLED_PAIRS);
    let close = (0..sampled)
        .map(|k| k * pairs / sampled)
        .filter(|&i| {
            let (a, b) = (rays[i].dir, rays[i + 1].dir);
            // cos ≥ c ⇔ a·b ≥ 0 and (a·b)² ≥ c² |a|² |b|² (no square roots; false on NaN).
            let d = a.dot(b);
            d >= 0.0 && d * d >= COHERENT_COS * COHERENT_COS * a.length_squared() * b.length_squared()
        })
        .count();
    2 * close >= sampled
}

impl<N: WideNode> WideTree<N> {
    /// `hits[i]` = `closest(rays[i])` for every ray: [`IN_FLIGHT`] rays interleaved, or
    /// (`interleaved == false`) one after the other on one stack.
    #[allow(unsafe_code)]
    pub(super) fn closest_stream(&self, rays: &[Ray], hits: &mut [Hit], interleaved: bool) {
        #[cfg(target_arch = "x86_64")]
        match self.kernel {
            // SAFETY: as in `WideTree::closest` (the kernel was detected at build time).
            KernelChoice::Avx512 => return unsafe { self.closest_stream_avx512(rays, hits, interleaved) },
            KernelChoice::Avx2 => return unsafe { self.closest_stream_avx2(rays, hits, interleaved) },
            KernelChoice::Scalar => {}
        }
        self.closest_stream_sized::<Scalar>(rays, hits, interleaved)
    }

    /// `out[i]` = `any(rays[i])` for every ray, as [`WideTree::closest_stream`]; `how`
    /// picks interleaved, one after the other, or one after the other with the
    /// last-occluder cache ([`AnyBatch`]).
    #[allow(unsafe_code)]
    pub(super) fn any_stream(&self, rays: &[Ray], out: &mut [bool], how: AnyBatch) {
        #[cfg(target_arch = "x86_64")]
        match self.kernel {
            // SAFETY: as in `closest_stream`.
            KernelChoice::Avx512 => return unsafe { self.any_stream_avx512(rays, out, how) },
            KernelChoice::Avx2 => return unsafe { self.any_stream_avx2(rays, out, how) },
            KernelChoice::Scalar => {}
        }
        self.any_stream_sized::<Scalar>(rays, out, how)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    unsafe fn closest_stream_avx2(&self, rays: &[Ray], hits: &mut [Hit], interleaved: bool) {
        self.closest_stream_sized::<super::kernel_avx2::Avx2>(rays, hits, interleaved)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,avx512f,avx512vl")]
    #[allow(unsafe_code)]
    unsafe fn closest_stream_avx512(&self, rays: &[Ray], hits: &mut [Hit], interleaved: bool) {
        self.closest_stream_sized::<super::kernel_avx512::Avx512>(rays, hits, interleaved)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    unsafe fn any_stream_avx2(&self, rays: &[Ray], out: &mut [bool], how: AnyBatch) {
        self.any_stream_sized::<super::kernel_avx2::Avx2>(rays, out, how)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,avx512f,avx512vl")]
    #[allow(unsafe_code)]
    unsafe fn any_stream_avx512(&self, rays: &[Ray], out: &mut [bool], how: AnyBatch) {
        self.any_stream_sized::<super::kernel_avx512::Avx512>(rays, out, how)
    }

    #[inline(always)]
    fn closest_stream_sized<K: Kernel>(&self, rays: &[Ray], hits: &mut [Hit], interleaved: bool) {
        crate::batch::check_batch_lengths(rays.len(), hits.len());
        match (interleaved, self.stack_need <= SMALL_STACK) {
            (true, true) => self.closest_stream_with::<K, SMALL_STACK>(rays, hits),
            (true, false) => self.closest_stream_with::<K, STACK_CAPACITY>(rays, hits),
            (false, true) => self.closest_each_with::<K, SMALL_STACK>(rays, hits),
            (false, false) => self.closest_each_with::<K, STACK_CAPACITY>(rays, hits),
        }
    }

    /// One ray after the other, as `closest` walks each, on one stack for the batch
    /// (`closest` sets up a stack per ray).
    #[inline(always)]
    fn closest_each_with<K: Kernel, const S: usize>(&self, rays: &[Ray], hits: &mut [Hit]) {
        let mut stack = [Entry::default(); S];
        for (ray, hit) in rays.iter().zip(hits) {
            let mut pr = None;
            *hit = Hit::MISS;
            let b = Below { root: 0, ray, br: &BoxRay::new(ray), tmin: ray.tmin, tmax: ray.tmax };
            self.closest_below::<K, NoCount>(&b, &mut pr, hit, &mut stack, &mut NoCount);
        }
    }

    #[inline(always)]
    fn any_stream_sized<K: Kernel>(&self, rays: &[Ray], out: &mut [bool], how: AnyBatch) {
        crate::batch::check_batch_lengths(rays.len(), out.len());
        let small = self.stack_need <= SMALL_STACK;
        match how {
            AnyBatch::Interleaved if small => self.any_stream_with::<K, SMALL_STACK>(rays, out),
            AnyBatch::Interleaved => self.any_stream_with::<K, STACK_CAPACITY>(rays, out),
            AnyBatch::EachCached if small => self.any_each::<K, SMALL_STACK, true>(rays, out),
            AnyBatch::EachCached => self.any_each::<K, STACK_CAPACITY, true>(rays, out),
            AnyBatch::Each if small => self.any_each::<K, SMALL_STACK, false>(rays, out),
            AnyBatch::Each => self.any_each::<K, STACK_CAPACITY, false>(rays, out),
        }
    }

    /// One ray after the other on one stack, as [`WideTree::closest_each_with`]; with
    /// `CACHED`, a last-occluder cache (Haines and Greenberg's shadow cache): a ray that
    /// follows an occluded one tests the leaf that occluded it first, and is done if that
    /// leaf holds a hit. The leaf test is the walk's own, so the answers are the uncached
    /// ones exactly; only the work changes. A ray that is not occluded empties the cache,
    /// so runs of lit points pay no extra test.
    #[inline(always)]
    fn any_each<K: Kernel, const S: usize, const CACHED: bool>(&self, rays: &[Ray], out: &mut [bool]) {
        let mut stack = [0 as ChildRef; S];
        let mut last: Option<ChildRef> = None;
        for (ray, o) in rays.iter().zip(out) {
            let mut pr = None;
            if let Some(leaf) = last {
                let (first, count) = leaf_blocks(leaf);
                if K::any_leaf(&self.blocks[first..first + count], prepared(&mut pr, ray)) {
                    *o = true;
                    continue;
                }
            }
            let b = Below { root: 0, ray, br: &BoxRay::new(ray), tmin: ray.tmin, tmax: ray.tmax };
            let found = self.any_below::<K, NoCount>(&b, &mut pr, &mut stack, &mut NoCount);
            *o = found.is_some();
            if CACHED {
                last = found;
            }
        }
    }

    #[inline(always)]
    fn closest_stream_with<K: Kernel, const S: usize>(&self, rays: &[Ray], hits: &mut [Hit]) {
        let mut walks: [Walk<Entry, S>; IN_FLIGHT] = std::array::from_fn(|_| Walk::idle());
        let mut next = 0;
        for w in walks.iter_mut().take(rays.len()) {
            w.start(next, &rays[next]);
            next += 1;
        }
        let mut live = walks.iter().filter(|w| w.live).count();
        while live > 0 {
            for w in walks.iter_mut() {
                if !w.live {
                    continue;
                }
                if !self.closest_step::<K, S>(&rays[w.ray], w) {
                    hits[w.ray] = w.best;
                    if next < rays.len() {
                        w.start(next, &rays[next]);
                        next += 1;
                    } else {
                        w.live = false;
                        live -= 1;
                    }
                }
            }
        }
    }

    #[inline(always)]
    fn any_stream_with<K: Kernel, const S: usize>(&self, rays: &[Ray], out: &mut [bool]) {
        let mut walks: [Walk<ChildRef, S>; IN_FLIGHT] = std::array::from_fn(|_| Walk::idle());
        let mut next = 0;
        for w in walks.iter_mut().take(rays.len()) {
            w.start(next, &rays[next]);
            next += 1;
        }
        let mut live = walks.iter().filter(|w| w.live).count();
        while live > 0 {
            for w in walks.iter_mut() {
                if !w.live {
                    continue;
                }
                if let Some(hit) = self.any_step::<K, S>(&rays[w.ray], w) {
                    out[w.ray] = hit;
                    if next < rays.len() {
                        w.start(next, &rays[next]);
                        next += 1;
                    } else {
                        w.live = false;
                        live -= 1;
                    }
                }
            }
        }
    }

    /// One step of `closest_below` for `w`'s ray: visits `w.cur` and picks the next node
    /// or leaf (prefetched); `false` when the ray is done (its answer is `w.best`).
    #[inline(always)]
    fn closest_step<K: Kernel, const S: usize>(&self, ray: &Ray, w: &mut Walk<Entry, S>) -> bool {
        let cur = w.cur;
        if is_leaf(cur) {
            let pr = prepared(&mut w.pr, ray);
            let (first, count) = leaf_blocks(cur);
            K::closest_leaf(&self.blocks[first..first + count], pr, &mut w.best);
        } else {
            let node = &self.nodes[cur as usize];
            let mut near: Nears = [0.0; 8];
            let mask = K::boxes(node, &w.br, ray.tmin, w.best.t.min(ray.tmax), &mut near);
            if mask != 0 {
                if mask.count_ones() <= 2 {
                    let (next, deferred) = next_of_one_or_two(node, mask, &near, cur, &mut w.stack, &mut w.sp);
                    self.prefetch_child_branch_free::<K>(deferred);
                    self.prefetch_child_branch_free::<K>(next);
                    w.cur = next;
                    return true;
                }
                let start = w.sp;
                w.cur = push_hits(node, mask, &near, &mut w.stack, &mut w.sp);
                for e in &w.stack[start..w.sp] {
                    self.prefetch_child_branch_free::<K>(e.node);
                }
                self.prefetch_child_branch_free::<K>(w.cur);
                return true;
            }
        }
        loop {
            if w.sp == 0 {
                return false;
            }
            w.sp -= 1;
            let e = w.stack[w.sp];
            if e.t <= w.best.t {
                w.cur = e.node;
                return true;
            }
        }
    }

    /// One step of the any-hit walk for `w`'s ray: `Some(answer)` when the ray is done.
    #[inline(always)]
    fn any_step<K: Kernel, const S: usize>(&self, ray: &Ray, w: &mut Walk<ChildRef, S>) -> Option<bool> {
        let cur = w.cur;
        if is_leaf(cur) {
            let pr = prepared(&mut w.pr, ray);
            let (first, count) = leaf_blocks(cur);
            if K::any_leaf(&self.blocks[first..first + count], pr) {
                return Some(true);
            }
        } else {
            let node = &self.nodes[cur as usize];
            let mut near: Nears = [0.0; 8];
            let m = K::boxes(node, &w.br, ray.tmin, ray.tmax, &mut near);
            if m != 0 {
                w.cur = self.push_any::<K>(node, m, &mut w.stack, &mut w.sp);
                self.prefetch_child::<K>(w.cur);
                return None;
            }
        }
        if w.sp == 0 {
            return Some(false);
        }
        w.sp -= 1;
        w.cur = w.stack[w.sp];
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_geom::Vec3;

    fn rays(dirs: impl Iterator<Item = Vec3>) -> Vec<Ray> {
        dirs.map(|d| Ray::new(Vec3::ZERO, d)).collect()
    }

    #[test]
    fn camera_rows_look_coherent_and_scattered_rays_do_not() {
        // A 64 × 16 image of a 60° camera: neighbours a fraction of a degree apart.
        let camera = rays((0..16 * 64).map(|i| Vec3::new((i % 64) as f32 / 64.0 - 0.5, (i / 64) as f32 / 64.0, -1.0)));
        assert!(looks_coherent(&camera));
        // Directions stepping ~137° around a circle: never within 8° of the last.
        let scattered = rays((0..1024).map(|i| {
            let a = i as f32 * 2.4;
            Vec3::new(a.cos(), a.sin(), 0.1)
        }));
        assert!(!looks_coherent(&scattered));
        // Opposite directions are not coherent (the sign of the dot product counts).
        assert!(!looks_coherent(&rays((0..100).map(|i| Vec3::new(0.0, 0.0, if i % 2 == 0 { 1.0 } else { -1.0 })))));
    }

    #[test]
    fn tiny_and_nan_batches_are_decided_without_panicking() {
        assert!(looks_coherent(&[]));
        assert!(looks_coherent(&rays([Vec3::X].into_iter())));
        assert!(looks_coherent(&rays([Vec3::X, Vec3::X].into_iter())));
        // NaN directions compare false: never counted as close.
        assert!(!looks_coherent(&rays((0..10).map(|_| Vec3::splat(f32::NAN)))));
    }

    #[test]
    fn the_policy_follows_the_key() {
        let scattered = rays((0..64).map(|i| {
            let a = i as f32 * 2.4;
            Vec3::new(a.cos(), a.sin(), 0.1)
        }));
        let parallel = rays((0..64).map(|_| Vec3::Z));
        let (big, small) = (INTERLEAVE_MIN_BYTES, INTERLEAVE_MIN_BYTES - 1);
        assert!(Interleave::Auto.applies(&scattered, big) && !Interleave::Auto.applies(&parallel, big));
        assert!(!Interleave::Auto.applies(&scattered, small));
        assert!(Interleave::On.applies(&parallel, small) && !Interleave::Off.applies(&scattered, big));
        for (i, name) in Interleave::NAMES.iter().enumerate() {
            assert_eq!(Interleave::NAMES[Interleave::from_index(i) as usize], *name);
        }
    }
}
