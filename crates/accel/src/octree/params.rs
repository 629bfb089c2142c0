//! Build parameters of the octree, with named presets.

use crate::structure_params::{out_of_range, unknown_key, value, ParamKey, StructureParams};
use crate::BuildError;

/// Deepest octree the builder accepts. The cube map holds `6·4^d` addresses at the finest
/// boundary depth `d` (100 MB at 11, the paper's deepest tree), and [`super::LeafBox`]
/// stores cell coordinates in 16 bits; the descent's stack is sized from this limit.
pub const MAX_DEPTH_LIMIT: u32 = 11;

/// How the octree is built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OctreeParams {
    /// Deepest subdivision level (root = 0). Useful range 5..=11; the seed used 8 for the
    /// bunny, 10 for the armadillo, 11 for the dragon.
    pub max_depth: u32,
    /// A cell with more triangles than this is split (while shallower than `max_depth`).
    /// Useful range 1..=32; the seed's leaves held 6 on average.
    pub leaf_threshold: u32,
    /// Enforce the 2:1 face balance the seed's neighbour walk needs (0, 1 or 4 leaves per
    /// face). Without it faces with more neighbours are crossed by point location.
    pub balance: bool,
}

impl Default for OctreeParams {
    /// Depth 8 and 12 triangles per leaf: the seed's bunny depth; on the 69k-triangle
    /// bunny this gives 96k leaves balanced / 77k unbalanced (the seed: 83k / 69k) and
    /// 20 MB (the seed: 18.6 MB), built in a few hundred milliseconds.
    fn default() -> Self {
        Self { max_depth: 8, leaf_threshold: 12, balance: true }
    }
}

impl OctreeParams {
    /// Shallow, quick to build: depth 7, up to 16 triangles per leaf.
    pub fn fast() -> Self {
        Self { max_depth: 7, leaf_threshold: 16, ..Self::default() }
    }

    /// Deeper tree with smaller leaves, for large meshes (the seed's armadillo depth):
    /// depth 10, 6 per leaf.
    pub fn high_quality() -> Self {
        Self { max_depth: 10, leaf_threshold: 6, ..Self::default() }
    }

    /// The default tree without 2:1 balance, to measure what balance costs (seed Table 1).
    pub fn unbalanced() -> Self {
        Self { balance: false, ..Self::default() }
    }
}

impl StructureParams for OctreeParams {
    const STRUCTURE: &'static str = "octree";
    const KEYS: &'static [ParamKey] = &[
        ParamKey { name: "max_depth", doc: "deepest level, 5–11 (default 8)" },
        ParamKey { name: "leaf_threshold", doc: "split cells with more triangles, 1–32 (default 12)" },
        ParamKey { name: "balance", doc: "2:1 face balance, on/off (default on)" },
    ];

    fn presets() -> Vec<(&'static str, Self)> {
        vec![
            ("fast", Self::fast()),
            ("default", Self::default()),
            ("high_quality", Self::high_quality()),
            ("unbalanced", Self::unbalanced()),
        ]
    }

    fn set(&mut self, key: &str, v: &str) -> Result<(), BuildError> {
        let s = Self::STRUCTURE;
        match key {
            "max_depth" => self.max_depth = value::u32(s, key, v)?,
            "leaf_threshold" => self.leaf_threshold = value::u32(s, key, v)?,
            "balance" => self.balance = value::bool(s, key, v)?,
            _ => return Err(unknown_key::<Self>(key)),
        }
        Ok(())
    }

    /// Rejects values outside the encodable range.
    fn validate(&self) -> Result<(), BuildError> {
        let err = out_of_range::<Self>;
        if self.max_depth > MAX_DEPTH_LIMIT {
            return err("max_depth", format!("{} exceeds the limit {MAX_DEPTH_LIMIT}", self.max_depth));
        }
        if self.leaf_threshold == 0 {
            return err("leaf_threshold", "must be at least 1".into());
        }
        Ok(())
    }
}
