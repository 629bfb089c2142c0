//! The top-level tree: a binary BVH over instance boxes, one instance per leaf (each
//! instance is a whole bottom-level traversal, so a leaf never holds two).
//!
//! Built by a full sweep of the surface-area heuristic along the widest centroid axis
//! (instances are few: sorting is cheaper than binning here and finds the best split);
//! below [`MEDIAN_BELOW_DEPTH`] it splits at the median, so the depth stays within the
//! traversal stack whatever the boxes.

use crate::BvhNode;
use dynray_geom::Aabb;

/// Depth from which subtrees split at the median (then at most log2(n) more levels).
const MEDIAN_BELOW_DEPTH: u32 = 32;

/// Entries of the traversal stack: the deepest possible tree is `MEDIAN_BELOW_DEPTH` +
/// 32 levels of median splits, and the stack holds one sibling per level.
pub(crate) const STACK: usize = 72;

/// Builds the tree over `boxes`: nodes (root first, children as adjacent pairs) and the
/// leaf order (`order[node.index]` is a leaf's instance). An empty input gives no nodes.
pub(crate) fn build(boxes: &[Aabb]) -> (Vec<BvhNode>, Vec<u32>) {
    let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
    let mut nodes = Vec::with_capacity(2 * boxes.len());
    if boxes.is_empty() {
        return (nodes, order);
    }
    nodes.push(BvhNode::default());
    let mut todo = vec![(0usize, 0usize, boxes.len(), 0u32)];
    let mut scratch = Vec::new();
    while let Some((node, lo, hi, depth)) = todo.pop() {
        let bounds = order[lo..hi].iter().fold(Aabb::EMPTY, |b, &i| b.union(&boxes[i as usize]));
        if hi - lo == 1 {
            nodes[node] = BvhNode::leaf(&bounds, lo as u32, 1);
            continue;
        }
        let mid = split(boxes, &mut order[lo..hi], depth, &mut scratch) + lo;
        let left = nodes.len();
        nodes.push(BvhNode::default());
        nodes.push(BvhNode::default());
        nodes[node] = BvhNode::interior(&bounds, left as u32);
        todo.push((left, lo, mid, depth + 1));
        todo.push((left + 1, mid, hi, depth + 1));
    }
    (nodes, order)
}

/// Sorts `ids` along the widest centroid axis and returns the split position (1..n).
fn split(boxes: &[Aabb], ids: &mut [u32], depth: u32, right_area: &mut Vec<f32>) -> usize {
    let n = ids.len();
    let centroids = ids.iter().fold(Aabb::EMPTY, |b, &i| b.grown(boxes[i as usize].center()));
    let axis = centroids.largest_axis();
    let key = |i: &u32| boxes[*i as usize].center()[axis];
    ids.sort_by(|a, b| key(a).total_cmp(&key(b)).then(a.cmp(b)));
    if depth >= MEDIAN_BELOW_DEPTH {
        return n / 2;
    }
    // Sweep: area of the right side's box for each split, then left to right.
    right_area.clear();
    right_area.resize(n, 0.0);
    let mut b = Aabb::EMPTY;
    for k in (1..n).rev() {
        b = b.union(&boxes[ids[k] as usize]);
        right_area[k] = b.surface_area();
    }
    // Equal costs (boxes on top of each other) go to the split nearest the middle.
    let (mut best, mut best_cost) = (n / 2, (f32::INFINITY, usize::MAX));
    let mut b = Aabb::EMPTY;
    for k in 1..n {
        b = b.union(&boxes[ids[k - 1] as usize]);
        let cost = (b.surface_area() * k as f32 + right_area[k] * (n - k) as f32, k.abs_diff(n / 2));
        if cost.0 < best_cost.0 || (cost.0 == best_cost.0 && cost.1 < best_cost.1) {
            (best, best_cost) = (k, cost);
        }
    }
    best
}
