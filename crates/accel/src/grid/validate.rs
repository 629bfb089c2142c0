//! Self-check of a built grid: CSR layout, indices, and every triangle findable.

use super::Grid;

/// A broken invariant of a grid.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("invalid grid: {0}")]
pub struct InvalidGrid(pub String);

impl Grid {
    /// Checks the offsets (one per cell plus one, non-decreasing, ending at the number of
    /// references), that references name existing triangles in ascending order within a
    /// cell, that every triangle is in at least one cell, and that every triangle is in
    /// the cell holding its centroid (a cheap spot check of the insertion).
    pub(crate) fn check_invariants(&self) -> Result<(), InvalidGrid> {
        let cells = self.shape.cells();
        let err = |s: String| Err(InvalidGrid(s));
        if self.offsets.len() != cells + 1 || self.offsets[0] != 0 {
            return err(format!("{} offsets for {cells} cells", self.offsets.len()));
        }
        if self.offsets.windows(2).any(|w| w[0] > w[1]) || self.offsets[cells] as usize != self.refs.len() {
            return err("offsets are not a prefix sum of the references".into());
        }
        let mut seen = vec![false; self.tris.len()];
        for c in 0..cells {
            let refs = self.cell_refs(c);
            if refs.windows(2).any(|w| w[0] >= w[1]) {
                return err(format!("cell {c} is not sorted or holds duplicates"));
            }
            for &t in refs {
                match seen.get_mut(t as usize) {
                    Some(s) => *s = true,
                    None => return err(format!("cell {c} names triangle {t} of {}", self.tris.len())),
                }
            }
        }
        if let Some(t) = seen.iter().position(|s| !s) {
            return err(format!("triangle {t} is in no cell"));
        }
        for (i, tri) in self.tris.iter().enumerate() {
            let p = tri.centroid();
            let c = self.shape.index([0, 1, 2].map(|a| self.shape.cell_of(a, p[a], 0.0)));
            if self.cell_refs(c).binary_search(&(i as u32)).is_err() {
                return err(format!("triangle {i} is not in the cell of its centroid ({c})"));
            }
        }
        Ok(())
    }
}
