//! Build parameters of the kd-tree, with named presets and their useful ranges.

use crate::structure_params::{out_of_range, unknown_key, value, ParamKey, StructureParams};
use crate::BuildError;

/// Deepest tree any preset or user may ask for. The traversal stack holds one entry per
/// level, so this also sizes it (`STACK_SIZE` in traverse.rs).
pub const MAX_DEPTH_LIMIT: u32 = 60;

/// How the SAH kd-tree is built. Costs are relative: only `intersection_cost /
/// traversal_cost` matters for the shape of the tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KdTreeParams {
    /// Cost of one traversal step (`K_T`). Useful range 0.5–2; default 1.
    pub traversal_cost: f32,
    /// Cost of one ray–triangle test (`K_I`). Useful range 0.5–4; default 1.5. Higher
    /// values give deeper trees with smaller leaves.
    pub intersection_cost: f32,
    /// Factor (`λ`) applied to a split's cost when one side holds no triangle, so that
    /// empty space is cut off (Wald & Havran 2006 use 0.8). Range 0.5–1; 1 disables it.
    pub empty_bonus: f32,
    /// Depth limit; `None` means `8 + depth_factor·log2(N)`, capped at
    /// [`MAX_DEPTH_LIMIT`]. Useful range 10–[`MAX_DEPTH_LIMIT`].
    pub max_depth: Option<u32>,
    /// Slope of the automatic depth limit: Havran's rule `8 + 1.3·log2(N)` by default.
    /// The greedy SAH keeps splitting around shared vertices (every cell near a vertex
    /// holds all its triangles), so on meshes the limit, not the SAH, ends most paths and
    /// sets the duplication: on the bunny 1.3 gives depth 29 and ≈5.5 references per
    /// triangle, 1.0 gives depth 24. Range 0.8–1.6.
    pub depth_factor: f32,
    /// A node with at most this many triangles becomes a leaf without trying a split.
    /// Range 0–16; 0 leaves termination to the SAH alone.
    pub min_prims: u32,
    /// Cap on triangle references per triangle, over the whole tree. Straddling
    /// triangles are duplicated; the SAH alone keeps this near 2–4 on real models, but
    /// adversarial input (many long crossing slivers) could multiply it per level. Once
    /// the cap would be passed, nodes become leaves. Range 2–32; default 8.
    pub max_refs_per_triangle: f32,
}

impl Default for KdTreeParams {
    fn default() -> Self {
        Self {
            traversal_cost: 1.0,
            intersection_cost: 1.5,
            empty_bonus: 0.8,
            max_depth: None,
            depth_factor: 1.3,
            min_prims: 1,
            max_refs_per_triangle: 8.0,
        }
    }
}

impl KdTreeParams {
    /// Shallower tree, bigger leaves: quicker build, slower traversal.
    pub fn fast() -> Self {
        Self { intersection_cost: 1.2, depth_factor: 1.0, min_prims: 2, max_refs_per_triangle: 4.0, ..Self::default() }
    }

    /// Deeper tree, smaller leaves: slower build, fastest traversal.
    pub fn high_quality() -> Self {
        Self { intersection_cost: 2.0, depth_factor: 1.5, min_prims: 0, max_refs_per_triangle: 12.0, ..Self::default() }
    }

    /// The depth limit for `n` triangles.
    pub fn depth_limit(&self, n: usize) -> u32 {
        let auto = || (8.0 + self.depth_factor as f64 * (n.max(1) as f64).log2()).round() as u32;
        self.max_depth.unwrap_or_else(auto).min(MAX_DEPTH_LIMIT)
    }
}

impl StructureParams for KdTreeParams {
    const STRUCTURE: &'static str = "kdtree";
    const KEYS: &'static [ParamKey] = &[
        ParamKey { name: "traversal_cost", doc: "SAH K_T, 0.5–2 (default 1)" },
        ParamKey { name: "intersection_cost", doc: "SAH K_I, 0.5–4 (default 1.5)" },
        ParamKey { name: "empty_bonus", doc: "cost factor for empty-side splits, 0.5–1 (default 0.8)" },
        ParamKey { name: "max_depth", doc: "depth limit, 10–60 or `auto` (default auto: 8 + depth_factor·log2 N)" },
        ParamKey { name: "depth_factor", doc: "slope of the automatic depth limit, 0.8–1.6 (default 1.3)" },
        ParamKey { name: "min_prims", doc: "leaf without trying a split at this size, 0–16 (default 1)" },
        ParamKey { name: "max_refs_per_triangle", doc: "cap on references per triangle, 2–32 (default 8)" },
    ];

    fn presets() -> Vec<(&'static str, Self)> {
        vec![("fast", Self::fast()), ("default", Self::default()), ("high_quality", Self::high_quality())]
    }

    fn set(&mut self, key: &str, v: &str) -> Result<(), BuildError> {
        let s = Self::STRUCTURE;
        match key {
            "traversal_cost" => self.traversal_cost = value::f32(s, key, v)?,
            "intersection_cost" => self.intersection_cost = value::f32(s, key, v)?,
            "empty_bonus" => self.empty_bonus = value::f32(s, key, v)?,
            "max_depth" if v.trim() == "auto" => self.max_depth = None,
            "max_depth" => {
                self.max_depth = Some(value::u32(s, key, v).map_err(|_| BuildError::BadValue {
                    structure: s,
                    key: key.to_string(),
                    value: v.to_string(),
                    expected: "a whole number or auto",
                })?)
            }
            "depth_factor" => self.depth_factor = value::f32(s, key, v)?,
            "min_prims" => self.min_prims = value::u32(s, key, v)?,
            "max_refs_per_triangle" => self.max_refs_per_triangle = value::f32(s, key, v)?,
            _ => return Err(unknown_key::<Self>(key)),
        }
        Ok(())
    }

    /// Rejects values outside the ranges the builder can honour.
    fn validate(&self) -> Result<(), BuildError> {
        let bad = out_of_range::<Self>;
        if !(self.traversal_cost > 0.0 && self.traversal_cost.is_finite()) {
            return bad("traversal_cost", format!("{} is not a positive number", self.traversal_cost));
        }
        if !(self.intersection_cost > 0.0 && self.intersection_cost.is_finite()) {
            return bad("intersection_cost", format!("{} is not a positive number", self.intersection_cost));
        }
        if !(self.empty_bonus > 0.0 && self.empty_bonus <= 1.0) {
            return bad("empty_bonus", format!("{} is outside (0, 1]", self.empty_bonus));
        }
        if !(self.depth_factor >= 0.0 && self.depth_factor <= 4.0) {
            return bad("depth_factor", format!("{} is outside [0, 4]", self.depth_factor));
        }
        if let Some(d) = self.max_depth.filter(|&d| d > MAX_DEPTH_LIMIT) {
            return bad("max_depth", format!("{d} is above the limit {MAX_DEPTH_LIMIT}"));
        }
        if !(self.max_refs_per_triangle >= 1.0 && self.max_refs_per_triangle <= 1024.0) {
            return bad("max_refs_per_triangle", format!("{} is outside [1, 1024]", self.max_refs_per_triangle));
        }
        Ok(())
    }
}
