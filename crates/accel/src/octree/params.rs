//! Build parameters of the octree, with named presets.

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

    /// Every preset, for tests that loop over them.
    pub fn presets() -> [(&'static str, Self); 4] {
        [
            ("fast", Self::fast()),
            ("default", Self::default()),
            ("high_quality", Self::high_quality()),
            ("unbalanced", Self::unbalanced()),
        ]
    }

    /// Rejects values outside the encodable range.
    pub fn check(&self) -> Result<(), BuildError> {
        if self.max_depth > MAX_DEPTH_LIMIT {
            return Err(BuildError::Param {
                name: "max_depth",
                message: format!("{} exceeds the limit {MAX_DEPTH_LIMIT}", self.max_depth),
            });
        }
        if self.leaf_threshold == 0 {
            return Err(BuildError::Param { name: "leaf_threshold", message: "must be at least 1".into() });
        }
        Ok(())
    }
}
