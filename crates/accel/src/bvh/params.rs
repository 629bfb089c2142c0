//! Build parameters of the wide BVH: the width, the binary builder's settings and cost
//! model, and the kernel, with presets.

use super::kernel::KernelRequest;
use super::stream::Interleave;
use crate::structure_params::{out_of_range, unknown_key, value, ParamKey, StructureParams};
use crate::{BuildError, BvhParams};

/// How a [`super::Wbvh`] is built and traversed. Every field documents its useful range;
/// [`WbvhParams::validate`] rejects values outside it with [`BuildError::Param`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WbvhParams {
    /// Children per node: 4 or 8.
    pub width: u32,
    /// The binary SAH builder whose tree is collapsed (bins, leaf sizes, `K_T`, `K_I`).
    /// `max_leaf_size` is limited to 32 here (a leaf reference holds 8 blocks of 4).
    pub bvh: BvhParams,
    /// Cost leaves in blocks of 4 triangles (`⌈n/4⌉` tests, as the leaves are tested),
    /// Embree's block SAH; off costs `n`, as the binary BVH does. Blocks of 8 (`⌈n/8⌉`,
    /// the AVX-512 kernel's block pair; nodes under 9 triangles made leaves) lost 3–11 %
    /// on every ray kind on the bunny and the BART kitchen (round 6).
    pub block_cost: bool,
    /// The kernel: `Auto` (the fastest the CPU runs) or one named (the tests of each; a
    /// build fails where the CPU lacks it). `DYNRAY_FORCE_SCALAR=1` sends `Auto` to scalar.
    pub kernel: KernelRequest,
    /// Pick `K_I` by the mesh's size instead of `bvh.intersection_cost`:
    /// [`SMALL_TREE_INTERSECTION_COST`] for meshes under [`SMALL_TREE_TRIANGLES`], 1
    /// above. Setting the `intersection_cost` key turns it off, `intersection_cost=auto`
    /// on.
    ///
    /// Why: our f64 block test costs more against a box test than Embree's f32 one, so on
    /// trees that stay in the caches more, smaller leaves pay (single-block leaves: two
    /// bench runs, 2 threads, bunny +6–9 %, BART kitchen +8–19 % and robots +20–25 % on
    /// primary and shadow rays); on the 47 MiB dragon the extra nodes are memory traffic
    /// and the gains turn into losses (docs/structures.md, "The leaf cost by tree size").
    pub auto_intersection_cost: bool,
    /// When batches of independent rays keep several in flight per thread (stream.rs):
    /// `Auto` for batches that do not look coherent on trees of 16 MiB or more. Same
    /// answers either way.
    pub interleave: Interleave,
    /// Any-hit batches that look coherent ([`super::looks_coherent`]) and are walked one
    /// ray after the other test the leaf that occluded the previous ray first (a
    /// last-occluder cache, stream.rs): same answers, less work where neighbouring rays
    /// share an occluder (shadow rays of neighbouring pixels).
    pub occluder_cache: bool,
    /// Pre-splitting (bvh2/presplit.rs): about `presplit × n` extra triangle references
    /// cut from the triangles that fill their boxes worst, before the binned build; 0 is
    /// off, at most [`MAX_PRESPLIT`]. Same answers; a refit keeps the tree valid with the
    /// moved triangles' whole boxes.
    pub presplit: f32,
    /// When the tree's nodes and blocks are laid out on huge pages (crate::huge_pages):
    /// `Auto` for trees of [`HUGE_PAGES_MIN_BYTES`] or more. Same tree either way.
    pub huge_pages: HugePages,
}

/// When a tree's arrays are advised for huge pages (`huge_pages=` of [`WbvhParams`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HugePages {
    /// For trees of at least [`HUGE_PAGES_MIN_BYTES`].
    Auto,
    /// Always.
    On,
    /// Never.
    Off,
}

impl HugePages {
    /// The values `huge_pages=` takes, in declaration order.
    pub const NAMES: [&'static str; 3] = ["auto", "on", "off"];

    /// The policy named `NAMES[i]`.
    pub fn from_index(i: usize) -> Self {
        [HugePages::Auto, HugePages::On, HugePages::Off][i]
    }

    /// Whether a tree of `tree_bytes` goes on huge pages under this policy.
    pub fn applies(self, tree_bytes: usize) -> bool {
        match self {
            HugePages::Auto => tree_bytes >= HUGE_PAGES_MIN_BYTES,
            HugePages::On => true,
            HugePages::Off => false,
        }
    }
}

/// Trees below this size stay on ordinary pages under `huge_pages=auto`. They fit the
/// reach of Zen 4's L2 TLB (3,072 pages of 4 KiB, 12 MiB), and there huge pages measured
/// −1 to −3 % on the BART kitchen (6.5 MiB) and ±1 % on the bunny (4 MiB); on the 47 MiB
/// dragon, +6–10 % on diffuse and random rays and +25 % on shuffled shadow rays
/// (docs/structures.md, "Huge pages").
pub const HUGE_PAGES_MIN_BYTES: usize = 16 << 20;

/// Largest [`WbvhParams::presplit`] budget (4 extra references per triangle).
pub const MAX_PRESPLIT: f32 = 4.0;

/// Meshes under this many triangles count as small for [`WbvhParams::auto_intersection_cost`]:
/// their trees (~56 bytes per triangle) stay under the 16 MiB from which the walks wait on
/// memory ([`super::INTERLEAVE_MIN_BYTES`]).
pub const SMALL_TREE_TRIANGLES: usize = 300_000;

/// `K_I` of small meshes under [`WbvhParams::auto_intersection_cost`]. 1.5 and 2 measured
/// the same as 1.25 on the bunny and BART's kitchen and robots (leaves split into single
/// blocks either way); 1.25 builds fastest.
pub const SMALL_TREE_INTERSECTION_COST: f32 = 1.25;

impl WbvhParams {
    /// The binary builder's parameters for a mesh of `triangles` triangles: `bvh`, with
    /// `K_I` picked by size where [`WbvhParams::auto_intersection_cost`] is on.
    pub fn bvh_for(&self, triangles: usize) -> BvhParams {
        let mut b = self.bvh;
        if self.auto_intersection_cost {
            b.intersection_cost = if triangles < SMALL_TREE_TRIANGLES { SMALL_TREE_INTERSECTION_COST } else { 1.0 };
        }
        b
    }

    /// Quicker builds: 8 bins (as [`BvhParams::fast`]).
    pub fn fast() -> Self {
        Self { bvh: BvhParams { bins: 8, ..Self::default().bvh }, ..Self::default() }
    }

    /// Slower builds, better trees: 32 bins and reinsertion on the binary tree before the
    /// collapse (figures: docs/structures.md, "Reinsertion").
    pub fn high_quality() -> Self {
        Self { bvh: BvhParams { bins: 32, reinsert: true, ..Self::default().bvh }, ..Self::default() }
    }
}

impl Default for WbvhParams {
    /// Width 8, 16 bins, block cost, nodes of up to 4 triangles become leaves (Embree's
    /// minimum leaf for 4-triangle blocks), leaves up to 16 triangles (4 blocks), `K_I` by
    /// the mesh's size. The width and leaf sizes were measured: see docs/structures.md,
    /// "The wide BVH".
    fn default() -> Self {
        Self {
            width: 8,
            bvh: BvhParams {
                bins: 16,
                leaf_size: 5,
                max_leaf_size: 16,
                traversal_cost: 1.0,
                intersection_cost: 1.0,
                reinsert: false,
            },
            block_cost: true,
            auto_intersection_cost: true,
            kernel: KernelRequest::Auto,
            interleave: Interleave::Auto,
            occluder_cache: true,
            presplit: 0.0,
            huge_pages: HugePages::Auto,
        }
    }
}

impl StructureParams for WbvhParams {
    const STRUCTURE: &'static str = "bvh";
    const KEYS: &'static [ParamKey] = &[
        ParamKey { name: "width", doc: "children per node, 4 or 8 (default 8)" },
        ParamKey { name: "bins", doc: "SAH bins per axis, 2–256 (default 16)" },
        ParamKey { name: "leaf_size", doc: "nodes under this many triangles become leaves, 2–32 (default 5)" },
        ParamKey { name: "max_leaf_size", doc: "hard cap on a leaf, leaf_size − 1 to 32 (default 16)" },
        ParamKey { name: "block_cost", doc: "SAH leaf cost in 4-triangle blocks, on/off (default on)" },
        ParamKey { name: "traversal_cost", doc: "SAH K_T, (0, 1000] (default 1)" },
        ParamKey {
            name: "intersection_cost",
            doc: "SAH K_I, (0, 1000], or auto (default auto: 1.25 under 300,000 triangles, 1 above)",
        },
        ParamKey {
            name: "interleave",
            doc: "batches of rays keep several in flight per thread: auto (incoherent batches on trees of 16 MiB or more), on, off (default auto)",
        },
        ParamKey {
            name: "occluder_cache",
            doc: "coherent any-hit batches test the previous ray's occluding leaf first, on/off (default on)",
        },
        ParamKey {
            name: "presplit",
            doc: "extra triangle references cut from badly boxed triangles before the build, per triangle, 0–4 (default 0: off)",
        },
        ParamKey {
            name: "huge_pages",
            doc: "lay the tree out on huge pages (Linux THP): auto (trees of 16 MiB or more), on, off (default auto)",
        },
        ParamKey {
            name: "reinsert",
            doc: "move subtrees to lower the SAH cost before the collapse, on/off (default off)",
        },
        ParamKey { name: "kernel", doc: "auto (the fastest present), avx512, avx2 or scalar (default auto)" },
    ];

    fn presets() -> Vec<(&'static str, Self)> {
        vec![("fast", Self::fast()), ("default", Self::default()), ("high_quality", Self::high_quality())]
    }

    fn set(&mut self, key: &str, v: &str) -> Result<(), BuildError> {
        let s = Self::STRUCTURE;
        match key {
            "width" => self.width = value::u32(s, key, v)?,
            "bins" => self.bvh.bins = value::u32(s, key, v)?,
            "leaf_size" => self.bvh.leaf_size = value::u32(s, key, v)?,
            "max_leaf_size" => self.bvh.max_leaf_size = value::u32(s, key, v)?,
            "block_cost" => self.block_cost = value::bool(s, key, v)?,
            "traversal_cost" => self.bvh.traversal_cost = value::f32(s, key, v)?,
            "intersection_cost" if v == "auto" => self.auto_intersection_cost = true,
            "intersection_cost" => {
                self.bvh.intersection_cost = value::f32(s, key, v)?;
                self.auto_intersection_cost = false;
            }
            "reinsert" => self.bvh.reinsert = value::bool(s, key, v)?,
            "occluder_cache" => self.occluder_cache = value::bool(s, key, v)?,
            "presplit" => self.presplit = value::f32(s, key, v)?,
            "interleave" => {
                let i = value::choice(s, key, v, &Interleave::NAMES, "auto, on or off")?;
                self.interleave = Interleave::from_index(i);
            }
            "huge_pages" => {
                let i = value::choice(s, key, v, &HugePages::NAMES, "auto, on or off")?;
                self.huge_pages = HugePages::from_index(i);
            }
            "kernel" => {
                let i = value::choice(s, key, v, &KernelRequest::NAMES, "auto, avx512, avx2 or scalar")?;
                self.kernel = KernelRequest::from_index(i);
            }
            _ => return Err(unknown_key::<Self>(key)),
        }
        Ok(())
    }

    /// Checks every field against its documented range.
    fn validate(&self) -> Result<(), BuildError> {
        let err = out_of_range::<Self>;
        if self.width != 4 && self.width != 8 {
            return err("width", format!("{} is neither 4 nor 8", self.width));
        }
        if self.bvh.max_leaf_size > 32 {
            return err("max_leaf_size", format!("{} is above 32 (8 blocks of 4)", self.bvh.max_leaf_size));
        }
        if !(0.0..=MAX_PRESPLIT).contains(&self.presplit) {
            return err("presplit", format!("{} is outside 0–{MAX_PRESPLIT}", self.presplit));
        }
        // The binary builder's own ranges (bins, leaf_size, costs), named as ours.
        self.bvh.validate().map_err(|e| match e {
            BuildError::Param { name, message, .. } => BuildError::Param { structure: Self::STRUCTURE, name, message },
            other => other,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `key=value` pairs as `from_pairs` takes them.
    fn pairs(s: &[(&str, &str)]) -> Vec<(String, String)> {
        s.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect()
    }

    #[test]
    fn presets_are_valid() {
        for (_, p) in WbvhParams::presets() {
            p.validate().unwrap();
        }
    }

    #[test]
    fn out_of_range_fields_are_named() {
        let d = WbvhParams::default();
        let bad = [
            (WbvhParams { width: 2, ..d }, "width"),
            (WbvhParams { width: 16, ..d }, "width"),
            (WbvhParams { bvh: BvhParams { max_leaf_size: 33, ..d.bvh }, ..d }, "max_leaf_size"),
            (WbvhParams { bvh: BvhParams { bins: 1, ..d.bvh }, ..d }, "bins"),
            (WbvhParams { bvh: BvhParams { leaf_size: 40, ..d.bvh }, ..d }, "leaf_size"),
            (WbvhParams { presplit: -0.5, ..d }, "presplit"),
            (WbvhParams { presplit: f32::NAN, ..d }, "presplit"),
            (WbvhParams { presplit: 5.0, ..d }, "presplit"),
        ];
        for (p, want) in bad {
            match p.validate() {
                Err(BuildError::Param { structure, name, .. }) => {
                    assert_eq!((structure, name), ("bvh", want), "{p:?}")
                }
                other => panic!("{p:?}: expected a {want} error, got {other:?}"),
            }
        }
    }

    #[test]
    fn keys_set_their_fields() {
        let p = WbvhParams::from_pairs(&pairs(&[("width", "4"), ("kernel", "scalar"), ("block_cost", "off")])).unwrap();
        assert_eq!((p.width, p.kernel, p.block_cost), (4, KernelRequest::Scalar, false));
        for (name, k) in
            [("avx512", KernelRequest::Avx512), ("avx2", KernelRequest::Avx2), ("auto", KernelRequest::Auto)]
        {
            assert_eq!(WbvhParams::from_pairs(&pairs(&[("kernel", name)])).unwrap().kernel, k);
            assert_eq!(k.name(), name);
        }
        assert!(WbvhParams::from_pairs(&pairs(&[("kernel", "sse")])).is_err());
    }

    #[test]
    fn intersection_cost_is_picked_by_size_unless_set() {
        let d = WbvhParams::default();
        assert_eq!(d.bvh_for(SMALL_TREE_TRIANGLES - 1).intersection_cost, SMALL_TREE_INTERSECTION_COST);
        assert_eq!(d.bvh_for(SMALL_TREE_TRIANGLES).intersection_cost, 1.0);
        let set = WbvhParams::from_pairs(&pairs(&[("intersection_cost", "2")])).unwrap();
        assert!(!set.auto_intersection_cost);
        assert_eq!((set.bvh_for(10).intersection_cost, set.bvh_for(1 << 20).intersection_cost), (2.0, 2.0));
        let auto = WbvhParams::from_pairs(&pairs(&[("intersection_cost", "2"), ("intersection_cost", "auto")]));
        assert_eq!(auto.unwrap().bvh_for(10).intersection_cost, SMALL_TREE_INTERSECTION_COST);
        assert!(WbvhParams::from_pairs(&pairs(&[("intersection_cost", "cheap")])).is_err());
    }

    #[test]
    fn huge_pages_key_and_threshold() {
        assert_eq!(WbvhParams::default().huge_pages, HugePages::Auto);
        for (i, name) in HugePages::NAMES.iter().enumerate() {
            let p = WbvhParams::from_pairs(&pairs(&[("huge_pages", name)])).unwrap();
            assert_eq!(p.huge_pages, HugePages::from_index(i));
        }
        let e = WbvhParams::from_pairs(&pairs(&[("huge_pages", "sometimes")])).unwrap_err().to_string();
        assert!(e.contains("huge_pages") && e.contains("sometimes"), "{e}");
        assert!(HugePages::Auto.applies(HUGE_PAGES_MIN_BYTES) && !HugePages::Auto.applies(HUGE_PAGES_MIN_BYTES - 1));
        assert!(HugePages::On.applies(0) && !HugePages::Off.applies(usize::MAX));
    }
}
