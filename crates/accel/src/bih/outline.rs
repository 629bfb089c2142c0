//! The BIH's outline. Nodes store two clip planes, not boxes, so each node's box is
//! derived on the way down as `cost.rs` derives it: the root's is the scene box, a left
//! child's is its parent's with the upper side on the split axis moved to the left plane,
//! a right child's its parent's with the lower side moved to the right plane, and the one
//! child of an empty-space cut gets the finite plane. Planes are clamped to the parent's
//! box, so children always nest (a refit keeps the planes inside it anyway).

use super::Bih;
use crate::OutlineBox;

impl Bih {
    /// Pushes the derived node boxes with depth `<= max_depth` onto `out`, parents first.
    pub(super) fn outline_boxes(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        if self.nodes.is_empty() {
            return;
        }
        // One stack for the walk: at most one pending right child per level.
        let mut stack = vec![(0u32, self.bounds, 0u32)];
        while let Some((i, b, depth)) = stack.pop() {
            let node = &self.nodes[i as usize];
            out.push(OutlineBox { depth, bounds: b, leaf: node.is_leaf() });
            if node.is_leaf() || depth >= max_depth {
                continue;
            }
            let axis = node.axis();
            let (left, right) = (i + 1, node.index());
            let mut lb = b;
            lb.max[axis] = b.max[axis].min(node.clip[0]).max(b.min[axis]);
            let mut rb = b;
            rb.min[axis] = b.min[axis].max(node.clip[1]).min(b.max[axis]);
            if left == right {
                // A one-child node: the finite plane cuts the one child's box.
                let child = if node.clip[1] == f32::INFINITY { lb } else { rb };
                stack.push((left, child, depth + 1));
            } else {
                stack.push((right, rb, depth + 1));
                stack.push((left, lb, depth + 1));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::outline::checks::{self, Cover};
    use crate::{Accel, Bih, BihParams};

    #[test]
    fn outline_nests_and_covers_every_centroid() {
        let mesh = checks::mesh();
        for params in [BihParams::fast(), BihParams::default(), BihParams::high_quality()] {
            let bih = Bih::build(&mesh, &params).unwrap();
            let deepest = checks::check(&bih, &mesh, Cover::Centroids);
            let full = checks::outline(&bih, u32::MAX);
            let stats = bih.stats();
            assert_eq!((deepest, full.len()), (stats.max_depth, stats.nodes));
            assert_eq!(full.iter().filter(|b| b.leaf).count(), stats.leaves);
            // Every leaf's box holds its triangles: the derived boxes are the real bounds.
            for (k, n) in bih.nodes().iter().enumerate().filter(|(_, n)| n.is_leaf()) {
                let ids = &bih.prim_ids()[n.index() as usize..][..n.count as usize];
                let b = ids.iter().fold(dynray_geom::Aabb::EMPTY, |b, &t| b.union(&mesh.triangle(t as usize).bounds()));
                assert!(full.iter().any(|o| o.leaf && o.bounds.contains(&b)), "leaf node {k}: {b:?} in no leaf box");
            }
            checks::appends(&bih);
        }
    }
}
