//! Closest-hit and any-hit traversal of the wide BVH: one box test per node for all its
//! children, hit children visited nearest first, boxes culled against the best `t`.
//!
//! The traversal is written once, generic over the node width and the [`Kernel`]; the AVX2
//! and AVX-512 entry points below are the same code compiled with `#[target_feature]`, so
//! the kernel's intrinsics and the traversal loop inline into one function.

#[cfg(target_arch = "x86_64")]
use super::kernel::KernelChoice;
use super::kernel::{BoxRay, Kernel, Nears, Scalar};
use super::node::{is_leaf, leaf_blocks, ChildRef, WideNode, LEAF_BIT};
use super::WideTree;
use crate::Counter;
use dynray_geom::{Hit, PreparedRay, Ray};

/// Stack entries of trees whose bound (see [`stack_need`]) fits: 768 bytes to set up per
/// ray, enough for 13 levels of an 8-wide tree (the 871k-triangle dragon has 9). Deeper
/// trees (pathological meshes) use [`STACK_CAPACITY`], whose 8 KB memset per ray cost the
/// dragon's random rays ~10 % when its bound briefly exceeded a 64-entry stack.
pub(super) const SMALL_STACK: usize = 96;
/// The largest stack: `validate` rejects trees whose [`stack_need`] exceeds it. The
/// binary builder's depth bound (`MAX_DEPTH` = 96) times 7 fits.
pub(super) const STACK_CAPACITY: usize = 1024;

/// Entries the traversal stack can need for a tree with `levels` interior levels: each
/// interior node visited pushes its hit children (at most `W`) and pops the nearest, so at
/// most `W - 1` entries per level stay, plus `W` for the node being expanded, plus one: a
/// node with one hit child writes (and does not keep) an entry above the top
/// ([`next_of_one_or_two`]).
pub(super) fn stack_need(levels: u32, width: usize) -> usize {
    levels as usize * (width - 1) + 2
}

/// A deferred child and its entry distance when it was pushed.
#[derive(Clone, Copy, Default, Debug, PartialEq)]
pub(super) struct Entry {
    pub node: ChildRef,
    pub t: f32,
}

/// Pushes the children in `mask` (two or more) but the nearest onto `stack` above `sp`,
/// farthest deepest, and returns the nearest, which the walk visits next: two children
/// by one compare into conditional moves, more by an insertion sort (usually 3); ties go
/// to the higher lane. Shared by the single-ray walk and the interleaved one (stream.rs).
///
/// The two-child case (round 7) spares incoherent rays the loop's data-dependent exits:
/// one thread, best of 3 alternated rounds, diffuse +1–4 %, random +1–3 %, primary
/// within ±1 % (bunny, dragon, kitchen, duck); in round 4's two-thread bench runs the same
/// change had looked like noise (0.99–1.03×). Three children by a 3-comparator network as
/// well: −1 to +2 %, dropped. Also dropped: a 19-comparator sorting network over all 8
/// lanes (slower on primary rays, see kernel_avx512.rs), and pushing in a per-octant
/// order precomputed in the node (docs/structures.md, "Where it stands").
#[inline(always)]
pub(super) fn push_hits<N: WideNode>(
    node: &N,
    mask: u32,
    near: &Nears,
    stack: &mut [Entry],
    sp: &mut usize,
) -> ChildRef {
    debug_assert!(mask.count_ones() >= 2);
    if mask.count_ones() == 2 {
        // The common case without the loop's data-dependent branches: one compare picks
        // the nearer child (conditional moves), the other is pushed.
        let (far, nearer) = far_and_near(node, mask, near);
        stack[*sp] = far;
        *sp += 1;
        return nearer.node;
    }
    let start = *sp;
    let mut m = mask;
    while m != 0 {
        let i = m.trailing_zeros() as usize;
        m &= m - 1;
        let e = Entry { node: node.child(i), t: near[i] };
        let mut j = *sp;
        while j > start && stack[j - 1].t < e.t {
            stack[j] = stack[j - 1];
            j -= 1;
        }
        stack[j] = e;
        *sp += 1;
    }
    *sp -= 1;
    stack[*sp].node
}

/// The farther and the nearer of the lowest and the highest lane of `mask` as entries
/// (one compare into conditional moves; on a tie the higher lane is the nearer, visited
/// first, as in [`push_hits`]'s sort). With one lane in `mask` both are that lane.
#[inline(always)]
fn far_and_near<N: WideNode>(node: &N, mask: u32, near: &Nears) -> (Entry, Entry) {
    let (i, j) = (mask.trailing_zeros() as usize, 31 - mask.leading_zeros() as usize);
    let (low, high) = (Entry { node: node.child(i), t: near[i] }, Entry { node: node.child(j), t: near[j] });
    if low.t < high.t {
        (high, low)
    } else {
        (low, high)
    }
}

/// For a node `at` with one or two hit children (`mask`), the child to visit next (the
/// nearer; ties to the higher lane, as [`push_hits`]) and the child to prefetch: with two,
/// the farther one, which is pushed; with one, the node `at` itself, which is in cache.
/// The entry above `sp` is written either way (`stack_need` leaves room) and kept only
/// with two: no branch on the hit count. Used by the interleaved walk (stream.rs), which
/// prefetches every next step anyway: dragon diffuse rays +7–8 %, random +3–12 % (round 7, one
/// thread, two sets of 3 alternated rounds). In the single-ray walk, which does not prefetch
/// a lone child, it lost 6–18 % on primary rays and 6 % on the bunny's and the kitchen's
/// diffuse ones.
#[inline(always)]
pub(super) fn next_of_one_or_two<N: WideNode>(
    node: &N,
    mask: u32,
    near: &Nears,
    at: ChildRef,
    stack: &mut [Entry],
    sp: &mut usize,
) -> (ChildRef, ChildRef) {
    debug_assert!((1..=2).contains(&mask.count_ones()));
    let (far, nearer) = far_and_near(node, mask, near);
    let two = mask & (mask - 1) != 0;
    stack[*sp] = far;
    *sp += two as usize;
    (nearer.node, if two { far.node } else { at })
}

/// The triangle test's constants of `ray`, made on the first call (the walk's first leaf).
///
/// Not `get_or_insert_with(|| ...)`: the closure is a function of its own, compiled
/// without the walk's AVX2/AVX-512 features, and LLVM kept it out of line (one call per
/// ray, `PreparedRay::new` inside it built for baseline x86-64).
#[inline(always)]
pub(super) fn prepared<'a>(pr: &'a mut Option<PreparedRay>, ray: &Ray) -> &'a PreparedRay {
    if pr.is_none() {
        *pr = Some(PreparedRay::new(ray));
    }
    pr.as_ref().expect("set above")
}

/// Where a single-ray walk starts and what it tests with: the subtree, the ray, its box
/// constants and its interval.
pub(super) struct Below<'a> {
    pub root: ChildRef,
    pub ray: &'a Ray,
    pub br: &'a BoxRay,
    pub tmin: f32,
    pub tmax: f32,
}

impl<N: WideNode> WideTree<N> {
    /// Closest hit with the kernel chosen at build time.
    #[inline]
    #[allow(unsafe_code)]
    pub(super) fn closest<C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        #[cfg(target_arch = "x86_64")]
        match self.kernel {
            // SAFETY: `KernelChoice::Avx512` is only chosen when AVX2, AVX-512 F and VL
            // were detected, `Avx2` when AVX2 was.
            KernelChoice::Avx512 => return unsafe { self.closest_avx512(ray, c) },
            KernelChoice::Avx2 => return unsafe { self.closest_avx2(ray, c) },
            KernelChoice::Scalar => {}
        }
        self.closest_sized::<Scalar, C>(ray, c)
    }

    /// Any hit with the kernel chosen at build time.
    #[inline]
    #[allow(unsafe_code)]
    pub(super) fn any<C: Counter>(&self, ray: &Ray, c: &mut C) -> bool {
        #[cfg(target_arch = "x86_64")]
        match self.kernel {
            // SAFETY: as in `closest`.
            KernelChoice::Avx512 => return unsafe { self.any_avx512(ray, c) },
            KernelChoice::Avx2 => return unsafe { self.any_avx2(ray, c) },
            KernelChoice::Scalar => {}
        }
        self.any_sized::<Scalar, C>(ray, c)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    unsafe fn closest_avx2<C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        self.closest_sized::<super::kernel_avx2::Avx2, C>(ray, c)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    unsafe fn any_avx2<C: Counter>(&self, ray: &Ray, c: &mut C) -> bool {
        self.any_sized::<super::kernel_avx2::Avx2, C>(ray, c)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,avx512f,avx512vl")]
    #[allow(unsafe_code)]
    unsafe fn closest_avx512<C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        self.closest_sized::<super::kernel_avx512::Avx512, C>(ray, c)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,avx512f,avx512vl")]
    #[allow(unsafe_code)]
    unsafe fn any_avx512<C: Counter>(&self, ray: &Ray, c: &mut C) -> bool {
        self.any_sized::<super::kernel_avx512::Avx512, C>(ray, c)
    }

    #[inline(always)]
    pub(super) fn closest_sized<K: Kernel, C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        if self.stack_need <= SMALL_STACK {
            self.closest_with::<K, C, SMALL_STACK>(ray, c)
        } else {
            self.closest_with::<K, C, STACK_CAPACITY>(ray, c)
        }
    }

    #[inline(always)]
    pub(super) fn any_sized<K: Kernel, C: Counter>(&self, ray: &Ray, c: &mut C) -> bool {
        if self.stack_need <= SMALL_STACK {
            self.any_with::<K, C, SMALL_STACK>(ray, c)
        } else {
            self.any_with::<K, C, STACK_CAPACITY>(ray, c)
        }
    }

    /// Closest hit with an `S`-entry stack (`S >= self.stack_need`).
    #[inline(always)]
    fn closest_with<K: Kernel, C: Counter, const S: usize>(&self, ray: &Ray, c: &mut C) -> Hit {
        // The triangle test's constants (f64 shear, axis order) only once a leaf is reached:
        // rays that miss every box never pay for them.
        let mut pr: Option<PreparedRay> = None;
        let mut best = Hit::MISS;
        let mut stack = [Entry::default(); S];
        let b = Below { root: 0, ray, br: &BoxRay::new(ray), tmin: ray.tmin, tmax: ray.tmax };
        self.closest_below::<K, C>(&b, &mut pr, &mut best, &mut stack, c);
        best
    }

    /// Keeps in `best` the closest hit of the subtree `b.root` for one ray, as the
    /// single-ray walk does it from the root (also how a packet's lanes finish a subtree
    /// alone): `pr` is filled at the first leaf, `stack` holds at least `stack_need`
    /// entries.
    #[inline(always)]
    pub(super) fn closest_below<K: Kernel, C: Counter>(
        &self,
        b: &Below<'_>,
        pr: &mut Option<PreparedRay>,
        best: &mut Hit,
        stack: &mut [Entry],
        c: &mut C,
    ) {
        let (ray, br, tmin, tmax) = (b.ray, b.br, b.tmin, b.tmax);
        let mut sp = 0usize;
        let mut near: Nears = [0.0; 8];
        let mut cur: ChildRef = b.root;
        loop {
            if is_leaf(cur) {
                let pr = prepared(pr, ray);
                let (first, count) = leaf_blocks(cur);
                c.triangles(4 * count as u32);
                K::closest_leaf(&self.blocks[first..first + count], pr, best);
            } else {
                let node = &self.nodes[cur as usize];
                c.node();
                // Cull only boxes entered after the best hit: `limit` = best.t keeps a box
                // entered exactly at best.t (a lower-index triangle may tie there).
                let mask = K::boxes(node, br, tmin, best.t.min(tmax), &mut near);
                if mask != 0 {
                    if mask & (mask - 1) == 0 {
                        cur = node.child(mask.trailing_zeros() as usize);
                        continue;
                    }
                    let start = sp;
                    cur = push_hits(node, mask, &near, stack, &mut sp);
                    // The deferred children's first cache misses overlap the work on the
                    // nearest one (the traversal is bound by node and block loads).
                    // Prefetching the nearest one too, right after the box test, was
                    // 1–4 % slower (round 6): its load follows a few cycles later anyway.
                    for e in &stack[start..sp] {
                        self.prefetch_child_branch_free::<K>(e.node);
                    }
                    continue;
                }
            }
            // Pop the next child still entered no later than the best hit.
            loop {
                if sp == 0 {
                    return;
                }
                sp -= 1;
                let e = stack[sp];
                if e.t <= best.t {
                    cur = e.node;
                    break;
                }
            }
        }
    }

    /// Pushes the children in `mask` (one or more) but the lowest lane onto `stack` above
    /// `sp`, unsorted and prefetched, and returns the lowest lane's, which the any-hit
    /// walk visits next. Shared by the single-ray walk and the interleaved one.
    ///
    /// Tried and dropped (round 10, one thread): the push without a loop, the children
    /// compressed by the mask in a register (AVX-512 `vpcompressd`) and stored at once,
    /// without the prefetch: dragon shadow rays +2 %, the same rays shuffled −13 %, BART
    /// kitchen −4 to −5 %, bunny 0 %.
    #[inline(always)]
    pub(super) fn push_any<K: Kernel>(&self, node: &N, mask: u32, stack: &mut [ChildRef], sp: &mut usize) -> ChildRef {
        let mut m = mask & (mask - 1);
        while m != 0 {
            let c = node.child(m.trailing_zeros() as usize);
            self.prefetch_child::<K>(c);
            stack[*sp] = c;
            *sp += 1;
            m &= m - 1;
        }
        node.child(mask.trailing_zeros() as usize)
    }

    /// Starts loading child `r`: its node, or its leaf's blocks. What the coherent walks
    /// (any hit, packets) use: their branches are predicted.
    #[inline(always)]
    pub(super) fn prefetch_child<K: Kernel>(&self, r: ChildRef) {
        if is_leaf(r) {
            let (first, count) = leaf_blocks(r);
            for b in &self.blocks[first..first + count] {
                K::prefetch(b);
            }
        } else {
            K::prefetch(&self.nodes[r as usize]);
        }
    }

    /// [`WideTree::prefetch_child`] without a branch, for the closest-hit walks of single
    /// rays, whose node-or-leaf and block-count branches mispredict on incoherent rays:
    /// the node (4 cache lines at width 8) or the leaf's first block (3 lines), the address
    /// picked by a mask. Measured (round 7, one thread, best of 3 alternated rounds; bunny,
    /// dragon, kitchen, duck): diffuse rays +1–6 %, random −1 to +2 %, primary −1 to +2 %;
    /// used in the any-hit walk too, shadow rays lost 2–3 %, so that keeps the branches.
    #[inline(always)]
    pub(super) fn prefetch_child_branch_free<K: Kernel>(&self, r: ChildRef) {
        let (first, _) = leaf_blocks(r);
        // Addresses only, never dereferenced: the one not picked may lie out of range.
        let node = self.nodes.as_ptr().wrapping_add((r & !LEAF_BIT) as usize) as usize;
        let block = self.blocks.as_ptr().wrapping_add(first) as usize;
        let leaf = ((r >> 31) as usize).wrapping_neg();
        let at = (node & !leaf) | (block & leaf);
        // A block is 160 bytes from a line start or 32 bytes in: 3 lines from `at` hold it.
        // The fourth prefetch is a node's last line, or the block's third again.
        let last = (192 & !leaf) | (128 & leaf);
        K::prefetch_lines([at, at.wrapping_add(64), at.wrapping_add(128), at.wrapping_add(last)]);
    }

    /// Any hit with an `S`-entry stack: returns at the first triangle accepted. Children
    /// are not sorted: any hit ends the walk, so order buys little. Measured (round 6, one
    /// thread, shadow rays): the nearest hit child first instead of the lowest lane, bunny
    /// −1 %, BART kitchen −5 %; the farthest first, bunny +2 %, kitchen −6 %.
    #[inline(always)]
    fn any_with<K: Kernel, C: Counter, const S: usize>(&self, ray: &Ray, c: &mut C) -> bool {
        let b = Below { root: 0, ray, br: &BoxRay::new(ray), tmin: ray.tmin, tmax: ray.tmax };
        self.any_below::<K, C>(&b, &mut None, &mut [0 as ChildRef; S], c).is_some()
    }

    /// The leaf holding a triangle the ray hits within its interval in the subtree
    /// `b.root`, the first the any-hit walk from the root finds there (also how a packet's
    /// lane finishes a subtree alone); `None` when there is none. `pr` is filled at the
    /// first leaf.
    #[inline(always)]
    pub(super) fn any_below<K: Kernel, C: Counter>(
        &self,
        b: &Below<'_>,
        pr: &mut Option<PreparedRay>,
        stack: &mut [ChildRef],
        c: &mut C,
    ) -> Option<ChildRef> {
        let (ray, br, tmin, tmax) = (b.ray, b.br, b.tmin, b.tmax);
        let mut sp = 0usize;
        let mut near: Nears = [0.0; 8];
        let mut cur: ChildRef = b.root;
        loop {
            if is_leaf(cur) {
                let pr = prepared(pr, ray);
                let (first, count) = leaf_blocks(cur);
                c.triangles(4 * count as u32);
                if K::any_leaf(&self.blocks[first..first + count], pr) {
                    return Some(cur);
                }
            } else {
                let node = &self.nodes[cur as usize];
                c.node();
                let m = K::boxes(node, br, tmin, tmax, &mut near);
                if m != 0 {
                    cur = self.push_any::<K>(node, m, stack, &mut sp);
                    continue;
                }
            }
            if sp == 0 {
                return None;
            }
            sp -= 1;
            cur = stack[sp];
        }
    }
}
