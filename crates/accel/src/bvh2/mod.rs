//! The binned-SAH bounding volume hierarchy of seed 003 (Martins 2010, §2.3 and §3.3):
//! a binary BVH over triangle centroids, split by the surface-area heuristic evaluated on
//! `k` bins per axis, stored as a flat array of 32-byte nodes.
//!
//! This is `--accel bvh2`: what the GPU backend uploads and the tree the wide BVH
//! (crates/accel/src/wbvh, `--accel bvh`, the default) is collapsed from.
//!
//! Files: [`params`] (presets), [`node`] (encoding), `build.rs` (parallel deterministic
//! builder: binning and the SAH sweep), `partition.rs` (its serial and parallel
//! partitions), `prim_ref.rs` (the 32-byte triangle references they move), `assemble.rs` (joining the parallel subtrees), `traverse.rs` (closest and any hit), `closest.rs` (closest-point query),
//! `refit.rs`, `validate.rs`, `outline.rs` (the viewer's boxes), `reinsert.rs` (the `high_quality` presets' SAH
//! optimisation pass).
//!
//! Leaf size `M` (the seed found 5): measured with `benches/bvh.rs` on this 2-core machine,
//! see the comment on [`BvhParams::default`].

mod assemble;
mod build;
mod closest;
pub mod node;
pub(crate) mod outline;
pub mod params;
mod partition;
mod presplit;
mod prim_ref;
mod refit;
mod reinsert;
mod traverse;
mod validate;

pub use closest::{closest_on_triangle, closest_point_brute, ClosestPoint};
pub use node::BvhNode;
pub use params::BvhParams;
pub use validate::{BvhStats, InvalidBvh};

use crate::InvalidStructure;
use crate::{Accel, AccelStats, BuildError, NoCount, OutlineBox, TraversalCounts};
use dynray_geom::{Hit, Ray, Triangle, TriangleMesh};

/// A binned-SAH BVH over one mesh.
#[derive(Clone, Debug)]
pub struct Bvh {
    /// Root first; children pairs adjacent (see [`BvhNode`]).
    nodes: Vec<BvhNode>,
    /// Copies of the mesh's triangles in leaf order, so leaves read contiguous memory.
    tris: Vec<Triangle>,
    /// `ids[i]` = the mesh index of `tris[i]`.
    ids: Vec<u32>,
    /// The parameters it was built with (SAH constants feed `stats`).
    params: BvhParams,
    /// Depth of the deepest leaf (root = 0): picks the traversal stack size.
    depth: u32,
}

impl Bvh {
    /// Builds the tree over `mesh`. Errors on invalid parameters, an invalid mesh
    /// (empty, non-finite, bad index) or more than 2^31 - 1 triangles.
    pub fn build(mesh: &TriangleMesh, params: &BvhParams) -> Result<Self, BuildError> {
        let built = build::build(mesh, params)?;
        let bvh = Self { nodes: built.nodes, tris: built.tris, ids: built.ids, params: *params, depth: built.depth };
        #[cfg(debug_assertions)]
        if let Err(e) = bvh.check_invariants(mesh) {
            panic!("the builder produced an invalid BVH: {e}");
        }
        Ok(bvh)
    }

    /// [`Bvh::build`] with leaves costed in blocks of `2^block_shift` triangles (the wide
    /// BVH's leaf blocks; see `build::build_blocks`): the binary tree the wide BVH collapses.
    #[cfg(test)]
    pub(crate) fn build_block_cost(
        mesh: &TriangleMesh,
        params: &BvhParams,
        block_shift: u32,
    ) -> Result<Self, BuildError> {
        let built = build::build_blocks(mesh, params, block_shift, true, 0.0)?;
        let bvh = Self { nodes: built.nodes, tris: built.tris, ids: built.ids, params: *params, depth: built.depth };
        #[cfg(debug_assertions)]
        if let Err(e) = bvh.check_invariants(mesh) {
            panic!("the builder produced an invalid BVH: {e}");
        }
        Ok(bvh)
    }

    /// The node array and leaf-order mesh ids of [`Bvh::build_block_cost`]'s tree, without
    /// the leaf-order triangle copies the wide BVH's collapse does not read; with
    /// `presplit > 0` over pre-split references (a mesh id may then repeat across leaves).
    pub(crate) fn build_block_cost_nodes(
        mesh: &TriangleMesh,
        params: &BvhParams,
        block_shift: u32,
        presplit: f32,
    ) -> Result<(Vec<BvhNode>, Vec<u32>), BuildError> {
        let built = build::build_blocks(mesh, params, block_shift, false, presplit)?;
        Ok((built.nodes, built.ids))
    }

    /// A tree assembled from arrays built elsewhere (the GPU builders of `dynray-gpu`),
    /// accepted only if it passes every invariant [`Bvh::build`]'s trees do, against `mesh`:
    /// children pairs adjacent and after their parent, every triangle in exactly one leaf,
    /// leaf triangles exact copies of the mesh's, depth within the traversal stack.
    pub fn from_parts(
        mesh: &TriangleMesh,
        nodes: Vec<BvhNode>,
        tris: Vec<Triangle>,
        ids: Vec<u32>,
        params: &BvhParams,
    ) -> Result<Self, InvalidBvh> {
        let depth = deepest_leaf(&nodes);
        let bvh = Self { nodes, tris, ids, params: *params, depth };
        bvh.check_invariants(mesh)?;
        Ok(bvh)
    }

    /// The node array, root first.
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// Triangles in leaf order.
    pub fn triangles(&self) -> &[Triangle] {
        &self.tris
    }

    /// Mesh index of each leaf-order triangle.
    pub fn triangle_ids(&self) -> &[u32] {
        &self.ids
    }

    /// The parameters of the build.
    pub fn params(&self) -> &BvhParams {
        &self.params
    }

    /// Depth of the deepest leaf (root = 0): what a traversal stack must hold.
    pub fn depth(&self) -> u32 {
        self.depth
    }
}

/// Depth of the deepest leaf of a node array not yet known to be a tree: bad links and
/// cycles end the walk early (the validator then reports them).
fn deepest_leaf(nodes: &[BvhNode]) -> u32 {
    let (mut deepest, mut visits) = (0, 0);
    let mut stack = vec![(0usize, 0u32)];
    while let Some((i, depth)) = stack.pop() {
        visits += 1;
        let Some(node) = nodes.get(i).filter(|_| visits <= nodes.len()) else { break };
        deepest = deepest.max(depth);
        if !node.is_leaf() {
            let left = node.index as usize;
            stack.extend([(left, depth + 1), (left.saturating_add(1), depth + 1)]);
        }
    }
    deepest
}

impl Accel for Bvh {
    fn validate(&self, mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        let invalid = |e| InvalidStructure::new(self.name(), e);
        self.check_invariants(mesh).map_err(invalid)?;
        Ok(self.stats())
    }

    fn name(&self) -> &'static str {
        "bvh2"
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        self.traverse(ray, &mut NoCount)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.any_hit(ray, &mut NoCount)
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        self.traverse(ray, counts)
    }

    fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.nodes.len() * size_of::<BvhNode>() + self.tris.len() * size_of::<Triangle>() + self.ids.len() * 4
    }

    fn stats(&self) -> AccelStats {
        // A tree this type built or refitted is valid; should that ever break, report the
        // breakage instead of panicking in a listing.
        let (s, extra) = match self.check_shape() {
            Ok(s) => (s, Vec::new()),
            Err(e) => (BvhStats::default(), vec![("invalid".to_string(), e.to_string())]),
        };
        let mut extra = extra;
        extra.push(("bins".into(), self.params.bins.to_string()));
        extra.push(("leaf_size".into(), self.params.leaf_size.to_string()));
        AccelStats {
            nodes: s.nodes,
            leaves: s.leaves,
            max_depth: s.max_depth,
            primitive_refs: self.tris.len(),
            leaf_sizes: s.leaf_sizes,
            sah_cost: s.sah_cost,
            memory_bytes: self.memory_bytes(),
            extra,
        }
    }

    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        self.refit(mesh)
    }

    fn update_refits(&self) -> bool {
        true
    }

    /// Every node's box, leaves marked (outline.rs).
    fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        outline::outline_nodes(&self.nodes, max_depth, out);
    }

    /// The formula of `stats` (validate.rs) in one pass over the node array, without the
    /// checks and their allocations: what the `auto` update policy reads every frame.
    fn sah_cost(&self) -> Option<f64> {
        let root_area = self.nodes.first()?.bounds().surface_area() as f64;
        if root_area.is_nan() || root_area <= 0.0 {
            return None;
        }
        let (kt, ki) = (self.params.traversal_cost as f64, self.params.intersection_cost as f64);
        let sah: f64 = self
            .nodes
            .iter()
            .map(|n| {
                let area = n.bounds().surface_area() as f64;
                if n.is_leaf() {
                    ki * n.count as f64 * area
                } else {
                    kt * area
                }
            })
            .sum();
        Some(sah / root_area)
    }
}

#[cfg(test)]
mod tests;
