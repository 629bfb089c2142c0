//! BIH construction: the in-place, quicksort-like partition of seed 000 §2.3 over
//! precomputed triangle boxes, with the top levels built in parallel.
//!
//! Per node (Wächter & Keller's "global heuristic"): the *node box* is a spatial box,
//! not the triangles' bounds; the root's is the scene box and each child gets its half
//! of the parent's box. The split candidate is the midpoint of the node box's longest
//! axis; each triangle goes, whole, to the side of its box centre. The left clip plane is
//! the largest coordinate of the left triangles on that axis, the right clip plane the
//! smallest of the right ones.
//!
//! Empty children are never stored. When every triangle falls on one side, the node box
//! is halved towards that side and the node is split again (seed §2.3 step 4); the node
//! becomes a leaf when halving no longer changes the box or after [`MAX_RETRIES`]
//! halvings. So a two-child node always has two non-empty children (the seed's empty
//! nodes "discarded at once"), and there are no 0-triangle leaves.
//!
//! Empty space is cut off instead by Wächter & Keller's one-child nodes, when
//! `BihParams::empty_cut` is set: before splitting, if the triangles leave an empty slab
//! larger than that fraction of the node's *region* (what its ancestors' planes bound)
//! on some axis, a node with a single finite clip plane (the other ±∞, see `node.rs`)
//! cuts it off. Without them a leaf is bounded only along the axes its ancestors split,
//! and rays test 7–12× more triangles on the bunny (measurements in `mod.rs`).
//!
//! Seed 000's optimisation (`BihParams::shrink`): before splitting, when the triangles'
//! real extent on the split axis times the factor is smaller than the node box's, the
//! node box takes the triangles' extent on that axis (the seed's pseudo-code narrows the
//! split axis alone, then splits again on the longest axis). The triangles' bounds are
//! known for free: the parent's partition pass accumulates them for each side.
//!
//! Determinism: the partition is sequential within a node and subtrees are concatenated
//! left then right, so the arrays are identical whatever the number of threads.

use super::node::{BihNode, MAX_INDEX};
use super::params::BihParams;
use crate::BuildError;
use dynray_geom::{Aabb, Vec3};

/// Halvings of one node's box before it gives up and becomes a leaf. Each halving cuts
/// the box by 2, so 64 covers any cluster-to-box ratio f32 can express on one axis
/// (24 bits of mantissa plus the span of exponents that realistic scenes use) while
/// bounding the work on degenerate input (all centres equal) to 64 passes.
pub const MAX_RETRIES: u32 = 64;

/// Ranges at least this long are split with `rayon::join`; below, the thread hand-off
/// costs more than the work.
const PARALLEL_MIN: usize = 4096;

/// Triangle boxes and centres, computed once per build.
pub(super) struct Prims {
    pub boxes: Vec<Aabb>,
    pub centres: Vec<Vec3>,
}

/// Midpoint written so that `max + min` cannot overflow for huge coordinates; centres
/// and split planes use the same formula so that "centre == split" is decided alike.
#[inline(always)]
fn mid(lo: f32, hi: f32) -> f32 {
    lo * 0.5 + hi * 0.5
}

impl Prims {
    pub fn new(boxes: Vec<Aabb>) -> Self {
        let centres = boxes
            .iter()
            .map(|b| Vec3::new(mid(b.min.x, b.max.x), mid(b.min.y, b.max.y), mid(b.min.z, b.max.z)))
            .collect();
        Self { boxes, centres }
    }
}

/// Output of a build: nodes in pre-order, triangle indices in leaf order, depth.
pub(super) struct Built {
    pub nodes: Vec<BihNode>,
    pub order: Vec<u32>,
    pub depth: u32,
}

/// Builds the tree over `prims` whose union is `scene`.
pub(super) fn build(prims: &Prims, scene: Aabb, params: &BihParams) -> Result<Built, BuildError> {
    let n = prims.boxes.len();
    if n > MAX_INDEX as usize {
        return Err(BuildError::Limit(format!(
            "the BIH addresses at most {MAX_INDEX} triangles in its 30-bit index field; the mesh has {n}"
        )));
    }
    let mut order: Vec<u32> = (0..n as u32).collect();
    let ctx = Ctx { prims, params };
    let mut nodes = Vec::with_capacity(2 * n / params.max_prims.max(1) as usize + 1);
    let root = Task { first: 0, node_box: scene, bounds: scene, region: scene, depth: 0 };
    let depth = ctx.subdivide(&mut order, root, &mut nodes);
    if nodes.len() > MAX_INDEX as usize {
        return Err(BuildError::Limit(format!(
            "the BIH would need {} nodes; its 30-bit index field holds {MAX_INDEX}",
            nodes.len()
        )));
    }
    Ok(Built { nodes, order, depth })
}

struct Ctx<'a> {
    prims: &'a Prims,
    params: &'a BihParams,
}

/// What one partition pass found.
struct Split {
    /// Triangles left of the plane (they occupy `refs[..mid]`).
    mid: usize,
    left: Aabb,
    right: Aabb,
}

/// One node to build: its primitive slots, its spatial node box, the union of its
/// triangles' boxes, and its *region* — the intersection of the half-spaces its
/// ancestors' clip planes give it, i.e. what traversal will know about it.
#[derive(Clone, Copy)]
struct Task {
    first: u32,
    node_box: Aabb,
    bounds: Aabb,
    region: Aabb,
    depth: u32,
}

impl Ctx<'_> {
    /// Builds the subtree over `refs` (slots `t.first..t.first + refs.len()` of the final
    /// order) into `out`, with its root at `out.len()` and node indices relative to the
    /// start of `out`. Returns the depth of the deepest leaf.
    fn subdivide(&self, refs: &mut [u32], t: Task, out: &mut Vec<BihNode>) -> u32 {
        let n = refs.len();
        let leaf = |out: &mut Vec<BihNode>| {
            out.push(BihNode::leaf(t.first, n as u32));
            t.depth
        };
        if n <= self.params.max_prims as usize || t.depth >= self.params.max_depth {
            return leaf(out);
        }
        if let Some(cut) = self.empty_cut(&t) {
            return cut.emit(self, refs, t, out);
        }
        let mut node_box = t.node_box;
        let bounds = t.bounds;
        let mut retries = 0;
        let (axis, split, s) = loop {
            let mut axis = node_box.largest_axis();
            if let Some(f) = self.params.shrink {
                // The seed's step works on the split axis alone: when the triangles span
                // less than 1/f of the node box there, that extent becomes the box's, and
                // the node is split again (on what is then the longest axis). Each axis
                // shrinks at most once, so this ends after three rounds.
                while (bounds.max[axis] - bounds.min[axis]) * f < node_box.max[axis] - node_box.min[axis] {
                    node_box.min[axis] = bounds.min[axis];
                    node_box.max[axis] = bounds.max[axis];
                    axis = node_box.largest_axis();
                }
            }
            let (lo, hi) = (node_box.min[axis], node_box.max[axis]);
            let split = mid(lo, hi);
            let s = self.partition(refs, axis, split);
            if s.mid == 0 {
                // All right: keep the upper half. A box that cannot shrink any further
                // (split == lo) holds only equal centres: nothing will ever separate them.
                if split <= lo || retries >= MAX_RETRIES {
                    return leaf(out);
                }
                node_box.min[axis] = split;
            } else if s.mid == n {
                if split >= hi || retries >= MAX_RETRIES {
                    return leaf(out);
                }
                node_box.max[axis] = split;
            } else {
                break (axis, split, s);
            }
            retries += 1;
        };
        let (clip_l, clip_r) = (s.left.max[axis], s.right.min[axis]);
        let mut lt = Task { first: t.first, node_box, bounds: s.left, region: t.region, depth: t.depth + 1 };
        lt.node_box.max[axis] = split;
        lt.region.max[axis] = clip_l;
        let mut rt =
            Task { first: t.first + s.mid as u32, node_box, bounds: s.right, region: t.region, depth: t.depth + 1 };
        rt.node_box.min[axis] = split;
        rt.region.min[axis] = clip_r;
        let (lrefs, rrefs) = refs.split_at_mut(s.mid);
        let me = out.len();
        out.push(BihNode::default());
        let (ld, rd, right) = if n >= PARALLEL_MIN {
            let cap = |k: usize| 2 * k / self.params.max_prims as usize + 1;
            let ((mut lv, ld), (mut rv, rd)) = rayon::join(
                || {
                    let mut v = Vec::with_capacity(cap(lrefs.len()));
                    let d = self.subdivide(lrefs, lt, &mut v);
                    (v, d)
                },
                || {
                    let mut v = Vec::with_capacity(cap(rrefs.len()));
                    let d = self.subdivide(rrefs, rt, &mut v);
                    (v, d)
                },
            );
            let lbase = out.len() as u32;
            lv.iter_mut().for_each(|node| node.shift(lbase));
            out.extend_from_slice(&lv);
            let rbase = out.len() as u32;
            rv.iter_mut().for_each(|node| node.shift(rbase));
            out.extend_from_slice(&rv);
            (ld, rd, rbase)
        } else {
            let ld = self.subdivide(lrefs, lt, out);
            let right = out.len() as u32;
            let rd = self.subdivide(rrefs, rt, out);
            (ld, rd, right)
        };
        out[me] = BihNode::interior(axis, right, clip_l, clip_r);
        ld.max(rd)
    }

    /// The largest empty slab between the node's region and its triangles, when it is
    /// more than `empty_cut` of the region on its axis.
    fn empty_cut(&self, t: &Task) -> Option<Cut> {
        let frac = self.params.empty_cut?;
        let mut best: Option<(f32, Cut)> = None;
        for axis in 0..3 {
            let ext = t.region.max[axis] - t.region.min[axis];
            if !(ext > 0.0 && ext.is_finite()) {
                continue;
            }
            let below = (t.bounds.min[axis] - t.region.min[axis]) / ext;
            let above = (t.region.max[axis] - t.bounds.max[axis]) / ext;
            for (gap, upper) in [(below, false), (above, true)] {
                if gap > frac && best.is_none_or(|(g, _)| gap > g) {
                    best = Some((gap, Cut { axis, upper }));
                }
            }
        }
        best.map(|(_, c)| c)
    }
}

/// A one-child node that cuts off empty space on one side of its child.
#[derive(Clone, Copy)]
struct Cut {
    axis: usize,
    /// True: the empty slab is above the triangles (the child lies below `clip[0]`).
    upper: bool,
}

impl Cut {
    /// Stores the one-child node (see `node.rs` for the encoding) and builds its child,
    /// whose region is tight on the cut side, so the same cut is never made twice.
    fn emit(self, ctx: &Ctx<'_>, refs: &mut [u32], t: Task, out: &mut Vec<BihNode>) -> u32 {
        let a = self.axis;
        let me = out.len() as u32;
        let mut child = Task { depth: t.depth + 1, ..t };
        let node = if self.upper {
            child.region.max[a] = t.bounds.max[a];
            child.node_box.max[a] = child.node_box.max[a].min(t.bounds.max[a]);
            BihNode::interior(a, me + 1, t.bounds.max[a], f32::INFINITY)
        } else {
            child.region.min[a] = t.bounds.min[a];
            child.node_box.min[a] = child.node_box.min[a].max(t.bounds.min[a]);
            BihNode::interior(a, me + 1, f32::NEG_INFINITY, t.bounds.min[a])
        };
        out.push(node);
        ctx.subdivide(refs, child, out)
    }
}

impl Ctx<'_> {
    /// Hoare-style in-place partition by box centre: `centre < split` goes left.
    /// Accumulates both sides' bounding boxes on the way (they become the clip planes
    /// and the children's `bounds`).
    fn partition(&self, refs: &mut [u32], axis: usize, split: f32) -> Split {
        let (boxes, centres) = (&self.prims.boxes, &self.prims.centres);
        let (mut left, mut right) = (Aabb::EMPTY, Aabb::EMPTY);
        let (mut i, mut j) = (0, refs.len());
        while i < j {
            let p = refs[i] as usize;
            if centres[p][axis] < split {
                left = left.union(&boxes[p]);
                i += 1;
            } else {
                right = right.union(&boxes[p]);
                j -= 1;
                refs.swap(i, j);
            }
        }
        Split { mid: i, left, right }
    }
}
