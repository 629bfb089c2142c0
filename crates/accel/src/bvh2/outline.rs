//! The binary BVH's outline: every node's box down to the asked depth, leaves marked.
//! The two-level structure draws its top-level tree (the same node type) with it too.

use super::node::BvhNode;
use crate::OutlineBox;

/// Pushes the boxes of `nodes` (a tree as [`BvhNode`] encodes it, root first) with depth
/// `<= max_depth` onto `out`, parents before children. No nodes push nothing.
///
/// The walk keeps one stack of at most one pending sibling per level (plus the node
/// being opened): the only allocation besides `out`.
pub(crate) fn outline_nodes(nodes: &[BvhNode], max_depth: u32, out: &mut Vec<OutlineBox>) {
    if nodes.is_empty() {
        return;
    }
    let mut stack = vec![(0usize, 0u32)];
    while let Some((i, depth)) = stack.pop() {
        let n = &nodes[i];
        out.push(OutlineBox { depth, bounds: n.bounds(), leaf: n.is_leaf() });
        if !n.is_leaf() && depth < max_depth {
            let left = n.index as usize;
            stack.push((left + 1, depth + 1));
            stack.push((left, depth + 1));
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::outline::checks::{self, Cover};
    use crate::{Accel, Bvh, BvhParams};

    #[test]
    fn outline_nests_and_covers_every_centroid() {
        let mesh = checks::mesh();
        for params in [BvhParams::fast(), BvhParams::default(), BvhParams::high_quality()] {
            let bvh = Bvh::build(&mesh, &params).unwrap();
            let deepest = checks::check(&bvh, &mesh, Cover::Centroids);
            let full = checks::outline(&bvh, u32::MAX);
            let stats = bvh.stats();
            assert_eq!((deepest, full.len()), (stats.max_depth, stats.nodes));
            assert_eq!(full.iter().filter(|b| b.leaf).count(), stats.leaves);
            checks::appends(&bvh);
        }
    }
}
