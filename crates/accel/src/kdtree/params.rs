//! Build parameters of the kd-tree, with named presets and their useful ranges.

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

    /// Every preset with its name, for tests and the bench.
    pub fn presets() -> [(&'static str, Self); 3] {
        [("fast", Self::fast()), ("default", Self::default()), ("high_quality", Self::high_quality())]
    }

    /// The depth limit for `n` triangles.
    pub fn depth_limit(&self, n: usize) -> u32 {
        let auto = || (8.0 + self.depth_factor as f64 * (n.max(1) as f64).log2()).round() as u32;
        self.max_depth.unwrap_or_else(auto).min(MAX_DEPTH_LIMIT)
    }

    /// Rejects values outside the ranges the builder can honour.
    pub fn validate(&self) -> Result<(), BuildError> {
        let bad = |name: &'static str, message: String| Err(BuildError::Param { name, message });
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
