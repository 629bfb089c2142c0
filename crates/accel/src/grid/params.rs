//! Build parameters of the uniform grid, with named presets and their useful ranges.

use crate::BuildError;

/// How the grid is sized. All presets are checked by the oracle tests.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridParams {
    /// λ of the density heuristic: the longest axis of the scene box gets `λ·N^(1/3)`
    /// cells (N = triangles), the others proportionally to their length (at least 1),
    /// as in pbrt-v1's `GridAccel`. Useful range 1–8; must be finite and > 0. Default 2,
    /// chosen by measurement (see the module documentation of `grid`).
    pub density: f32,
    /// Upper bound on the number of cells (the offset array costs 4 bytes per cell);
    /// the resolution is scaled down uniformly to respect it. Useful 2^16–2^26; ≥ 1.
    pub max_cells: u32,
    /// Upper bound on the average number of cells a triangle is inserted into. When a
    /// resolution would exceed it (a few huge triangles, or thousands of identical ones
    /// in a fine grid), the resolution is halved until it fits, so memory stays bounded
    /// by `max_refs_per_triangle · N`. Useful 8–256; ≥ 1.
    pub max_refs_per_triangle: u32,
    /// Insert a triangle only into the cells its surface overlaps (separating-axis test
    /// of Akenine-Möller) instead of every cell its bounding box overlaps.
    pub exact_overlap: bool,
}

impl Default for GridParams {
    fn default() -> Self {
        Self { density: 2.0, max_cells: 1 << 23, max_refs_per_triangle: 64, exact_overlap: true }
    }
}

impl GridParams {
    /// Coarser grid: cheaper build, more triangles per cell.
    pub fn fast() -> Self {
        Self { density: 1.0, exact_overlap: false, ..Self::default() }
    }

    /// Finer grid: more memory, fewer triangle tests per ray.
    pub fn high_quality() -> Self {
        Self { density: 4.0, ..Self::default() }
    }

    /// Every preset with its name, for tests and benches that loop over them.
    pub fn presets() -> [(&'static str, GridParams); 3] {
        [("default", Self::default()), ("fast", Self::fast()), ("high_quality", Self::high_quality())]
    }

    /// Rejects values outside the documented ranges.
    pub fn check(&self) -> Result<(), BuildError> {
        if !(self.density.is_finite() && self.density > 0.0) {
            return Err(BuildError::Param {
                name: "density",
                message: format!("{} must be finite and > 0", self.density),
            });
        }
        if self.max_cells == 0 {
            return Err(BuildError::Param { name: "max_cells", message: "must be at least 1".into() });
        }
        if self.max_refs_per_triangle == 0 {
            return Err(BuildError::Param { name: "max_refs_per_triangle", message: "must be at least 1".into() });
        }
        Ok(())
    }
}
