//! The packet traversals of the wide tree (the kernels and the frustum are in packet.rs):
//! closest hit, children visited nearest first by the frustum's entry distance, each with
//! the mask of the lanes that enter it; any hit, children in lane order, each lane leaving
//! the packet at its first hit. Lanes left alone finish their subtree as single rays.

use super::kernel::{BoxRay, Kernel, Nears, Scalar};
use super::node::{is_leaf, leaf_blocks, ChildRef, WideNode};
use super::packet::{lanes, Frustum, Lanes, Packet, PacketKernel, PACKET};
use super::traverse::{self, Below};
use super::WideTree;
use crate::NoCount;
use dynray_geom::{Hit, PreparedRay, Ray};

/// A deferred child: which lanes enter it, where, and the frustum's entry distance.
///
/// Tried and dropped: entries without the lanes' distances (12 bytes instead of 44),
/// re-culled on pop by the frustum's distance, a superset of the lanes still entering:
/// exact, but 1–2 % slower on the kitchen and the bunny (more lanes test leaves).
#[derive(Clone, Copy, Default)]
struct Entry {
    node: ChildRef,
    mask: u32,
    key: f32,
    near: Lanes,
}

/// At or below this many lanes entering a node, the packet hands them to single-ray
/// walks of that subtree. Embree's switch threshold for coherent rays is 2; here two
/// lanes stay together, since leaves share their vertex set-up across lanes
/// (`Kernel::closest_leaf_lanes`): with 1 instead of 2, packets on one thread went
/// 12.6–13.0 → 13.3–14.0 Mrays/s on the BART kitchen and 25.7–26.2 → 27.5–27.8 on the
/// bunny (min of 8–10 passes, 3 alternated rounds), the dragon equal within its noise.
const ALONE: u32 = 1;

/// Working memory of packet traversals: the stacks and the lanes' triangle-test
/// constants. Made once per batch, so that a packet does not start by zeroing a stack.
pub struct PacketScratch {
    stack: Vec<Entry>,
    lane_stack: Vec<traverse::Entry>,
    /// The any-hit walk's deferred children and the lanes entering each.
    any_stack: Vec<(ChildRef, u32)>,
    lane_any_stack: Vec<ChildRef>,
    pr: [Option<PreparedRay>; PACKET],
}

impl PacketScratch {
    /// Scratch for a tree whose traversal needs `stack_need` stack entries.
    pub fn new(stack_need: usize) -> Self {
        Self {
            stack: vec![Entry::default(); stack_need],
            lane_stack: vec![traverse::Entry::default(); stack_need],
            any_stack: vec![(0, 0); stack_need],
            lane_any_stack: vec![0; stack_need],
            pr: [None; PACKET],
        }
    }
}

/// What a packet walk answers per lane, so that one kernel dispatch and one frustum
/// set-up ([`WideTree::coherent`]) serve the closest-hit and the any-hit walk.
pub(super) trait PacketWalk {
    /// A lane's answer.
    type Out;
    /// The walk of `p` from the root, `limit` and `frustum` as [`start`] makes them.
    #[allow(clippy::too_many_arguments)] // the packet's state, as the walks take it
    fn walk<N: WideNode, K: Kernel, P: PacketKernel, const ORDERED: bool>(
        tree: &WideTree<N>,
        rays: &[Ray],
        p: &Packet,
        frustum: Frustum,
        limit: Lanes,
        out: &mut [Self::Out],
        s: &mut PacketScratch,
    );

    /// The single-ray query this walk stands for, with kernel `K`: how a ray that cannot
    /// travel in a packet is answered.
    fn alone<N: WideNode, K: Kernel>(tree: &WideTree<N>, ray: &Ray) -> Self::Out;
}

/// Closest hits ([`WideTree::closest_packet_in`]): `out[l]` is `closest(rays[l])`.
pub(super) struct ClosestHits;

/// Any-hit flags ([`WideTree::any_packet_in`]): `out[l]` is `any(rays[l])`.
pub(super) struct AnyHits;

impl PacketWalk for ClosestHits {
    type Out = Hit;
    #[inline(always)]
    fn walk<N: WideNode, K: Kernel, P: PacketKernel, const ORDERED: bool>(
        tree: &WideTree<N>,
        rays: &[Ray],
        p: &Packet,
        frustum: Frustum,
        limit: Lanes,
        out: &mut [Hit],
        s: &mut PacketScratch,
    ) {
        tree.closest_packet_in::<K, P, ORDERED>(rays, p, frustum, limit, out, s)
    }

    #[inline(always)]
    fn alone<N: WideNode, K: Kernel>(tree: &WideTree<N>, ray: &Ray) -> Hit {
        tree.closest_sized::<K, NoCount>(ray, &mut NoCount)
    }
}

impl PacketWalk for AnyHits {
    type Out = bool;
    #[inline(always)]
    fn walk<N: WideNode, K: Kernel, P: PacketKernel, const ORDERED: bool>(
        tree: &WideTree<N>,
        rays: &[Ray],
        p: &Packet,
        frustum: Frustum,
        limit: Lanes,
        out: &mut [bool],
        s: &mut PacketScratch,
    ) {
        tree.any_packet_in::<K, P, ORDERED>(rays, p, frustum, limit, out, s)
    }

    #[inline(always)]
    fn alone<N: WideNode, K: Kernel>(tree: &WideTree<N>, ray: &Ray) -> bool {
        tree.any_sized::<K, NoCount>(ray, &mut NoCount)
    }
}

/// Where both packet walks start: each lane's limit (its `tmax`; −∞ outside the packet,
/// so those lanes enter nothing) and the packet's frustum.
#[inline(always)]
fn start<P: PacketKernel>(p: &Packet) -> (Lanes, Frustum) {
    let mut limit: Lanes = [f32::NEG_INFINITY; PACKET];
    for l in lanes(p.active) {
        limit[l] = p.tmax[l];
    }
    (limit, Frustum::with::<P>(p, &limit))
}

impl<N: WideNode> WideTree<N> {
    /// The answers of walk `Q` (closest hits or any-hit flags) for `rays` into `out`, with
    /// the kernel chosen at build time: packets of [`PACKET`] consecutive rays, each the
    /// lanes that can travel together ([`Packet::new`]), the other rays alone. One kernel
    /// dispatch per batch, so that setting up a packet compiles with the kernel's
    /// instruction set too.
    #[allow(unsafe_code)]
    pub(super) fn coherent<Q: PacketWalk>(&self, rays: &[Ray], out: &mut [Q::Out], s: &mut PacketScratch) {
        // Every stack of the scratch is made `stack_need` long together.
        assert!(s.stack.len() >= self.stack_need, "packet scratch made for another tree");
        #[cfg(target_arch = "x86_64")]
        match self.kernel {
            // SAFETY: `KernelChoice::Avx512` is only chosen when AVX2, AVX-512 F and VL
            // were detected, `Avx2` when AVX2 was.
            super::kernel::KernelChoice::Avx512 => return unsafe { self.coherent_avx512::<Q>(rays, out, s) },
            super::kernel::KernelChoice::Avx2 => return unsafe { self.coherent_avx2::<Q>(rays, out, s) },
            super::kernel::KernelChoice::Scalar => {}
        }
        self.coherent_with::<Q, Scalar, Scalar>(rays, out, s)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    unsafe fn coherent_avx2<Q: PacketWalk>(&self, rays: &[Ray], out: &mut [Q::Out], s: &mut PacketScratch) {
        use super::kernel_avx2::Avx2;
        self.coherent_with::<Q, Avx2, Avx2>(rays, out, s)
    }

    /// The AVX2 packet tests with the AVX-512 single-ray kernel (leaf blocks in pairs, lanes
    /// that finish alone): the packet box tests gain nothing from 512-bit registers, whose
    /// 8 f32 lanes are already one AVX2 register.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,avx512f,avx512vl")]
    #[allow(unsafe_code)]
    unsafe fn coherent_avx512<Q: PacketWalk>(&self, rays: &[Ray], out: &mut [Q::Out], s: &mut PacketScratch) {
        use super::kernel_avx2::Avx2;
        use super::kernel_avx512::Avx512;
        self.coherent_with::<Q, Avx512, Avx2>(rays, out, s)
    }

    /// [`WideTree::coherent`] with kernels `K` (leaves, single rays) and `P` (packet box
    /// tests).
    #[inline(always)]
    fn coherent_with<Q: PacketWalk, K: Kernel, P: PacketKernel>(
        &self,
        rays: &[Ray],
        out: &mut [Q::Out],
        s: &mut PacketScratch,
    ) {
        for (rs, os) in rays.chunks(PACKET).zip(out.chunks_mut(PACKET)) {
            let mut p = P::packet(rs);
            if p.active.count_ones() >= 2 {
                self.packet_ordered::<Q, K, P>(rs, &p, os, s);
            } else {
                p.active = 0;
            }
            for l in lanes(!p.active & ((1u32 << rs.len()) - 1)) {
                os[l] = Q::alone::<N, K>(self, &rs[l]);
            }
        }
    }

    /// Walk `Q` from the root, with the lane test of [`PacketKernel::lanes_ordered`] where
    /// the packet's frustum is bounded on every axis.
    #[inline(always)]
    fn packet_ordered<Q: PacketWalk, K: Kernel, P: PacketKernel>(
        &self,
        rays: &[Ray],
        p: &Packet,
        out: &mut [Q::Out],
        s: &mut PacketScratch,
    ) {
        let (limit, frustum) = start::<P>(p);
        if frustum.sign.iter().all(|&s| s != 0) {
            Q::walk::<N, K, P, true>(self, rays, p, frustum, limit, out, s)
        } else {
            Q::walk::<N, K, P, false>(self, rays, p, frustum, limit, out, s)
        }
    }

    /// The packet traversal. Its stack holds at most `stack_need` entries: each node
    /// pushes at most its `W` children and pops one, as in the single-ray traversal.
    /// `limit` holds each lane's `min(best t, tmax)` (the single-ray traversal's culling
    /// limit; `tmax` before any hit), `frustum` is the packet's.
    #[inline(always)]
    fn closest_packet_in<K: Kernel, P: PacketKernel, const ORDERED: bool>(
        &self,
        rays: &[Ray],
        p: &Packet,
        mut frustum: Frustum,
        mut limit: Lanes,
        hits: &mut [Hit],
        s: &mut PacketScratch,
    ) {
        let PacketScratch { stack, lane_stack, pr, .. } = s;
        // Each lane's triangle-test constants at its first leaf: made for every lane here
        // instead, bunny packets were 9 % slower (lanes that reach no leaf never pay).
        for l in lanes(p.active) {
            pr[l] = None;
        }
        let mut best = [Hit::MISS; PACKET];
        let mut sp = 0usize;
        let mut fnear: Nears = [0.0; 8];
        let (mut cur, mut mask): (ChildRef, u32) = (0, p.active);
        'walk: loop {
            if is_leaf(cur) {
                let (first, count) = leaf_blocks(cur);
                let blocks = &self.blocks[first..first + count];
                for l in lanes(mask) {
                    traverse::prepared(&mut pr[l], &rays[l]);
                }
                K::closest_leaf_lanes(blocks, mask, pr, &mut best);
                P::update_limits(&mut limit, &best, &p.tmax, mask);
            } else if mask.count_ones() <= ALONE {
                for l in lanes(mask) {
                    self.closest_lane::<K>(cur, l, &rays[l], p, &mut pr[l], &mut best[l], lane_stack);
                }
                P::update_limits(&mut limit, &best, &p.tmax, mask);
            } else {
                let node = &self.nodes[cur as usize];
                // The frustum of the lanes entering this node only (their limits).
                frustum.limit = P::max_limit(&limit, mask);
                let mut fm = P::frustum(node, &frustum, &mut fnear);
                let start = sp;
                while fm != 0 {
                    let i = fm.trailing_zeros() as usize;
                    fm &= fm - 1;
                    let mut e = Entry { node: node.child(i), mask: 0, key: fnear[i], near: [0.0; PACKET] };
                    e.mask = if ORDERED {
                        P::lanes_ordered(node, i, p, &frustum.sign, &limit, mask, &mut e.near)
                    } else {
                        P::lanes(node, i, p, &limit, mask, &mut e.near)
                    };
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
                // Start loading every child some lane will visit: the packet's lanes wait
                // on one cache miss together, and the deferred ones arrive while it works.
                for e in &stack[start..sp] {
                    self.prefetch_child::<K>(e.node);
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

    /// The any-hit packet walk: children in lane order (any hit ends a lane, so order buys
    /// little, as in the single-ray walk), each with the lanes entering it; a lane that
    /// hits leaves the packet (its limit drops to −∞, so the frustum shrinks to the lanes
    /// still looking). Each lane tests exactly the boxes its single-ray box test accepts
    /// (`PacketKernel::lanes`) and the leaves below them, so it finds a hit exactly when
    /// its single ray does: the answer is a yes/no, whatever the order of the tests. The
    /// stack holds at most `stack_need` entries, as the closest-hit walk's.
    #[allow(clippy::too_many_arguments)] // the packet's state, as `closest_packet_in`
    #[inline(always)]
    fn any_packet_in<K: Kernel, P: PacketKernel, const ORDERED: bool>(
        &self,
        rays: &[Ray],
        p: &Packet,
        mut frustum: Frustum,
        mut limit: Lanes,
        out: &mut [bool],
        s: &mut PacketScratch,
    ) {
        let PacketScratch { any_stack: stack, lane_any_stack, pr, .. } = s;
        for l in lanes(p.active) {
            pr[l] = None;
        }
        let mut done = 0u32;
        let mut sp = 0usize;
        let mut fnear: Nears = [0.0; 8];
        let mut near: Lanes = [0.0; PACKET];
        let (mut cur, mut mask): (ChildRef, u32) = (0, p.active);
        'walk: loop {
            if is_leaf(cur) {
                let (first, count) = leaf_blocks(cur);
                let blocks = &self.blocks[first..first + count];
                for l in lanes(mask) {
                    let r = traverse::prepared(&mut pr[l], &rays[l]);
                    if K::any_leaf(blocks, r) {
                        done |= 1 << l;
                        limit[l] = f32::NEG_INFINITY;
                    }
                }
                if done == p.active {
                    break;
                }
            } else if mask.count_ones() <= ALONE {
                for l in lanes(mask) {
                    if self.any_lane::<K>(cur, l, &rays[l], p, &mut pr[l], lane_any_stack) {
                        done |= 1 << l;
                        limit[l] = f32::NEG_INFINITY;
                    }
                }
                if done == p.active {
                    break;
                }
            } else {
                let node = &self.nodes[cur as usize];
                frustum.limit = P::max_limit(&limit, mask);
                let mut fm = P::frustum(node, &frustum, &mut fnear);
                let start = sp;
                while fm != 0 {
                    let i = fm.trailing_zeros() as usize;
                    fm &= fm - 1;
                    let m = if ORDERED {
                        P::lanes_ordered(node, i, p, &frustum.sign, &limit, mask, &mut near)
                    } else {
                        P::lanes(node, i, p, &limit, mask, &mut near)
                    };
                    if m != 0 {
                        let child = node.child(i);
                        self.prefetch_child::<K>(child);
                        stack[sp] = (child, m);
                        sp += 1;
                    }
                }
                if sp > start {
                    sp -= 1;
                    (cur, mask) = stack[sp];
                    continue;
                }
            }
            // Pop the next child some lane still looking enters.
            while sp > 0 {
                sp -= 1;
                let (node, m) = stack[sp];
                if m & !done != 0 {
                    (cur, mask) = (node, m & !done);
                    continue 'walk;
                }
            }
            break;
        }
        for l in lanes(p.active) {
            out[l] = done >> l & 1 == 1;
        }
    }

    /// Lane `l` alone through the subtree under the interior node `root`: the single-ray
    /// any-hit walk of traverse.rs ([`WideTree::any_below`]) with the packet's box
    /// constants for the lane.
    #[allow(clippy::too_many_arguments)] // the lane's share of the packet's state
    #[inline(always)]
    fn any_lane<K: Kernel>(
        &self,
        root: ChildRef,
        l: usize,
        ray: &Ray,
        p: &Packet,
        pr: &mut Option<PreparedRay>,
        stack: &mut [ChildRef],
    ) -> bool {
        let br = BoxRay::from_parts(p.org, [p.inv[0][l], p.inv[1][l], p.inv[2][l]]);
        let below = Below { root, ray, br: &br, tmin: p.tmin[l], tmax: p.tmax[l] };
        self.any_below::<K, NoCount>(&below, pr, stack, &mut NoCount).is_some()
    }

    /// Lane `l` (ray `ray`) alone through the subtree under the interior node `root`,
    /// from its best hit so far: the single-ray traversal of traverse.rs
    /// ([`WideTree::closest_below`]), with the packet's box constants for the lane.
    #[allow(clippy::too_many_arguments)] // the lane's share of the packet's state
    #[inline(always)]
    fn closest_lane<K: Kernel>(
        &self,
        root: ChildRef,
        l: usize,
        ray: &Ray,
        p: &Packet,
        pr: &mut Option<PreparedRay>,
        best: &mut Hit,
        stack: &mut [traverse::Entry],
    ) {
        // `BoxRay::new(ray)`'s values: the packet computed them the same way.
        let br = BoxRay::from_parts(p.org, [p.inv[0][l], p.inv[1][l], p.inv[2][l]]);
        let below = Below { root, ray, br: &br, tmin: p.tmin[l], tmax: p.tmax[l] };
        self.closest_below::<K, NoCount>(&below, pr, best, stack, &mut NoCount);
    }
}
