//! Reinsertion: the optional SAH optimisation pass of the `high_quality` presets (Bittner,
//! Hapala and Havran 2013, "Fast insertion-based optimization of bounding volume
//! hierarchies"; batched as in Meister and Bittner 2018).
//!
//! Each round takes the nodes with the worst inefficiency measure, and for each one removes
//! its subtree (its sibling takes the parent's place), finds by branch and bound the node
//! `X` where hanging it costs least (a new parent over `X` and the subtree), and moves it
//! there when that beats where it was. Round `r` tries the nodes ranked `r·batch ..` by the measure; rounds stop
//! after one sweep or when one gains under [`MIN_ROUND_GAIN`].
//! The node array is then laid out again, depth first, children pairs adjacent and after
//! their parent, leaf ranges renumbered in that order (so leaves read the leaf-order arrays
//! front to back, as the builder's do).
//!
//! Cost model: leaves and their boxes never change, only where they hang, so the build's
//! leaf cost (per triangle, or per block of `2^block_shift` for the wide BVH) is a constant
//! of every move; a move changes `K_T ×` the summed interior areas. The leaf cost enters
//! only the stopping rule, which weighs a round's gain against the whole tree's cost.
//!
//! Sequential, with total orders on every choice (ties by node index), so the result does
//! not depend on the thread count.

use super::build::MAX_DEPTH;
use super::BvhNode;
use dynray_geom::Aabb;
use glam::Vec3A;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Most rounds of a pass: with [`BATCH_FRACTION`], one sweep over every node in order of
/// the measure. On the bunny (bvh2:high_quality) sweeps of 1 % / 2 % / 5 % / 10 % batches
/// cost 31.31 → 31.31 / 31.28 / 31.25 / 31.13; ten rounds of all nodes 31.09 at 10× this
/// sweep's time. Leaves stay as built, so only the interior part (about a third) can move.
const MAX_ROUNDS: usize = 10;
/// Fraction of the nodes tried per round (the next ones by the measure).
const BATCH_FRACTION: f64 = 0.1;
/// A round gaining less than this fraction of the tree's SAH cost is the last.
const MIN_ROUND_GAIN: f64 = 1e-4;
/// No link.
const NONE: u32 = u32::MAX;

/// A box as two SIMD corners: the search unions one per visited node.
#[derive(Clone, Copy, Debug)]
struct Box3 {
    lo: Vec3A,
    hi: Vec3A,
}

impl Box3 {
    fn of(n: &BvhNode) -> Self {
        Box3 { lo: n.min.into(), hi: n.max.into() }
    }

    #[inline(always)]
    fn union(&self, o: &Box3) -> Box3 {
        Box3 { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }

    /// In f64: corner differences and products of f32 coordinates are then exact or
    /// nearly so, and a move's gain (a difference of large ancestor areas) survives.
    #[inline(always)]
    fn area(&self) -> f64 {
        let e = self.hi.as_dvec3() - self.lo.as_dvec3();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    fn aabb(&self) -> Aabb {
        Aabb::new(self.lo.into(), self.hi.into())
    }
}

/// What a pass did: the rounds run and the SAH cost (relative to the root's area, the
/// build's `K_T`/`K_I`/leaf cost) before and after.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Outcome {
    pub rounds: usize,
    pub cost_before: f64,
    pub cost_after: f64,
}

/// A tree being optimised, with explicit links: node `i` keeps its index throughout
/// (the removed parent is reused as the new one), leaves keep their triangle range.
struct Tree {
    boxes: Vec<Box3>,
    /// Interior: both children; leaf: `[first, count]` of the input leaf order.
    kids: Vec<[u32; 2]>,
    leaf: Vec<bool>,
    parent: Vec<u32>,
    /// Levels below the node (a leaf: 0): bounds the depth of a move.
    height: Vec<u32>,
    root: u32,
}

/// Reinserts subtrees of the tree `nodes` (leaf-order mesh ids `ids`) and lays it out
/// again. `leaf_cost(n)` is the build's triangle-test cost of an `n`-triangle leaf.
/// Returns the new nodes, ids in the new leaf order, the deepest leaf's depth, and what
/// the pass did.
pub(super) fn reinsert(
    nodes: &[BvhNode],
    ids: &[u32],
    kt: f32,
    ki: f32,
    leaf_cost: impl Fn(u32) -> f32,
) -> (Vec<BvhNode>, Vec<u32>, u32, Outcome) {
    let mut t = Tree::from_nodes(nodes);
    // The part of the cost no move changes: leaves, and the root's area it is relative to.
    let root_area = t.boxes[0].area();
    let leaves: f64 = (0..nodes.len())
        .filter(|&i| t.leaf[i])
        .map(|i| ki as f64 * leaf_cost(t.kids[i][1]) as f64 * t.boxes[i].area())
        .sum();
    let cost = |t: &Tree| (kt as f64 * t.interior_area() + leaves) / root_area;
    let cost_before = cost(&t);
    let mut rounds = 0;
    // A tree of one leaf, or one without area, has nothing to gain.
    if nodes.len() >= 5 && root_area > 0.0 {
        let batch = ((nodes.len() as f64 * BATCH_FRACTION) as usize).max(1);
        let mut now = cost_before;
        while rounds < MAX_ROUNDS {
            rounds += 1;
            // Round r tries ranks r·batch .. (r+1)·batch: the same worst nodes again would
            // mostly stay where they are (measured: 1 of 1 % moved per round on the bunny).
            for n in t.worst((rounds - 1) * batch, batch) {
                t.reinsert_one(n);
            }
            let next = cost(&t);
            let gain = now - next;
            now = next;
            if gain < MIN_ROUND_GAIN * now {
                break;
            }
        }
    }
    let cost_after = cost(&t);
    let (nodes, ids, depth) = t.layout(ids);
    (nodes, ids, depth, Outcome { rounds, cost_before, cost_after })
}

/// A search entry: a candidate sibling `node` at `depth`, with the area its ancestors
/// would grow by (`induced`). Ordered so the heap pops the smallest `induced` first, ties
/// to the lower node index.
struct Entry {
    induced: f64,
    node: u32,
    depth: u32,
}

impl PartialEq for Entry {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        o.induced.total_cmp(&self.induced).then(o.node.cmp(&self.node))
    }
}

impl Tree {
    fn from_nodes(nodes: &[BvhNode]) -> Self {
        let n = nodes.len();
        let mut t = Tree {
            boxes: nodes.iter().map(Box3::of).collect(),
            kids: nodes.iter().map(|b| if b.is_leaf() { [b.index, b.count] } else { [b.index, b.index + 1] }).collect(),
            leaf: nodes.iter().map(BvhNode::is_leaf).collect(),
            parent: vec![NONE; n],
            height: vec![0; n],
            root: 0,
        };
        // Children come after parents: a reverse sweep sees both children first.
        for i in (0..n).rev() {
            if !t.leaf[i] {
                let [l, r] = t.kids[i];
                t.parent[l as usize] = i as u32;
                t.parent[r as usize] = i as u32;
                t.height[i] = 1 + t.height[l as usize].max(t.height[r as usize]);
            }
        }
        t
    }

    fn interior_area(&self) -> f64 {
        (0..self.boxes.len()).filter(|&i| !self.leaf[i]).map(|i| self.boxes[i].area()).sum()
    }

    /// Nodes ranked `skip .. skip + k` by Bittner et al.'s inefficiency measure, largest
    /// first: `A(N) · A(N)/min A(child) · A(N)/mean A(child)` (leaves: their area), ties to
    /// the lower index. The root and its children are left alone (they have no
    /// grandparent to hang a sibling on).
    fn worst(&self, skip: usize, k: usize) -> Vec<u32> {
        let mut m: Vec<(f64, u32)> = (0..self.boxes.len() as u32)
            .filter(|&i| i != self.root && self.parent[i as usize] != self.root)
            .map(|i| {
                let a = self.boxes[i as usize].area();
                if self.leaf[i as usize] {
                    return (a, i);
                }
                let [l, r] = self.kids[i as usize].map(|c| self.boxes[c as usize].area());
                let (min, sum) = (l.min(r).max(f64::MIN_POSITIVE), (l + r).max(f64::MIN_POSITIVE));
                (a * (a / min) * (2.0 * a / sum), i)
            })
            .collect();
        let by_worst = |x: &(f64, u32), y: &(f64, u32)| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1));
        let end = (skip + k).min(m.len());
        if end < m.len() {
            m.select_nth_unstable_by(end, by_worst);
            m.truncate(end);
        }
        m.sort_unstable_by(by_worst);
        m.into_iter().skip(skip).map(|(_, i)| i).collect()
    }

    /// Points `p`'s child slot that holds `old` (or the root, when `p` is `NONE`) at `new`.
    fn replace_child(&mut self, p: u32, old: u32, new: u32) {
        self.parent[new as usize] = p;
        if p == NONE {
            self.root = new;
        } else {
            let k = &mut self.kids[p as usize];
            let slot = if k[0] == old { 0 } else { 1 };
            k[slot] = new;
        }
    }

    /// Recomputes boxes and heights from `i` up to the root; returns the summed change of
    /// their areas.
    fn refit_up(&mut self, mut i: u32) -> f64 {
        let mut delta = 0.0;
        while i != NONE {
            let [l, r] = self.kids[i as usize];
            let (l, r) = (l as usize, r as usize);
            let b = self.boxes[l].union(&self.boxes[r]);
            delta += b.area() - self.boxes[i as usize].area();
            self.boxes[i as usize] = b;
            self.height[i as usize] = 1 + self.height[l].max(self.height[r]);
            i = self.parent[i as usize];
        }
        delta
    }

    /// Moves the subtree `n` to where it costs least, if that gains anything.
    fn reinsert_one(&mut self, n: u32) {
        let p = self.parent[n as usize];
        if n == self.root || p == self.root {
            return;
        }
        let [a, b] = self.kids[p as usize];
        let sibling = if a == n { b } else { a };
        let g = self.parent[p as usize];
        // Remove: the sibling takes the parent's place; `p` is free.
        self.replace_child(g, p, sibling);
        let saved = self.boxes[p as usize].area() - self.refit_up(g);
        let (best, cost) = self.search(n);
        // Hanging it back beside its sibling costs exactly `saved`, so `best` always
        // exists; a move must gain more than rounding to count.
        let target = if best != NONE && cost < saved * (1.0 - 1e-9) { best } else { sibling };
        // Insert: `p` becomes the parent of the target and `n`.
        let q = self.parent[target as usize];
        self.replace_child(q, target, p);
        self.kids[p as usize] = [target, n];
        self.parent[target as usize] = p;
        self.parent[n as usize] = p;
        self.refit_up(p);
    }

    /// Branch and bound over the tree without `n`: the node whose new parent over it and
    /// `n` grows the summed interior area least, and that growth. Entries pop in order of
    /// the growth their ancestors already induce; none below `best - A(n)` can win.
    fn search(&self, n: u32) -> (u32, f64) {
        let nb = self.boxes[n as usize];
        let an = nb.area();
        let room = MAX_DEPTH.saturating_sub(self.height[n as usize] + 1);
        let (mut best, mut best_cost) = (NONE, f64::INFINITY);
        let mut heap = BinaryHeap::new();
        heap.push(Entry { induced: 0.0, node: self.root, depth: 0 });
        while let Some(Entry { induced, node, depth }) = heap.pop() {
            if induced + an >= best_cost {
                break;
            }
            let x = node as usize;
            let union = self.boxes[x].union(&nb).area();
            let direct = induced + union;
            // The new parent sits at `depth`: `n` and `x`'s subtree one level lower.
            if direct < best_cost && depth <= room && depth + 1 + self.height[x] <= MAX_DEPTH {
                (best, best_cost) = (node, direct);
            }
            if !self.leaf[x] {
                let induced = induced + union - self.boxes[x].area();
                if induced + an < best_cost {
                    for c in self.kids[x] {
                        heap.push(Entry { induced, node: c, depth: depth + 1 });
                    }
                }
            }
        }
        (best, best_cost)
    }

    /// The node array in the builder's depth-first layout (a pair, then the left child's
    /// descendants, then the right one's), leaf ranges renumbered in that order, with the
    /// matching ids and the deepest leaf's depth.
    fn layout(&self, ids: &[u32]) -> (Vec<BvhNode>, Vec<u32>, u32) {
        let mut nodes = Vec::with_capacity(self.boxes.len());
        let mut out_ids = Vec::with_capacity(ids.len());
        nodes.push(BvhNode::default());
        let mut deepest = 0;
        // (tree node, output slot, depth)
        let mut stack = vec![(self.root, 0usize, 0u32)];
        while let Some((i, slot, depth)) = stack.pop() {
            let b = self.boxes[i as usize].aabb();
            let [x, y] = self.kids[i as usize];
            if self.leaf[i as usize] {
                nodes[slot] = BvhNode::leaf(&b, out_ids.len() as u32, y);
                out_ids.extend_from_slice(&ids[x as usize..(x + y) as usize]);
                deepest = deepest.max(depth);
            } else {
                let at = nodes.len();
                nodes[slot] = BvhNode::interior(&b, at as u32);
                nodes.extend([BvhNode::default(); 2]);
                // Right pushed first: the left subtree is written (and numbered) first.
                stack.push((y, at + 1, depth + 1));
                stack.push((x, at, depth + 1));
            }
        }
        (nodes, out_ids, deepest)
    }
}

#[cfg(test)]
mod tests {
    use super::super::build::build_blocks;
    use super::super::{Bvh, BvhParams};
    use super::*;
    use crate::{Accel, Brute};
    use dynray_geom::{Ray, TriangleMesh, Vec3};

    /// `n` slivers of mixed sizes and orientations scattered by a hash: binned splits
    /// leave the reinsertion something to find.
    fn cloud(n: u32) -> TriangleMesh {
        let mut pos = Vec::new();
        for i in 0..n {
            let h = i.wrapping_mul(2_654_435_761);
            let (x, y, z) = ((h % 1009) as f32 * 0.01, ((h >> 10) % 997) as f32 * 0.01, (i % 101) as f32 * 0.1);
            let s = 0.02 + (h >> 24) as f32 * 0.004;
            let d = if h & 1 == 0 { [s, 0.01, 0.0] } else { [0.0, s, 0.01] };
            pos.extend([[x, y, z], [x + d[0], y + d[1], z + d[2]], [x + 0.01, y + 0.02, z + s]]);
        }
        TriangleMesh::new(pos, (0..n).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect())
    }

    fn tree(mesh: &TriangleMesh, p: &BvhParams, shift: u32) -> Bvh {
        let b = build_blocks(mesh, p, shift, true, 0.0).unwrap();
        Bvh { nodes: b.nodes, tris: b.tris, ids: b.ids, params: *p, depth: b.depth }
    }

    #[test]
    fn reinserted_trees_validate_and_cost_no_more() {
        let mesh = cloud(20_000);
        let off = BvhParams::default();
        for shift in [0, 2] {
            let plain = tree(&mesh, &off, shift);
            let moved = tree(&mesh, &BvhParams { reinsert: true, ..off }, shift);
            // check_invariants: every node reached once, children pairs after their parent,
            // every triangle in exactly one leaf, ids a permutation, copies exact, depth.
            let (a, b) = (plain.check_invariants(&mesh).unwrap(), moved.check_invariants(&mesh).unwrap());
            assert_eq!((a.nodes, a.leaves, a.leaf_sizes), (b.nodes, b.leaves, b.leaf_sizes), "shift {shift}");
            let (before, after) = (a.sah_cost.unwrap(), b.sah_cost.unwrap());
            assert!(after < before, "shift {shift}: SAH {before} -> {after}");
            // The pass's own accounting agrees with the validator's.
            let leaf = |n: u32| ((n + (1 << shift) - 1) >> shift) as f32;
            let (_, _, _, o) = reinsert(&plain.nodes, &plain.ids, 1.0, 1.0, leaf);
            assert!(o.rounds >= 1 && o.cost_after <= o.cost_before, "{o:?}");
            if shift == 0 {
                assert!((o.cost_before - before).abs() < 1e-6 * before, "{o:?} vs {before}");
                assert!((o.cost_after - after).abs() < 1e-6 * after, "{o:?} vs {after}");
            }
        }
    }

    #[test]
    fn reinserted_tree_hits_what_brute_force_hits() {
        let mesh = cloud(5_000);
        let bvh = tree(&mesh, &BvhParams { reinsert: true, ..BvhParams::default() }, 0);
        let brute = Brute::build(&mesh).unwrap();
        let b = mesh.bounds();
        for i in 0..2_000u32 {
            let h = i.wrapping_mul(2_246_822_519);
            let o = Vec3::new((h % 1000) as f32 * 0.0105 - 0.1, ((h >> 10) % 1000) as f32 * 0.0105 - 0.1, -1.0);
            let d = Vec3::new(((h >> 20) % 64) as f32 / 256.0 - 0.125, ((h >> 26) % 32) as f32 / 128.0 - 0.125, 1.0);
            let ray = Ray::new(o, d.normalize());
            let (x, y) = (bvh.intersect(&ray), brute.intersect(&ray));
            assert_eq!(
                (x.prim, x.t.to_bits(), x.u.to_bits(), x.v.to_bits()),
                (y.prim, y.t.to_bits(), y.u.to_bits(), y.v.to_bits()),
                "ray {i} in {b:?}"
            );
            assert_eq!(bvh.occluded(&ray), brute.occluded(&ray), "ray {i}");
        }
    }

    #[test]
    fn same_tree_on_one_and_two_threads() {
        let mesh = cloud(30_000);
        let p = BvhParams { reinsert: true, ..BvhParams::default() };
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| build_blocks(&mesh, &p, 2, false, 0.0).unwrap())
        };
        let (one, two) = (run(1), run(2));
        assert_eq!((one.nodes, one.ids, one.depth), (two.nodes, two.ids, two.depth));
    }

    #[test]
    fn tiny_trees_pass_through() {
        for n in [1, 2, 3, 7] {
            let mesh = cloud(n);
            let p = BvhParams { reinsert: true, leaf_size: 2, max_leaf_size: 1, ..BvhParams::default() };
            tree(&mesh, &p, 0).check_invariants(&mesh).unwrap();
        }
    }
}
