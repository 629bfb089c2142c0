//! The wide BVH's outline: the root's box (the union of its children's, which is all the
//! tree stores of it) at depth 0, and each child box one level below its node. A child
//! that is a leaf (a run of triangle blocks) is a leaf box; an interior child's box is
//! its node's, so the node's own children come one level further down.

use super::node::{is_leaf, WideNode};
use super::WideTree;
use crate::OutlineBox;
use dynray_geom::Aabb;

impl<N: WideNode> WideTree<N> {
    /// Pushes the boxes with depth `<= max_depth` onto `out`, parents before children.
    pub(super) fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        let Some(root) = self.nodes.first() else { return };
        if root.count() == 0 {
            return;
        }
        let bounds = (0..root.count()).fold(Aabb::EMPTY, |b, k| b.union(&root.child_box(k)));
        out.push(OutlineBox { depth: 0, bounds, leaf: false });
        // (interior node, depth of its box): its children's boxes are one level deeper.
        // One stack for the walk, at most `W - 1` pending nodes per level.
        let mut stack = vec![(0usize, 0u32)];
        while let Some((i, depth)) = stack.pop() {
            if depth >= max_depth {
                continue;
            }
            let node = &self.nodes[i];
            // Reversed, so that lane 0's subtree comes out first.
            for k in (0..node.count()).rev() {
                let child = node.child(k);
                let leaf = is_leaf(child);
                out.push(OutlineBox { depth: depth + 1, bounds: node.child_box(k), leaf });
                if !leaf {
                    stack.push((child as usize, depth + 1));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::outline::checks::{self, Cover};
    use crate::{Accel, Wbvh, WbvhParams};

    #[test]
    fn outline_nests_and_covers_every_centroid() {
        let mesh = checks::mesh();
        for width in [4, 8] {
            for params in [WbvhParams::fast(), WbvhParams::default(), WbvhParams::high_quality()] {
                let w = Wbvh::build(&mesh, &WbvhParams { width, ..params }).unwrap();
                let deepest = checks::check(&w, &mesh, Cover::Centroids);
                assert!(deepest >= 3, "width {width}: depth {deepest}");
                let full = checks::outline(&w, u32::MAX);
                let stats = w.stats();
                // The stats count interior nodes and leaves; the outline adds no box
                // for a node beyond the root's.
                assert_eq!(full.len(), stats.nodes, "width {width}");
                assert_eq!(full.iter().filter(|b| b.leaf).count(), stats.leaves, "width {width}");
                assert_eq!(deepest, stats.max_depth, "width {width}: leaves sit one level below the last interior");
                checks::appends(&w);
            }
        }
    }
}
