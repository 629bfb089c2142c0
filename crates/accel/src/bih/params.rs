//! Build parameters of the BIH, with named presets and their useful ranges.

use crate::structure_params::{out_of_range, unknown_key, value, ParamKey, StructureParams};
use crate::BuildError;

/// Deepest tree the builder makes; traversal keeps a stack of this many entries, which
/// is enough because at most one entry is pushed per level of the current path.
pub const MAX_DEPTH_LIMIT: u32 = 64;

/// How the BIH is built. All presets are checked by the oracle tests.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BihParams {
    /// A node with at most this many triangles becomes a leaf. Useful range 1–32
    /// (seed 000 swept 1, 5, 10, 20, 30); must be ≥ 1. Default 8, chosen by measurement
    /// (see the module documentation of `bih`).
    pub max_prims: u32,
    /// A node at this depth (root = 0) becomes a leaf whatever its size. Useful range
    /// 16–64; must be in 1..=[`MAX_DEPTH_LIMIT`].
    pub max_depth: u32,
    /// Seed 000's "shrink" optimisation: when the node's triangles span less than
    /// `1/factor` of the node box on the split axis, the node box is replaced by their
    /// bounding box before splitting. `None` is the original Wächter–Keller global
    /// heuristic (the node box only ever halves). Useful factors 1.1–4; must be > 1
    /// and finite. Default `Some(1.3)`, the seed's empirical value.
    pub shrink: Option<f32>,
    /// Empty-space cuts (Wächter & Keller's one-child nodes): when the empty slab
    /// between a node's triangles and the region its ancestors' planes give it exceeds
    /// this fraction of the region on that axis, a one-child node with a single clip
    /// plane cuts it off. `None` disables them (seed 000 has none). Useful range
    /// 0.1–0.9; must be in (0, 1).
    pub empty_cut: Option<f32>,
}

impl Default for BihParams {
    fn default() -> Self {
        Self { max_prims: 8, max_depth: MAX_DEPTH_LIMIT, shrink: Some(1.3), empty_cut: Some(0.25) }
    }
}

impl BihParams {
    /// Cheapest build, for scenes rebuilt every frame with few rays per frame.
    pub fn fast() -> Self {
        Self { max_prims: 16, ..Self::default() }
    }

    /// Small leaves and eager empty-space cuts: more nodes, fewer triangle tests.
    pub fn high_quality() -> Self {
        Self { max_prims: 2, empty_cut: Some(0.15), ..Self::default() }
    }

    /// Seed 000 as written: the shrink step, no empty-space cuts.
    pub fn seed_000() -> Self {
        Self { empty_cut: None, ..Self::default() }
    }

    /// Wächter and Keller's basic build (EGSR 2006): the node box only ever halves, no
    /// shrink step, no empty-space cuts.
    pub fn wachter_keller() -> Self {
        Self { shrink: None, empty_cut: None, ..Self::default() }
    }
}

impl StructureParams for BihParams {
    const STRUCTURE: &'static str = "bih";
    const KEYS: &'static [ParamKey] = &[
        ParamKey { name: "max_prims", doc: "leaf size, 1–32 (default 8)" },
        ParamKey { name: "max_depth", doc: "depth limit, 1–64 (default 64)" },
        ParamKey { name: "shrink", doc: "shrink factor 1.1–4, `on` (1.3) or `off` (default 1.3)" },
        ParamKey { name: "empty_cut", doc: "empty-space cut fraction 0.1–0.9 or `off` (default 0.25)" },
    ];

    fn presets() -> Vec<(&'static str, Self)> {
        vec![
            ("default", Self::default()),
            ("fast", Self::fast()),
            ("high_quality", Self::high_quality()),
            ("seed_000", Self::seed_000()),
            ("wachter_keller", Self::wachter_keller()),
        ]
    }

    fn set(&mut self, key: &str, v: &str) -> Result<(), BuildError> {
        let s = Self::STRUCTURE;
        let d = Self::default();
        match key {
            "max_prims" => self.max_prims = value::u32(s, key, v)?,
            "max_depth" => self.max_depth = value::u32(s, key, v)?,
            // `shrink=on` restores the seed's factor after a preset turned it off.
            "shrink" => self.shrink = value::opt_f32(s, key, v, d.shrink.unwrap_or(1.3))?,
            "empty_cut" => self.empty_cut = value::opt_f32(s, key, v, d.empty_cut.unwrap_or(0.25))?,
            _ => return Err(unknown_key::<Self>(key)),
        }
        Ok(())
    }

    /// Rejects values outside the documented ranges.
    fn validate(&self) -> Result<(), BuildError> {
        let err = out_of_range::<Self>;
        if self.max_prims == 0 {
            return err("max_prims", "must be at least 1".into());
        }
        if !(1..=MAX_DEPTH_LIMIT).contains(&self.max_depth) {
            return err("max_depth", format!("{} is outside 1..={MAX_DEPTH_LIMIT}", self.max_depth));
        }
        if let Some(f) = self.shrink {
            if !(f.is_finite() && f > 1.0) {
                return err("shrink", format!("factor {f} must be finite and > 1"));
            }
        }
        if let Some(f) = self.empty_cut {
            if !(f > 0.0 && f < 1.0) {
                return err("empty_cut", format!("fraction {f} must be in (0, 1)"));
            }
        }
        Ok(())
    }
}
