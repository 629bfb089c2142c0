//! The A-PIT: the six A-buffers with each pixel's fragments in a pseudo-interval tree, so
//! that a ray tests only the fragments whose depth interval meets its own in that frustum.

use super::build::{build_filed, Base};
use super::node::{Fragment, PitNode, NONE};
use super::params::{ApitParams, Observer};
use super::pit::IntervalForest;
use super::query::{any, closest, Candidates};
use crate::InvalidStructure;
use crate::{Accel, AccelStats, BuildError, Counter, NoCount, OutlineBox, TraversalCounts};
use dynray_geom::{Hit, Ray, TriangleMesh, Vec3};
use std::ops::ControlFlow;

/// A-buffers + pseudo-interval trees on a cube around an observer (`--accel apit`).
#[derive(Clone, Debug)]
pub struct Apit {
    pub(crate) base: Base,
    /// Root node of each pixel's tree, or [`NONE`] (the seed's entry matrix).
    pub(crate) roots: Vec<u32>,
    /// Nodes and fragments of all trees.
    pub(crate) forest: IntervalForest,
    /// Deepest node of any tree (root = 0).
    pub(crate) depth_max: u32,
    /// Mean over non-empty pixels of the tree's deepest node.
    pub(crate) depth_mean: f64,
}

/// SplitMix64 finaliser: a fixed pseudo-random insertion order.
fn mix(mut x: u64) -> u64 {
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d049bb133111eb);
    x ^ (x >> 31)
}

impl Apit {
    /// Rasterises `mesh` into the six A-buffers and builds one tree per pixel.
    ///
    /// The seed inserts fragments in rasterisation order (arbitrary on a GPU). Here each
    /// pixel's fragments are inserted in a fixed pseudo-random order: inserting them in
    /// triangle order would feed spatially sorted, often disjoint intervals, which makes
    /// an online tree degenerate into a list (depth = fragment count); a random order
    /// gives a random binary search tree's expected logarithmic depth.
    pub fn build(mesh: &TriangleMesh, params: &ApitParams) -> Result<Self, BuildError> {
        let filed = build_filed(mesh, params)?;
        let pixels = filed.base.cube.pixels();
        let mut forest = IntervalForest::with_fragments(filed.frags);
        forest.nodes.reserve(forest.frags.len() / 2);
        let mut roots = vec![NONE; pixels];
        let (mut depth_max, mut depth_sum, mut nonempty) = (0u32, 0u64, 0u64);
        let mut order: Vec<u32> = Vec::new();
        for (p, root) in roots.iter_mut().enumerate() {
            let (s, e) = (filed.offsets[p], filed.offsets[p + 1]);
            if s == e {
                continue;
            }
            order.clear();
            order.extend(s..e);
            order.sort_unstable_by_key(|&k| mix(k as u64));
            let mut deepest = 0;
            for &k in &order {
                deepest = deepest.max(forest.insert(root, k));
            }
            depth_max = depth_max.max(deepest);
            depth_sum += deepest as u64;
            nonempty += 1;
        }
        forest.nodes.shrink_to_fit();
        let depth_mean = if nonempty > 0 { depth_sum as f64 / nonempty as f64 } else { 0.0 };
        let me = Self { base: filed.base, roots, forest, depth_max, depth_mean };
        #[cfg(debug_assertions)]
        if let Err(e) = me.check_invariants() {
            panic!("A-PIT built broken: {e}");
        }
        Ok(me)
    }

    /// Parameters it was built with.
    pub fn params(&self) -> &ApitParams {
        &self.base.params
    }
}

impl Candidates for Apit {
    #[inline]
    fn candidates<C: Counter>(
        &self,
        pixel: usize,
        qa: f32,
        qb: f32,
        c: &mut C,
        mut visit: impl FnMut(u32) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let root = self.roots[pixel];
        if root == NONE {
            return ControlFlow::Continue(());
        }
        let frags = &self.forest.frags;
        // The query counts tree nodes and reported fragments (= triangle tests).
        self.forest.query(root, qa, qb, c, |f| visit(frags[f as usize].tri))
    }
}

impl Accel for Apit {
    fn validate(&self, _mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        let invalid = |e| InvalidStructure::new(self.name(), e);
        self.check_invariants().map_err(invalid)?;
        Ok(self.stats())
    }

    fn name(&self) -> &'static str {
        "apit"
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        closest(&self.base, self, ray, &mut NoCount)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        any(&self.base, self, ray)
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        closest(&self.base, self, ray, counts)
    }

    fn memory_bytes(&self) -> usize {
        self.base.memory_bytes()
            + self.roots.len() * 4
            + self.forest.nodes.len() * std::mem::size_of::<PitNode>()
            + self.forest.frags.len() * std::mem::size_of::<Fragment>()
    }

    fn stats(&self) -> AccelStats {
        let nonempty = self.roots.iter().filter(|&&r| r != NONE).count();
        let mut extra = self.base.extra(self.forest.frags.len(), nonempty);
        extra.push(("tree depth max/mean".into(), format!("{} / {:.2}", self.depth_max, self.depth_mean)));
        AccelStats {
            nodes: self.forest.nodes.len(),
            leaves: nonempty,
            max_depth: self.depth_max,
            primitive_refs: self.forest.frags.len() + self.base.near.len(),
            leaf_sizes: Vec::new(),
            sah_cost: None,
            memory_bytes: self.memory_bytes(),
            extra,
        }
    }

    /// Rebuilds: the frustums' contents depend on every vertex (and the default observer).
    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        if mesh.triangle_count() != self.base.tris.len() {
            return Err(BuildError::TopologyChanged { built: self.base.tris.len(), given: mesh.triangle_count() });
        }
        *self = Self::build(mesh, &self.base.params)?;
        Ok(())
    }

    /// Rebuilds with the cube centred on `eye` (seed 004 centres it on the observer every
    /// frame), unless the structure was told `observer=center`. Later plain updates keep
    /// this eye.
    fn update_for_eye(&mut self, mesh: &TriangleMesh, eye: Vec3) -> Result<(), BuildError> {
        if self.base.params.observer != Observer::BoundsCenter {
            self.base.params = self.base.params.with_observer(eye);
        }
        self.update(mesh)
    }

    /// The cube of A-buffers around the observer, one leaf (outline.rs).
    fn outline(&self, _max_depth: u32, out: &mut Vec<OutlineBox>) {
        self.base.outline(out);
    }
}
