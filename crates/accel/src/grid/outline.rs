//! The grid's outline: the grid's bounds at depth 0 (an interior box: the cells are below
//! it), and at depth 1 every cell that holds at least one triangle, as a leaf. Empty cells
//! are left out: a grid of 10⁵–10⁶ cells drawn whole is a solid block, while the
//! non-empty ones show where the surface is and how finely the grid samples it. A grid
//! has no depth beyond 1.

use super::Grid;
use crate::OutlineBox;
use dynray_geom::{Aabb, Vec3};

impl Grid {
    /// Pushes the bounds, then (for `max_depth >= 1`) the non-empty cells in index order.
    pub(super) fn outline_cells(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        let s = &self.shape;
        if s.cells() == 0 {
            return;
        }
        out.push(OutlineBox { depth: 0, bounds: s.bounds, leaf: false });
        if max_depth == 0 {
            return;
        }
        let [rx, ry, rz] = s.res;
        for z in 0..rz {
            for y in 0..ry {
                for x in 0..rx {
                    if self.cell_refs(s.index([x, y, z])).is_empty() {
                        continue;
                    }
                    let c = [x, y, z];
                    let lo = Vec3::from_array([0, 1, 2].map(|a| s.plane(a, c[a])));
                    let hi = Vec3::from_array([0, 1, 2].map(|a| s.plane(a, c[a] + 1)));
                    out.push(OutlineBox { depth: 1, bounds: Aabb::new(lo, hi), leaf: true });
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::grid::INSERT_SLACK;
    use crate::outline::checks::{self, Cover};
    use crate::{Accel, Grid, GridParams};
    use dynray_geom::{Aabb, Vec3};

    #[test]
    fn outline_shows_the_non_empty_cells() {
        let mesh = checks::mesh();
        for params in [GridParams::fast(), GridParams::default(), GridParams::high_quality()] {
            let grid = Grid::build(&mesh, &params).unwrap();
            assert_eq!(checks::check(&grid, &mesh, Cover::Cells), 1);
            let full = checks::outline(&grid, u32::MAX);
            let stats = grid.stats();
            // Every non-empty cell, and only those.
            assert_eq!(full.len() - 1, stats.leaves);
            assert!(stats.leaves < stats.nodes, "the spheres leave cells empty");
            // Cells come out in index order: the k-th leaf is the k-th non-empty cell,
            // and it touches each of its triangles (inserted with a slack of
            // INSERT_SLACK cells, hence the widening).
            let s = grid.shape();
            let non_empty = (0..s.cells()).filter(|&c| !grid.cell_refs(c).is_empty());
            let slack = Vec3::splat(2.0 * INSERT_SLACK * s.cell.max_element());
            for (c, cell) in non_empty.zip(full.iter().skip(1)) {
                let b = Aabb::new(cell.bounds.min - slack, cell.bounds.max + slack);
                for &id in grid.cell_refs(c) {
                    let t = mesh.triangle(id as usize).bounds();
                    assert!(!b.intersection(&t).is_empty(), "cell {c}: triangle {id} outside {cell:?}");
                }
            }
            checks::appends(&grid);
        }
    }
}
