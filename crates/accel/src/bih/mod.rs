//! Bounding Interval Hierarchy (Wächter & Keller, EGSR 2006) as seed 000 builds it for
//! per-frame rebuilds: 16-byte nodes with two clip planes, a midpoint split of a spatial
//! node box, and the seed's "shrink" step (`BihParams::shrink`).
//!
//! Files: `node.rs` (encoding), `params.rs`, `build.rs`, `traverse.rs`, `refit.rs`,
//! `validate.rs`, `outline.rs` (the viewer's boxes).
//!
//! Measured (release, 2 loaded cores, 200k rays from outside aimed into the box; per ray
//! single-threaded). Work per ray is exact, Mrays/s are ±15 % noise:
//!
//! | bunny 69k tris, max_prims 8        | nodes/ray | tris/ray | Mrays/s | build ms | MB   |
//! |------------------------------------|-----------|----------|---------|----------|------|
//! | seed 000 (shrink 1.3, no cuts)     | 87.7      | 138      | 0.10    | 18       | 3.0  |
//! | W-K (no shrink, no cuts)           | 66.4      | 82       | 0.20    | 17       | 3.0  |
//! | shrink 1.3 + empty cuts 0.25       | 30.9      | 11.7     | 0.59    | 12       | 3.1  |
//! | no shrink + empty cuts 0.25        | 30.9      | 11.7     | 0.62    | 11       | 3.1  |
//!
//! (Rows measured when the shrink step narrowed all three axes; it now narrows the split
//! axis alone, as the seed's pseudo-code does, which tests about 10 % fewer triangles than
//! that but still more than no shrink: `dynray bench --preset seed000`, docs/results.md.)
//!
//! Without empty-space cuts a BIH leaf is bounded only on the axes its ancestors split,
//! and a node whose triangles fill a small part of its box leaves that emptiness
//! unbounded: rays test 7–12× more triangles. The seed's shrink step alone makes this
//! worse on the bunny (it moves split planes but adds none); with cuts it is neutral.
//! Hence the default adds W-K's one-child nodes (`BihParams::empty_cut`) and keeps the
//! shrink step as the seed asks. With cuts, leaf sizes 4–8 trace equally fast on the
//! bunny and the dragon (0.6 / 0.38 Mrays/s) and 8 builds faster than 4 (bunny 12 ms vs
//! 14–21 ms, dragon 60 vs 78 ms), so 8 is the default; seed 000 found 10 best on the GPU.

mod build;
mod cost;
mod node;
mod outline;
mod params;
mod refit;
mod traverse;
mod validate;

pub use node::{BihNode, LEAF_FLAG, MAX_INDEX};
pub use params::{BihParams, MAX_DEPTH_LIMIT};
pub use validate::InvalidBih;

use crate::InvalidStructure;
use crate::StructureParams;
use crate::{Accel, AccelStats, BuildError, NoCount, OutlineBox, TraversalCounts};
use dynray_geom::{Aabb, Hit, Ray, Triangle, TriangleMesh};
use rayon::prelude::*;

/// A BIH over one triangle mesh.
pub struct Bih {
    /// Nodes in depth-first pre-order; the root is node 0.
    nodes: Vec<BihNode>,
    /// Triangles copied in leaf order (a leaf owns a contiguous run).
    tris: Vec<Triangle>,
    /// Mesh triangle index of each entry of `tris`.
    prim_ids: Vec<u32>,
    /// Union of all triangle boxes; rays are clipped to it first.
    bounds: Aabb,
    /// Depth of the deepest leaf (root = 0).
    depth: u32,
    params: BihParams,
}

impl Bih {
    /// Builds the hierarchy over `mesh`.
    pub fn build(mesh: &TriangleMesh, params: &BihParams) -> Result<Self, BuildError> {
        params.validate()?;
        mesh.validate()?;
        let boxes: Vec<Aabb> = (0..mesh.triangle_count()).into_par_iter().map(|i| mesh.triangle(i).bounds()).collect();
        let bounds = boxes.par_iter().cloned().reduce(|| Aabb::EMPTY, |a, b| a.union(&b));
        let prims = build::Prims::new(boxes);
        let built = build::build(&prims, bounds, params)?;
        let tris = built.order.par_iter().map(|&i| mesh.triangle(i as usize)).collect();
        let bih = Self { nodes: built.nodes, tris, prim_ids: built.order, bounds, depth: built.depth, params: *params };
        #[cfg(debug_assertions)]
        if let Err(e) = bih.check_invariants() {
            panic!("BIH builder produced an invalid tree: {e}");
        }
        Ok(bih)
    }

    /// The node array (pre-order, root first), e.g. for a GPU upload.
    pub fn nodes(&self) -> &[BihNode] {
        &self.nodes
    }

    /// Mesh triangle indices in leaf order (a leaf's `index()` points into this).
    pub fn prim_ids(&self) -> &[u32] {
        &self.prim_ids
    }

    /// The parameters the tree was built with.
    pub fn params(&self) -> &BihParams {
        &self.params
    }

    /// Depth of the deepest leaf (root = 0).
    pub fn depth(&self) -> u32 {
        self.depth
    }
}

impl Accel for Bih {
    fn validate(&self, _mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        let invalid = |e| InvalidStructure::new(self.name(), e);
        self.check_invariants().map_err(invalid)?;
        Ok(self.stats())
    }

    fn name(&self) -> &'static str {
        "bih"
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        self.closest(ray, &mut NoCount)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.any(ray, &mut NoCount)
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        self.closest(ray, counts)
    }

    fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.nodes.len() * size_of::<BihNode>()
            + self.tris.len() * size_of::<Triangle>()
            + self.prim_ids.len() * size_of::<u32>()
    }

    fn stats(&self) -> AccelStats {
        let mut sizes = crate::LeafSizes::new();
        let mut leaves = 0;
        for n in self.nodes.iter().filter(|n| n.is_leaf()) {
            leaves += 1;
            sizes.add(n.count as usize);
        }
        let leaf_sizes = sizes.finish();
        let shrink = self.params.shrink.map_or("off".to_string(), |f| f.to_string());
        AccelStats {
            nodes: self.nodes.len(),
            leaves,
            max_depth: self.depth,
            primitive_refs: self.tris.len(),
            leaf_sizes,
            sah_cost: Bih::sah_cost(self),
            memory_bytes: self.memory_bytes(),
            extra: vec![
                ("max_prims".into(), self.params.max_prims.to_string()),
                ("max_depth".into(), self.params.max_depth.to_string()),
                ("shrink".into(), shrink),
            ],
        }
    }

    fn sah_cost(&self) -> Option<f64> {
        Bih::sah_cost(self)
    }

    /// Refits (same topology, new clip planes); see `refit.rs`.
    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        self.refit(mesh)
    }

    fn update_refits(&self) -> bool {
        true
    }

    /// Node boxes derived from the scene box and the clip planes (outline.rs).
    fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        self.outline_boxes(max_depth, out);
    }
}
