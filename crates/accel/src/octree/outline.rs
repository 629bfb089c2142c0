//! The octree's outline, shared by both traversals: the root cube at depth 0, each
//! internal node's cell and its eight children one level down. Leaves (empty ones
//! included: they tile the cube with the others) draw their stored box; internal cells
//! come from the same exact plane formula (`Frame::cell_box`), so children nest.

use super::node::{LEAF_BIT, REC_LEAF};
use super::Octree;
use crate::OutlineBox;

impl Octree {
    /// Pushes the cells with depth `<= max_depth` onto `out`, parents before children.
    pub(super) fn outline_cells(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        // (child reference, cell at its depth, depth); one stack for the walk, at most
        // seven pending siblings per level.
        let mut stack = vec![(self.root, [0u32; 3], 0u32)];
        while let Some((r, cell, depth)) = stack.pop() {
            if r & LEAF_BIT != 0 {
                let leaf = self.records[(r & !LEAF_BIT) as usize + REC_LEAF];
                let b = &self.boxes[leaf as usize];
                debug_assert_eq!(b.depth(), depth, "leaf {leaf} stored at depth {}, reached at {depth}", b.depth());
                out.push(OutlineBox { depth, bounds: b.aabb(), leaf: true });
                continue;
            }
            out.push(OutlineBox { depth, bounds: self.frame.cell_box(cell, depth), leaf: false });
            if depth >= max_depth {
                continue;
            }
            // Octant `bx | by << 1 | bz << 2`, reversed so octant 0 comes out first.
            for (oct, &child) in self.inner[r as usize].child.iter().enumerate().rev() {
                let c = [0, 1, 2].map(|a| 2 * cell[a] + ((oct >> a) & 1) as u32);
                stack.push((child, c, depth + 1));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::outline::checks::{self, Cover};
    use crate::{Accel, Octree, OctreeDescent, OctreeParams};

    #[test]
    fn outline_cells_nest_and_tile_the_cube() {
        let mesh = checks::mesh();
        for params in [OctreeParams::fast(), OctreeParams::default(), OctreeParams::high_quality()] {
            let oct = Octree::build(&mesh, &params).unwrap();
            let descent = OctreeDescent::build(&mesh, &params).unwrap();
            for accel in [&oct as &dyn Accel, &descent] {
                let deepest = checks::check(accel, &mesh, Cover::Tiling);
                let full = checks::outline(accel, u32::MAX);
                let stats = accel.stats();
                assert_eq!((deepest, full.len()), (stats.max_depth, stats.nodes), "{}", accel.name());
                assert_eq!(full.iter().filter(|b| b.leaf).count(), stats.leaves, "{}", accel.name());
                // The root is a cube (up to the rounding of `min + size`).
                let e = full[0].bounds.extent();
                assert!(e.max_element() - e.min_element() <= 1e-5 * e.max_element(), "{}: root {e:?}", accel.name());
                checks::appends(accel);
            }
            assert_eq!(checks::outline(&oct, 5), checks::outline(&descent, 5));
        }
    }
}
