//! Binned-SAH builder (seed 003 Algorithms 2.1 and 2.2; the partition is partition.rs),
//! parallel over subtrees and deterministic: the node array does not depend on the number
//! of threads.
//!
//! Determinism: splits depend only on the refs of a node, never on the thread count
//! (binning reduces with exact min/max/sum over fixed chunks, so parallel binning is exact);
//! subtrees below `PARALLEL_THRESHOLD` are built by one thread each into their own vector,
//! and assemble.rs joins them in a fixed depth-first order.

use super::assemble::{assemble, Part};
use super::partition::{median_split, par_partition, partition, Sides};
use super::prim_ref::{Box3, PrimRef};
use super::reinsert::reinsert;
use super::{BvhNode, BvhParams};
use crate::BuildError;
use crate::StructureParams;
use dynray_geom::{Triangle, TriangleMesh};
use glam::{BVec3A, UVec4, Vec3A};
use rayon::prelude::*;

/// Nodes with at least this many triangles build their two subtrees with `rayon::join`.
/// Below it the task overhead outweighs the work.
const PARALLEL_THRESHOLD: usize = 4096;
/// Nodes with at least this many triangles bin their triangles in parallel chunks.
const PARALLEL_BIN_THRESHOLD: usize = 1 << 16;
/// Chunk size of parallel binning.
const BIN_CHUNK: usize = 1 << 14;
/// Depth from which nodes are split at the object median instead of by the SAH. SAH
/// splits may peel one triangle off at a time (exponentially spaced centroids); median
/// splits halve the node, so no leaf is deeper than `SAH_DEPTH_LIMIT + 31`.
pub(super) const SAH_DEPTH_LIMIT: u32 = 64;
/// Deepest possible leaf (root = 0): the SAH limit plus log2 of the largest triangle count
/// the node encoding allows (2^31).
pub(super) const MAX_DEPTH: u32 = SAH_DEPTH_LIMIT + 32;

/// SAH bins of all three axes, bin-major (Embree's layout): per bin, the three axes' boxes
/// and counts (a bin holds the triangles whose centroid falls into one slice of the
/// centroid box), so the sweep of [`Builder::pick`] runs the three axes as SIMD lanes; plus
/// the sweep's per-plane scratch.
struct Bins {
    boxes: Vec<[Box3; 3]>,
    /// Lane `a`: the count of axis `a` (lane 3 unused).
    counts: Vec<UVec4>,
    right_area: Vec<Vec3A>,
    right_count: Vec<UVec4>,
}

impl Bins {
    fn new(k: usize) -> Self {
        let mut b = Bins { boxes: Vec::new(), counts: Vec::new(), right_area: Vec::new(), right_count: Vec::new() };
        b.reset(k);
        b
    }

    /// Empties the bins for a node with `k` bins per axis, keeping the allocations.
    fn reset(&mut self, k: usize) {
        self.boxes.clear();
        self.boxes.resize(k, [Box3::EMPTY; 3]);
        self.counts.clear();
        self.counts.resize(k, UVec4::ZERO);
        self.right_area.resize(k, Vec3A::ZERO);
        self.right_count.resize(k, UVec4::ZERO);
    }

    fn merge(mut self, o: Bins) -> Bins {
        for (a, b) in self.boxes.iter_mut().zip(&o.boxes) {
            *a = [a[0].union(&b[0]), a[1].union(&b[1]), a[2].union(&b[2])];
        }
        for (a, b) in self.counts.iter_mut().zip(&o.counts) {
            *a += *b;
        }
        self
    }
}

/// Surface areas of three boxes as the lanes of one vector, each lane `2(xy + yz + zx)` of
/// the box's extent in that order (the per-axis scalar sweep's formula, bit for bit).
#[inline(always)]
fn areas3(b: &[Box3; 3]) -> Vec3A {
    let [e0, e1, e2] = [b[0].hi - b[0].lo, b[1].hi - b[1].lo, b[2].hi - b[2].lo];
    let x = Vec3A::new(e0.x, e1.x, e2.x);
    let y = Vec3A::new(e0.y, e1.y, e2.y);
    let z = Vec3A::new(e0.z, e1.z, e2.z);
    2.0 * (x * y + y * z + z * x)
}

/// The bins (per axis) of the centroids whose scaled offsets `t = (c - cmin) * scale` are
/// given: `trunc(t)` clamped to `0 ..= k - 1`, NaN to 0. All in vector instructions: a
/// scalar `as usize` per lane saturates with compares and branches, and was the largest
/// share of binning's instructions. Adding 2^23 to a whole number below 2^23 puts it in
/// the float's mantissa bits.
#[inline(always)]
fn bins3(t: Vec3A, kmax: Vec3A) -> [usize; 3] {
    // `max` returns its argument for a NaN lane, so NaN maps to bin 0.
    let t = t.max(Vec3A::ZERO).min(kmax).trunc() + Vec3A::splat(8_388_608.0);
    t.to_array().map(|x| (x.to_bits() & 0x7f_ffff) as usize)
}

/// Whether a centroid coordinate `c` goes left of the plane at `bin` (1 ..= k - 1) on its
/// axis: exactly when [`bins3`] put it in a bin `< bin` (for `t >= 0`, `trunc(t) < bin` iff
/// `t < bin`; negative and NaN `t` are bin 0), so partition puts exactly the binned counts
/// on each side. A float compare instead of a saturating cast per ref.
#[inline(always)]
fn goes_left(c: f32, cmin: f32, scale: f32, bin: f32) -> bool {
    let t = (c - cmin) * scale;
    t < bin || t.is_nan()
}

thread_local! {
    /// Per-thread bins, reused by every node below the parallel-binning size: most nodes
    /// hold a handful of triangles, where allocating bins cost more than filling them.
    static SCRATCH: std::cell::RefCell<Bins> = std::cell::RefCell::new(Bins::new(0));
}

/// The result of a build: nodes, triangles in leaf order (empty when not asked for), and
/// their mesh indices.
pub(super) struct Built {
    pub nodes: Vec<BvhNode>,
    pub tris: Vec<Triangle>,
    pub ids: Vec<u32>,
    pub depth: u32,
}

/// Builds the BVH of `mesh`.
pub(super) fn build(mesh: &TriangleMesh, params: &BvhParams) -> Result<Built, BuildError> {
    build_limited(mesh, params, SAH_DEPTH_LIMIT, 0, true, 0.0)
}

/// [`build`] with the block-cost SAH of wide BVHs: a leaf of `n` triangles costs
/// `⌈n / 2^block_shift⌉` triangle tests instead of `n`, because the wide BVH tests its
/// leaves `2^block_shift` triangles at a time (Embree's `sahBlockSize`). `block_shift = 0`
/// is [`build`] exactly. Without `tris` the leaf-order triangle copies are not made (the
/// wide BVH's collapse reads the mesh by id: the copies were 31 MB it threw away).
/// `presplit > 0` cuts about `presplit × n` extra references first (presplit.rs): a
/// triangle may then sit in several leaves, never twice in one.
pub(super) fn build_blocks(
    mesh: &TriangleMesh,
    params: &BvhParams,
    block_shift: u32,
    tris: bool,
    presplit: f32,
) -> Result<Built, BuildError> {
    build_limited(mesh, params, SAH_DEPTH_LIMIT, block_shift, tris, presplit)
}

/// [`build`] with median splits from depth `sah_depth_limit` on (tests use small limits:
/// real meshes whose SAH splits go 64 deep are hard to make in f32).
fn build_limited(
    mesh: &TriangleMesh,
    params: &BvhParams,
    sah_depth_limit: u32,
    block_shift: u32,
    with_tris: bool,
    presplit: f32,
) -> Result<Built, BuildError> {
    params.validate()?;
    mesh.validate()?;
    let n = mesh.triangle_count();
    // Node indices up to 2n - 1 must fit in a u32, and depth bounds assume n <= 2^31.
    if n > (u32::MAX / 2) as usize {
        return Err(BuildError::Limit(format!("{n} triangles: the BVH node encoding holds at most 2^31 - 1")));
    }
    let mut refs = triangle_refs(mesh);
    if presplit > 0.0 {
        super::presplit::cut_refs(mesh, &mut refs, presplit);
    }
    // Box and centroid box in one pass; below the root, partition gathers centroid boxes.
    let (bounds, cb) = refs
        .par_chunks(BIN_CHUNK)
        .map(|c| c.iter().fold((Box3::EMPTY, Box3::EMPTY), |(b, cb), r| (b.union(&r.bounds()), cb.with(r.center2()))))
        .reduce(|| (Box3::EMPTY, Box3::EMPTY), |(a, ac), (b, bc)| (a.union(&b), ac.union(&bc)));

    let builder = Builder { params, bins: params.bins as usize, sah_depth_limit, block_shift };
    let (part, count) = builder.subtree(&mut refs, 0, bounds, cb, 0);
    let (mut nodes, mut depth) = assemble(part, count as usize);
    let mut ids: Vec<u32> = refs.par_iter().with_min_len(4096).map(|r| r.id()).collect();
    drop(refs);
    if ids.len() > n {
        // Parts of one triangle often land in one leaf: test it there once.
        ids = super::presplit::dedup_leaves(&mut nodes, &ids);
    }
    if params.reinsert {
        let (kt, ki) = (params.traversal_cost, params.intersection_cost);
        // The leaf cost this build used, so the pass's stopping rule weighs what it did.
        let leaf_cost = |n: u32| builder.tri_cost(n);
        let outcome;
        (nodes, ids, depth, outcome) = reinsert(&nodes, &ids, kt, ki, leaf_cost);
        let (before, after) = (outcome.cost_before, outcome.cost_after);
        debug_assert!(after <= before * (1.0 + 1e-9), "{} rounds raised the SAH {before} to {after}", outcome.rounds);
    }

    let tris = if with_tris {
        ids.par_iter().with_min_len(4096).map(|&id| mesh.triangle(id as usize)).collect()
    } else {
        Vec::new()
    };
    Ok(Built { nodes, tris, ids, depth })
}

/// One reference per triangle of `mesh`, in mesh order: its box and index.
pub(super) fn triangle_refs(mesh: &TriangleMesh) -> Vec<PrimRef> {
    let n = mesh.triangle_count();
    (0..n).into_par_iter().with_min_len(4096).map(|i| PrimRef::new(&mesh.triangle(i).bounds(), i as u32)).collect()
}

/// How a node is divided.
enum Split {
    /// Make it a leaf.
    Leaf,
    /// Left = centroids in bins `< bin` along `axis` (see [`goes_left`]).
    Plane { axis: usize, bin: usize, cmin: f32, scale: f32, left: Box3, right: Box3, left_count: usize },
    /// Halve by object median along `axis`, or by index when `axis` is `None` (all
    /// centroids coincide).
    Median { axis: Option<usize> },
}

struct Builder<'a> {
    params: &'a BvhParams,
    bins: usize,
    sah_depth_limit: u32,
    /// Leaves are costed in blocks of `2^block_shift` triangles (0: per triangle).
    block_shift: u32,
}

impl Builder<'_> {
    /// SAH cost of intersecting `n` triangles: `n`, or the number of blocks they fill.
    #[inline(always)]
    fn tri_cost(&self, n: u32) -> f32 {
        ((n + (1 << self.block_shift) - 1) >> self.block_shift) as f32
    }

    /// Splits the node over `refs` (box `bounds`, centroid box `cb`), reordering `refs`
    /// left side first; `None` makes it a leaf.
    fn split(&self, refs: &mut [PrimRef], bounds: &Box3, cb: &Box3, depth: u32) -> Option<Sides> {
        let n = refs.len();
        if n == 1 || n < self.params.leaf_size as usize {
            return None;
        }
        let s = match self.choose_split(refs, bounds, cb, depth) {
            Split::Leaf => return None,
            Split::Plane { axis, bin, cmin, scale, left, right, left_count } => {
                let b = bin as f32;
                let is_left = |c: Vec3A| goes_left(c[axis], cmin, scale, b);
                let (nl, lc, rc) =
                    if n >= PARALLEL_BIN_THRESHOLD { par_partition(refs, is_left) } else { partition(refs, is_left) };
                assert_eq!(nl, left_count, "partition disagrees with binning (axis {axis}, bin {bin})");
                Sides { nl, lb: left, rb: right, lc, rc }
            }
            Split::Median { axis } => median_split(refs, axis),
        };
        debug_assert!(s.nl > 0 && s.nl < n, "split of {n} left {}", s.nl);
        Some(s)
    }

    /// Builds the subtree over `refs` (triangles `first ..` of the leaf order) and returns
    /// it with its node count. Large nodes build their two sides with `rayon::join`; below
    /// `PARALLEL_THRESHOLD` one thread builds the subtree straight into its final layout.
    fn subtree(&self, refs: &mut [PrimRef], first: u32, bounds: Box3, cb: Box3, depth: u32) -> (Part, u32) {
        let n = refs.len();
        if n < PARALLEL_THRESHOLD {
            // Capacity is only reserved: untouched pages cost nothing.
            let mut nodes = Vec::with_capacity(2 * n - 1);
            nodes.push(BvhNode::default());
            let deepest = self.sequential(refs, first, bounds, cb, depth, &mut nodes, 0);
            let count = nodes.len() as u32;
            return (Part::Nodes { nodes, deepest }, count);
        }
        let Some(s) = self.split(refs, &bounds, &cb, depth) else {
            let nodes = vec![BvhNode::leaf(&bounds.aabb(), first, n as u32)];
            return (Part::Nodes { nodes, deepest: depth }, 1);
        };
        let (lrefs, rrefs) = refs.split_at_mut(s.nl);
        let rfirst = first + s.nl as u32;
        let ((l, lc), (r, rc)) = rayon::join(
            || self.subtree(lrefs, first, s.lb, s.lc, depth + 1),
            || self.subtree(rrefs, rfirst, s.rb, s.rc, depth + 1),
        );
        let part = Part::Pair { bounds: bounds.aabb(), kids: Box::new([l, r]) };
        (part, 1 + lc + rc)
    }

    /// Builds the subtree over `refs` into `nodes` (its root at `nodes[at]`, already
    /// pushed) in depth-first order: each children pair, then the left child's
    /// descendants, then the right one's. Returns the depth of its deepest leaf.
    #[allow(clippy::too_many_arguments)]
    fn sequential(
        &self,
        refs: &mut [PrimRef],
        first: u32,
        bounds: Box3,
        cb: Box3,
        depth: u32,
        nodes: &mut Vec<BvhNode>,
        at: usize,
    ) -> u32 {
        let Some(s) = self.split(refs, &bounds, &cb, depth) else {
            nodes[at] = BvhNode::leaf(&bounds.aabb(), first, refs.len() as u32);
            return depth;
        };
        let l = nodes.len();
        nodes[at] = BvhNode::interior(&bounds.aabb(), l as u32);
        nodes.extend([BvhNode::default(); 2]);
        let (lrefs, rrefs) = refs.split_at_mut(s.nl);
        let dl = self.sequential(lrefs, first, s.lb, s.lc, depth + 1, nodes, l);
        let dr = self.sequential(rrefs, first + s.nl as u32, s.rb, s.rc, depth + 1, nodes, l + 1);
        dl.max(dr)
    }

    /// Seed 003 steps 3–6: bins on all three axes over the centroid box, the cheapest of
    /// the `k - 1` planes per axis, and a leaf when that plane costs more than a leaf.
    fn choose_split(&self, refs: &[PrimRef], bounds: &Box3, cb: &Box3, depth: u32) -> Split {
        let n = refs.len();
        let cb = *cb;
        // A node of n triangles fills at most n bins per axis: small nodes use fewer
        // (never below 8), which cut the dragon's build by 6 % at an unchanged SAH cost.
        let k = self.bins.min(n.max(8));
        let ext = cb.hi - cb.lo;
        // An axis with zero (or denormal) extent cannot separate centroids.
        let scale = Vec3A::from_array([0, 1, 2].map(|a| {
            if ext[a] > 0.0 && (k as f32 / ext[a]).is_finite() {
                k as f32 / ext[a]
            } else {
                0.0
            }
        }));
        if scale == Vec3A::ZERO {
            // All centroids coincide: nothing separates them, so split by index (bounded
            // depth) unless the leaf is small enough.
            return if n <= self.params.max_leaf_size as usize { Split::Leaf } else { Split::Median { axis: None } };
        }
        if depth >= self.sah_depth_limit {
            return Split::Median { axis: Some(cb.aabb().largest_axis()) };
        }

        if n >= PARALLEL_BIN_THRESHOLD {
            let mut bins = refs
                .par_chunks(BIN_CHUNK)
                .map(|c| {
                    let mut b = Bins::new(k);
                    bin_refs(c, &cb, scale, k, &mut b);
                    b
                })
                .reduce(|| Bins::new(k), Bins::merge);
            self.pick(&mut bins, &cb, scale, k, bounds, n)
        } else {
            SCRATCH.with_borrow_mut(|bins| {
                bins.reset(k);
                bin_refs(refs, &cb, scale, k, bins);
                self.pick(bins, &cb, scale, k, bounds, n)
            })
        }
    }

    /// Steps 5–6 on filled bins: the cheapest plane, or a leaf. The three axes are the
    /// lanes of one sweep (Embree's heuristic_binning.h); each lane computes exactly the
    /// cost a per-axis scalar sweep would, and ties go to the lowest axis, then plane.
    fn pick(&self, bins: &mut Bins, cb: &Box3, scale: Vec3A, k: usize, bounds: &Box3, n: usize) -> Split {
        // Sweep: right-to-left suffix areas and counts, then left-to-right costs (Eq. 2.2).
        let Bins { boxes, counts, right_area, right_count } = bins;
        let (mut acc, mut cnt) = ([Box3::EMPTY; 3], UVec4::ZERO);
        for i in (1..k).rev() {
            acc = [acc[0].union(&boxes[i][0]), acc[1].union(&boxes[i][1]), acc[2].union(&boxes[i][2])];
            cnt += counts[i];
            // An empty side is masked below, so its (infinite) area is never used.
            right_area[i] = areas3(&acc);
            right_count[i] = cnt;
        }
        let axis_ok = scale.cmpgt(Vec3A::ZERO);
        let round = UVec4::splat((1 << self.block_shift) - 1);
        // Triangle cost of each lane's count: `tri_cost` lane by lane.
        let tri_cost = |c: UVec4| {
            let b = (c + round) >> self.block_shift;
            Vec3A::new(b.x as f32, b.y as f32, b.z as f32)
        };
        // Per axis (lane) the cheapest plane so far, kept with selects rather than a branch
        // per lane: the first plane an axis may use is taken whatever its cost, a later
        // one only when strictly cheaper, so ties go to the first plane.
        let (mut best_cost, mut best_bin, mut found) = (Vec3A::INFINITY, Vec3A::ZERO, BVec3A::FALSE);
        let (mut acc, mut cnt) = ([Box3::EMPTY; 3], UVec4::ZERO);
        for i in 1..k {
            acc = [acc[0].union(&boxes[i - 1][0]), acc[1].union(&boxes[i - 1][1]), acc[2].union(&boxes[i - 1][2])];
            cnt += counts[i - 1];
            let (lt, rt) = (tri_cost(cnt), tri_cost(right_count[i]));
            let cost = areas3(&acc) * lt + right_area[i] * rt;
            let ok = axis_ok & lt.cmpgt(Vec3A::ZERO) & rt.cmpgt(Vec3A::ZERO);
            let take = ok & (cost.cmplt(best_cost) | !found);
            best_cost = Vec3A::select(take, cost, best_cost);
            // Bin indices are below 257: exact as floats.
            best_bin = Vec3A::select(take, Vec3A::splat(i as f32), best_bin);
            found |= ok;
        }
        let mut best: Option<(f32, usize, usize)> = None;
        for a in 0..3 {
            if found.test(a) && best.is_none_or(|(c, _, _)| best_cost[a] < c) {
                best = Some((best_cost[a], a, best_bin[a] as usize));
            }
        }
        let Some((cost, axis, bin)) = best else {
            // Unreachable while scale > 0 (bin 0 and bin k-1 are both occupied), but a
            // median split is always a safe answer.
            return Split::Median { axis: Some(cb.aabb().largest_axis()) };
        };

        // Eq. 2.1 against the leaf cost K_I·n; a flat or point-like node (area 0) gains
        // nothing from a split.
        let (kt, ki) = (self.params.traversal_cost, self.params.intersection_cost);
        let area = bounds.aabb().surface_area();
        let leaf_cost = ki * self.tri_cost(n as u32);
        let split_cost = if area > 0.0 { kt + ki * cost / area } else { kt + leaf_cost };
        if split_cost > leaf_cost && n <= self.params.max_leaf_size as usize {
            return Split::Leaf;
        }
        let left = boxes[..bin].iter().fold(Box3::EMPTY, |a, x| a.union(&x[axis]));
        let right = boxes[bin..].iter().fold(Box3::EMPTY, |a, x| a.union(&x[axis]));
        let left_count = counts[..bin].iter().map(|c| c[axis]).sum::<u32>() as usize;
        Split::Plane { axis, bin, cmin: cb.lo[axis], scale: scale[axis], left, right, left_count }
    }
}

/// Adds `refs` to the bins of all three axes.
///
/// Tried and dropped: even and odd refs into two sets of bins merged afterwards, so that
/// neighbouring refs in one bin do not wait on each other's store; dragon builds within
/// noise of this loop (docs/structures.md, "Builder").
fn bin_refs(refs: &[PrimRef], cb: &Box3, scale: Vec3A, k: usize, bins: &mut Bins) {
    let kmax = Vec3A::splat((k - 1) as f32);
    for r in refs {
        // Lane by lane the same IEEE operations as `goes_left`, so partition agrees exactly.
        let i = bins3((r.center2() - cb.lo) * scale, kmax);
        let b = r.bounds();
        for (axis, &i) in i.iter().enumerate() {
            bins.boxes[i][axis] = bins.boxes[i][axis].union(&b);
            bins.counts[i][axis] += 1;
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use dynray_geom::{Aabb, Vec3};

    /// A point-sized reference at `x` on the x axis (partition.rs's tests use it too).
    pub(in crate::bvh2) fn r(x: f32, id: u32) -> PrimRef {
        let p = Vec3::new(x, 0.0, 0.0);
        PrimRef::new(&Aabb::new(p, p), id)
    }

    #[test]
    fn prim_ref_is_32_bytes_and_keeps_its_id() {
        assert_eq!(std::mem::size_of::<PrimRef>(), 32);
        // Ids whose bits are NaNs or denormals as floats survive.
        for id in [0, 1, 0x7fc0_0001, u32::MAX] {
            assert_eq!(r(1.0, id).id(), id);
        }
    }

    #[test]
    fn depth_limit_switches_to_median_splits() {
        // 2000 triangles on a 2-D grid of jittered positions.
        let mut pos = Vec::new();
        for i in 0..2000u32 {
            let (x, y) = ((i % 50) as f32 + (i % 7) as f32 * 0.1, (i / 50) as f32 + (i % 5) as f32 * 0.1);
            pos.extend([[x, y, 0.0], [x + 0.5, y, 0.1], [x, y + 0.5, 0.2]]);
        }
        let mesh = TriangleMesh::new(pos, (0..2000u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect());
        let p = BvhParams::default();
        let sah = build(&mesh, &p).unwrap();
        for limit in [0, 1, 3] {
            let b = build_limited(&mesh, &p, limit, 0, true, 0.0).unwrap();
            // Median splits halve every node: at most ceil(log2(2000)) = 11 more levels.
            assert!(b.depth <= limit + 11, "limit {limit}: depth {}", b.depth);
            assert_ne!(b.nodes, sah.nodes, "limit {limit} changed nothing");
            let mut ids = b.ids.clone();
            ids.sort_unstable();
            assert!(ids.iter().enumerate().all(|(i, &id)| id == i as u32));
        }
    }

    /// The node array and leaf order do not depend on the thread count, on a mesh large
    /// enough for parallel binning (`PARALLEL_BIN_THRESHOLD`) and parallel subtrees.
    #[test]
    fn same_tree_on_one_and_two_threads() {
        let n = PARALLEL_BIN_THRESHOLD as u32 + 5000;
        let mut pos = Vec::new();
        for i in 0..n {
            // A scrambled cloud: clustered in x, spread in y and z.
            let h = i.wrapping_mul(2_654_435_761);
            let (x, y, z) = ((h % 97) as f32 * 0.01, (h >> 8) as f32 * 1e-6, (i % 1000) as f32 * 0.03);
            pos.extend([[x, y, z], [x + 0.04, y, z + 0.01], [x, y + 0.05, z + 0.02]]);
        }
        let mesh = TriangleMesh::new(pos, (0..n).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect());
        let p = BvhParams::default();
        let run = |threads: usize, shift: u32| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| build_blocks(&mesh, &p, shift, false, 0.0).unwrap())
        };
        for shift in [0, 2] {
            let (one, two) = (run(1, shift), run(2, shift));
            assert!(one.nodes.len() > 2 * n as usize / p.max_leaf_size as usize);
            assert_eq!(one.nodes, two.nodes, "block shift {shift}");
            assert_eq!(one.ids, two.ids, "block shift {shift}");
            assert_eq!(one.depth, two.depth);
            assert!(one.tris.is_empty());
        }
    }

    #[test]
    fn bins_clamp_and_map_nan_to_zero() {
        let kmax = Vec3A::splat(15.0);
        assert_eq!(bins3(Vec3A::new(16.0, 0.0, -3.0), kmax), [15, 0, 0]);
        assert_eq!(bins3(Vec3A::new(f32::NAN, 14.999, f32::INFINITY), kmax), [0, 14, 15]);
    }

    /// `goes_left` puts a coordinate left of plane `bin` exactly when `bins3` bins it below.
    #[test]
    fn goes_left_agrees_with_binning() {
        let (cmin, scale, kmax) = (-1.5f32, 3.7f32, Vec3A::splat(15.0));
        let mut cs = vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -1e30, 1e30, cmin];
        cs.extend((-200..2000).map(|i| i as f32 * 0.0031 - 2.0));
        for bin in 1..16 {
            for &c in &cs {
                let binned = bins3(Vec3A::splat((c - cmin) * scale), kmax)[0];
                assert_eq!(goes_left(c, cmin, scale, bin as f32), binned < bin, "c {c} bin {bin}");
            }
        }
    }
}
