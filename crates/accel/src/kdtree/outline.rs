//! The kd-tree's outline, shared by both traversals: cells, the root's being the box of
//! all triangles and each child's its parent's cell cut at the split plane. Leaves are
//! cells whether or not they hold triangles (empty leaves tile space too).

use super::tree::Tree;
use crate::OutlineBox;

impl Tree {
    /// Pushes the cells with depth `<= max_depth` onto `out`, parents before children.
    /// The split is clamped to the parent's cell, so children always nest.
    pub(super) fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        if self.nodes.is_empty() {
            return;
        }
        // One stack for the walk: at most one pending right child per level.
        let mut stack = vec![(0u32, self.bounds, 0u32)];
        while let Some((i, b, depth)) = stack.pop() {
            let n = self.nodes[i as usize];
            out.push(OutlineBox { depth, bounds: b, leaf: n.is_leaf() });
            if n.is_leaf() || depth >= max_depth {
                continue;
            }
            let a = n.axis();
            let split = n.split().clamp(b.min[a], b.max[a]);
            let (mut l, mut r) = (b, b);
            l.max[a] = split;
            r.min[a] = split;
            stack.push((n.right(), r, depth + 1));
            stack.push((i + 1, l, depth + 1));
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::outline::checks::{self, Cover};
    use crate::{Accel, KdTree, KdTreeParams, KdTreeRopes, OutlineBox};
    use dynray_geom::{Aabb, Vec3};

    #[test]
    fn outline_cells_nest_and_tile_the_root() {
        let mesh = checks::mesh();
        for params in [KdTreeParams::fast(), KdTreeParams::default(), KdTreeParams::high_quality()] {
            let kd = KdTree::build_with(&mesh, &params).unwrap();
            let ropes = KdTreeRopes::build_with(&mesh, &params).unwrap();
            for accel in [&kd as &dyn Accel, &ropes] {
                let deepest = checks::check(accel, &mesh, Cover::Tiling);
                let full = checks::outline(accel, u32::MAX);
                let stats = accel.stats();
                assert_eq!((deepest, full.len()), (stats.max_depth, stats.nodes), "{}", accel.name());
                assert_eq!(full.iter().filter(|b| b.leaf).count(), stats.leaves, "{}", accel.name());
                checks::appends(accel);
            }
            // Both traversals draw the same tree.
            assert_eq!(checks::outline(&kd, 6), checks::outline(&ropes, 6));
            // The cells are those the tree's own walk (what `stats` reads) derives: the
            // clamp never moved a split.
            let mut walked = Vec::new();
            kd.tree.walk(|i, b, depth| {
                walked.push(OutlineBox { depth, bounds: *b, leaf: kd.tree.nodes[i as usize].is_leaf() })
            });
            assert_eq!(checks::outline(&kd, u32::MAX), walked);
            // Leaves come out in pre-order, which is array order (left subtree first):
            // the k-th leaf cell is leaf node k's, and it meets the box of each of its
            // triangles (the builder sorts by clipped boxes, so a triangle may sit in a
            // leaf that only its box touches; widened by 1e-6 of the scene for rounding).
            let t = &kd.tree;
            let cells = checks::outline(&kd, u32::MAX).into_iter().filter(|b| b.leaf);
            let leaves = t.nodes.iter().filter(|n| n.is_leaf());
            let slack = Vec3::splat(1e-6 * t.bounds.extent().max_element());
            for (k, (n, cell)) in leaves.zip(cells).enumerate() {
                let b = Aabb::new(cell.bounds.min - slack, cell.bounds.max + slack);
                for &id in t.leaf_prims(n.leaf_index()) {
                    let tri = t.tris[id as usize].bounds();
                    assert!(!b.intersection(&tri).is_empty(), "leaf {k}: triangle {id} outside {cell:?}");
                }
            }
        }
    }
}
