//! Build parameters of the uniform grid, with named presets and their useful ranges.

use crate::structure_params::{out_of_range, unknown_key, value, ParamKey, StructureParams};
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
}

impl StructureParams for GridParams {
    const STRUCTURE: &'static str = "grid";
    const KEYS: &'static [ParamKey] = &[
        ParamKey { name: "density", doc: "λ, cells along the longest axis per cube root of N, 1–8 (default 2)" },
        ParamKey { name: "max_cells", doc: "cap on cells, 2^16–2^26 (default 2^23)" },
        ParamKey { name: "max_refs_per_triangle", doc: "cap on average cells per triangle, 8–256 (default 64)" },
        ParamKey { name: "exact_overlap", doc: "insert by triangle–box overlap, on/off (default on)" },
    ];

    fn presets() -> Vec<(&'static str, Self)> {
        vec![("default", Self::default()), ("fast", Self::fast()), ("high_quality", Self::high_quality())]
    }

    fn set(&mut self, key: &str, v: &str) -> Result<(), BuildError> {
        let s = Self::STRUCTURE;
        match key {
            "density" => self.density = value::f32(s, key, v)?,
            "max_cells" => self.max_cells = value::u32(s, key, v)?,
            "max_refs_per_triangle" => self.max_refs_per_triangle = value::u32(s, key, v)?,
            "exact_overlap" => self.exact_overlap = value::bool(s, key, v)?,
            _ => return Err(unknown_key::<Self>(key)),
        }
        Ok(())
    }

    /// Rejects values outside the documented ranges.
    fn validate(&self) -> Result<(), BuildError> {
        let err = out_of_range::<Self>;
        if !(self.density.is_finite() && self.density > 0.0) {
            return err("density", format!("{} must be finite and > 0", self.density));
        }
        if self.max_cells == 0 {
            return err("max_cells", "must be at least 1".into());
        }
        if self.max_refs_per_triangle == 0 {
            return err("max_refs_per_triangle", "must be at least 1".into());
        }
        Ok(())
    }
}
