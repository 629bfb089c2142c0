//! Build parameters of the BVH: bin count, leaf sizes and SAH cost constants, with presets.

use crate::structure_params::{out_of_range, unknown_key, value, ParamKey, StructureParams};
use crate::BuildError;

/// How a [`super::Bvh`] is built. Every field documents its useful range; [`BvhParams::validate`]
/// rejects values outside it with [`BuildError::Param`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhParams {
    /// SAH bins per axis (seed 003 §3.2: 16 on the CPU, 32 on the GPU). Range 2..=256.
    /// More bins find better planes at a linear cost in build time.
    pub bins: u32,
    /// The seed's `M`: a node holding fewer than `leaf_size` triangles becomes a leaf without
    /// trying a split. Range 2..=32. The seed found 5 by experiment.
    pub leaf_size: u32,
    /// Hard cap on a leaf: a node with more triangles is always split, even when the SAH
    /// says a leaf would be cheaper. Keeps leaf loops (and the GPU's) bounded.
    /// Range `leaf_size - 1`..=1024.
    pub max_leaf_size: u32,
    /// `K_T` of Eq. 2.1: cost of one traversal step (two box tests), in the same unit as
    /// [`BvhParams::intersection_cost`]. Range (0, 1000], finite.
    pub traversal_cost: f32,
    /// `K_I` of Eq. 2.1: cost of one ray–triangle test. Range (0, 1000], finite.
    pub intersection_cost: f32,
    /// After the build, move subtrees to where they cost least (reinsert.rs, Bittner et
    /// al. 2013): a lower SAH cost for a longer build. On in `high_quality`.
    pub reinsert: bool,
}

impl BvhParams {
    /// Quicker rebuilds of animated geometry: 8 bins and leaves below 6 triangles (about
    /// 0.93× the default's build time on the dragon, 4 % higher SAH cost).
    pub fn fast() -> Self {
        Self { bins: 8, leaf_size: 6, ..Self::default() }
    }

    /// Slower build, better trees: 32 bins, leaves below 3 triangles, reinsertion
    /// (figures: docs/structures.md, "Reinsertion").
    pub fn high_quality() -> Self {
        Self { bins: 32, leaf_size: 3, reinsert: true, ..Self::default() }
    }
}

impl Default for BvhParams {
    /// 16 bins (the seed's CPU value), leaves below 4 triangles, `K_T = K_I = 1` (not
    /// tuned; the stopping rule rarely fires before `leaf_size` does).
    ///
    /// `leaf_size` measured on this 2-core Xeon (one thread, CPU time, so the other jobs on
    /// the machine matter less; 512² primary rays from `Camera::framing`; ±5 % noise):
    ///
    /// | M | bunny build ms | bunny Mrays/s | dragon (871k) build ms | dragon Mrays/s | dragon SAH |
    /// |---|---|---|---|---|---|
    /// | 3 | 40.6 | 8.16 | 640 | 4.83 | 50.2 |
    /// | 4 | 37.4 | 8.16 | 580 | 5.07 | 50.5 |
    /// | 5 | 34.1 | 8.02 | 555 | 4.88 | 51.4 |
    /// | 6 | 34.2 | 7.87 | 543 | 4.95 | 52.5 |
    /// | 8 | 30.9 | 7.53 | 525 | 4.88 | 55.3 |
    ///
    /// M = 4 traces fastest on both models (the seed's 5 is within noise); larger M buys
    /// build time with trace time. Bins 8 / 32 at M = 4 on the dragon: 573 / 613 ms,
    /// 4.83 / 5.00 Mrays/s, SAH 51.7 / 50.0.
    fn default() -> Self {
        Self { bins: 16, leaf_size: 4, max_leaf_size: 16, traversal_cost: 1.0, intersection_cost: 1.0, reinsert: false }
    }
}

impl StructureParams for BvhParams {
    const STRUCTURE: &'static str = "bvh2";
    const KEYS: &'static [ParamKey] = &[
        ParamKey { name: "bins", doc: "SAH bins per axis, 2–256 (default 16)" },
        ParamKey { name: "leaf_size", doc: "nodes under this many triangles become leaves, 2–32 (default 4)" },
        ParamKey { name: "max_leaf_size", doc: "hard cap on a leaf, leaf_size − 1 to 1024 (default 16)" },
        ParamKey { name: "traversal_cost", doc: "SAH K_T, (0, 1000] (default 1)" },
        ParamKey { name: "intersection_cost", doc: "SAH K_I, (0, 1000] (default 1)" },
        ParamKey { name: "reinsert", doc: "move subtrees to lower the SAH cost after the build, on/off (default off)" },
    ];

    fn presets() -> Vec<(&'static str, Self)> {
        vec![("fast", Self::fast()), ("default", Self::default()), ("high_quality", Self::high_quality())]
    }

    fn set(&mut self, key: &str, v: &str) -> Result<(), BuildError> {
        let s = Self::STRUCTURE;
        match key {
            "bins" => self.bins = value::u32(s, key, v)?,
            "leaf_size" => self.leaf_size = value::u32(s, key, v)?,
            "max_leaf_size" => self.max_leaf_size = value::u32(s, key, v)?,
            "traversal_cost" => self.traversal_cost = value::f32(s, key, v)?,
            "intersection_cost" => self.intersection_cost = value::f32(s, key, v)?,
            "reinsert" => self.reinsert = value::bool(s, key, v)?,
            _ => return Err(unknown_key::<Self>(key)),
        }
        Ok(())
    }

    /// Checks every field against its documented range.
    fn validate(&self) -> Result<(), BuildError> {
        let err = out_of_range::<Self>;
        if !(2..=256).contains(&self.bins) {
            return err("bins", format!("{} is outside 2..=256", self.bins));
        }
        if !(2..=32).contains(&self.leaf_size) {
            return err("leaf_size", format!("{} is outside 2..=32", self.leaf_size));
        }
        if self.max_leaf_size + 1 < self.leaf_size || self.max_leaf_size > 1024 {
            return err(
                "max_leaf_size",
                format!("{} is outside {}..=1024 (leaf_size - 1 up to 1024)", self.max_leaf_size, self.leaf_size - 1),
            );
        }
        for (name, v) in [("traversal_cost", self.traversal_cost), ("intersection_cost", self.intersection_cost)] {
            if !(v > 0.0 && v <= 1000.0) {
                return err(name, format!("{v} is outside (0, 1000]"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_valid() {
        for (_, p) in BvhParams::presets() {
            p.validate().unwrap();
        }
    }

    #[test]
    fn out_of_range_fields_are_named() {
        let bad = [
            (BvhParams { bins: 1, ..Default::default() }, "bins"),
            (BvhParams { bins: 1000, ..Default::default() }, "bins"),
            (BvhParams { leaf_size: 1, ..Default::default() }, "leaf_size"),
            (BvhParams { max_leaf_size: 2, leaf_size: 8, ..Default::default() }, "max_leaf_size"),
            (BvhParams { traversal_cost: f32::NAN, ..Default::default() }, "traversal_cost"),
            (BvhParams { intersection_cost: 0.0, ..Default::default() }, "intersection_cost"),
        ];
        for (p, want) in bad {
            match p.validate() {
                Err(BuildError::Param { name, .. }) => assert_eq!(name, want, "{p:?}"),
                other => panic!("{p:?}: expected a {want} error, got {other:?}"),
            }
        }
    }
}
