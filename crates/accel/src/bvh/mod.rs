//! The wide BVH: the binned-SAH binary tree (optionally built with Embree's block cost)
//! collapsed into 4- or 8-wide nodes with SoA child boxes, leaves of 4-triangle SoA
//! blocks, and an f64×4 block test that is bit-identical to the scalar triangle test.
//!
//! Files: [`params`] (presets), [`node`] (node layout and child references), `block.rs`
//! (leaf blocks and their padding), `collapse.rs` (binary → wide), `kernel.rs` (the
//! scalar specification and kernel choice), `kernel_avx2.rs` and `kernel_avx512.rs` (the AVX2 and AVX-512 kernels),
//! `traverse.rs`, `packet.rs`, `packet_avx2.rs` and `packet_traverse.rs` (8-ray packets
//! for coherent rays), `stream.rs` (batches: two incoherent rays in flight per thread, or
//! one after the other on one stack, any-hit ones with a last-occluder cache),
//! `refit.rs`, `validate.rs`, `outline.rs` (the viewer's boxes).
//!
//! This is `--accel bvh`, the default structure and the CPU's fast path. The binary tree
//! it collapses (crates/accel/src/bvh, `--accel bvh2`) stays what the GPU backend uploads. Figures and what did not pay: docs/structures.md, "The wide BVH".

mod block;
mod collapse;
mod kernel;
#[cfg(target_arch = "x86_64")]
mod kernel_avx2;
#[cfg(target_arch = "x86_64")]
mod kernel_avx512;
pub mod node;
mod outline;
mod packet;
#[cfg(target_arch = "x86_64")]
mod packet_avx2;
#[cfg(test)]
mod packet_tests;
mod packet_traverse;
pub mod params;
mod refit;
pub(crate) mod scan;
mod stream;
mod traverse;
mod validate;

pub use block::TriBlock;
pub use kernel::{KernelRequest, FORCE_SCALAR_ENV};
pub use node::{Node4, Node8, WideNode};
pub use packet::PACKET;
pub use params::{HugePages, WbvhParams, HUGE_PAGES_MIN_BYTES};
pub use stream::{looks_coherent, Interleave, INTERLEAVE_MIN_BYTES};
pub use validate::InvalidWbvh;

use crate::{Accel, AccelStats, BuildError, Bvh, BvhNode, InvalidStructure, NoCount, OutlineBox, TraversalCounts};
use dynray_geom::{Hit, Ray, TriangleMesh};
pub(crate) use kernel::KernelChoice;
use packet_traverse::{AnyHits, ClosestHits, PacketScratch, PacketWalk};
use stream::AnyBatch;

/// A wide BVH over one mesh, 4 or 8 children per node ([`WbvhParams::width`]).
#[derive(Clone, Debug)]
pub struct Wbvh {
    tree: Tree,
    params: WbvhParams,
    /// The `K_I` the tree was built with (`params`, or picked by the mesh's size).
    intersection_cost: f32,
}

/// The tree at its width: one match per query picks the monomorphised traversal.
#[derive(Clone, Debug)]
enum Tree {
    W4(WideTree<Node4>),
    W8(WideTree<Node8>),
}

/// The arrays of a `W`-wide tree.
#[derive(Clone, Debug)]
struct WideTree<N> {
    /// Root first; a node's interior children come after it, in adjacent slots.
    nodes: Vec<N>,
    /// Leaf blocks; a leaf's blocks are contiguous.
    blocks: Vec<TriBlock>,
    /// Interior levels on the deepest path (root alone: 1).
    levels: u32,
    /// Traversal stack entries this tree can need (`traverse::stack_need`).
    stack_need: usize,
    /// The kernel chosen at build time.
    kernel: KernelChoice,
    /// Triangles of the mesh it was built over (what a refit's mesh must have).
    triangles: usize,
    /// Built over pre-split references: a triangle may sit in several leaves, each leaf's
    /// box holding only its part (`WbvhParams::presplit`).
    presplit: bool,
    /// The arrays were advised for huge pages (`WbvhParams::huge_pages`).
    huge_pages: bool,
}

impl<N: WideNode> WideTree<N> {
    /// Collapses the binary tree `bin` (leaf-order mesh ids `ids`) over `mesh`.
    fn collapse(
        bin: &[BvhNode],
        ids: &[u32],
        mesh: &TriangleMesh,
        kernel: KernelChoice,
        pages: HugePages,
    ) -> Result<Self, BuildError> {
        let triangles = mesh.triangle_count();
        let c = collapse::collapse::<N>(bin, ids, |_, id| mesh.triangle(id as usize), pages)?;
        Ok(Self::from(c, kernel, triangles, ids.len() > triangles))
    }

    /// Collapses a built binary tree, reading its triangle copies.
    #[cfg(test)]
    fn build(bvh: &Bvh, kernel: KernelChoice) -> Result<Self, BuildError> {
        let tris = bvh.triangles();
        let c = collapse::collapse::<N>(bvh.nodes(), bvh.triangle_ids(), |i, _| tris[i], HugePages::Auto)?;
        Ok(Self::from(c, kernel, tris.len(), false))
    }

    fn from(c: collapse::Collapsed<N>, kernel: KernelChoice, triangles: usize, presplit: bool) -> Self {
        let stack_need = traverse::stack_need(c.levels, N::W);
        let collapse::Collapsed { nodes, blocks, levels, huge_pages } = c;
        Self { nodes, blocks, levels, stack_need, kernel, triangles, presplit, huge_pages }
    }
}

/// Runs `$body` with `$t` bound to the tree at its width.
macro_rules! with_tree {
    ($self:expr, $t:ident => $body:expr) => {
        match &$self.tree {
            Tree::W4($t) => $body,
            Tree::W8($t) => $body,
        }
    };
}

impl Wbvh {
    /// Builds the tree over `mesh`: binary SAH build (block cost unless
    /// `params.block_cost` is off), then the collapse. Errors on invalid parameters, an
    /// invalid mesh, or more triangles than the references address.
    pub fn build(mesh: &TriangleMesh, params: &WbvhParams) -> Result<Self, BuildError> {
        use crate::StructureParams;
        params.validate()?;
        let shift = if params.block_cost { 2 } else { 0 };
        let bvh = params.bvh_for(mesh.triangle_count());
        let (bin, ids) = Bvh::build_block_cost_nodes(mesh, &bvh, shift, params.presplit)?;
        let kernel = KernelChoice::resolve(params.kernel).map_err(|message| BuildError::Param {
            structure: "bvh",
            name: "kernel",
            message: format!("{}: {message}", params.kernel.name()),
        })?;
        let tree = match params.width {
            4 => Tree::W4(WideTree::collapse(&bin, &ids, mesh, kernel, params.huge_pages)?),
            _ => Tree::W8(WideTree::collapse(&bin, &ids, mesh, kernel, params.huge_pages)?),
        };
        let w = Self { tree, params: *params, intersection_cost: bvh.intersection_cost };
        #[cfg(debug_assertions)]
        if let Err(e) = w.check_invariants(mesh) {
            panic!("the builder produced an invalid wide BVH: {e}");
        }
        Ok(w)
    }

    /// The parameters of the build.
    pub fn params(&self) -> &WbvhParams {
        &self.params
    }

    /// The kernel in use: `"avx512"`, `"avx2"` or `"scalar"`.
    pub fn kernel(&self) -> &'static str {
        with_tree!(self, t => t.kernel.name())
    }

    /// Children per node.
    pub fn width(&self) -> usize {
        match self.tree {
            Tree::W4(_) => 4,
            Tree::W8(_) => 8,
        }
    }

    /// Closest hits of up to [`PACKET`] rays traced as one packet (packet.rs): `hits[i]`
    /// is `self.intersect(&rays[i])` bit for bit (triangle, `t`, `u`, `v`). The rays that
    /// share the first ray's origin travel together; any other ray (another origin, a
    /// NaN in it, a non-finite origin) is traced alone, and so is a packet of one.
    /// Panics unless `rays.len() == hits.len() <= PACKET`.
    pub fn intersect_packet(&self, rays: &[Ray], hits: &mut [Hit]) {
        assert!(rays.len() <= PACKET, "a packet holds at most {PACKET} rays, not {}", rays.len());
        self.coherent_in::<ClosestHits>(rays, hits);
    }

    /// Any-hit answers of up to [`PACKET`] rays traced as one packet: `out[i]` is
    /// `self.occluded(&rays[i])`. As [`Wbvh::intersect_packet`], the rays sharing the
    /// first ray's origin travel together and any other ray is traced alone.
    /// Panics unless `rays.len() == out.len() <= PACKET`.
    pub fn occluded_packet(&self, rays: &[Ray], out: &mut [bool]) {
        assert!(rays.len() <= PACKET, "a packet holds at most {PACKET} rays, not {}", rays.len());
        self.coherent_in::<AnyHits>(rays, out);
    }

    /// A coherent batch through walk `Q` ([`WideTree::coherent`]): packets of [`PACKET`]
    /// consecutive rays on one scratch, the rays that cannot travel together alone.
    fn coherent_in<Q: PacketWalk>(&self, rays: &[Ray], out: &mut [Q::Out]) {
        crate::batch::check_batch_lengths(rays.len(), out.len());
        with_tree!(self, t => t.coherent::<Q>(rays, out, &mut PacketScratch::new(t.stack_need)))
    }

    /// Checks every invariant traversal relies on against `mesh` (see validate.rs).
    pub fn check_invariants(&self, mesh: &TriangleMesh) -> Result<validate::WbvhShape, InvalidWbvh> {
        with_tree!(self, t => t.check(mesh))
    }
}

impl Accel for Wbvh {
    fn name(&self) -> &'static str {
        "bvh"
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        with_tree!(self, t => t.closest(ray, &mut NoCount))
    }

    fn occluded(&self, ray: &Ray) -> bool {
        with_tree!(self, t => t.any(ray, &mut NoCount))
    }

    /// Packets of [`PACKET`] consecutive rays ([`Wbvh::intersect_packet`]): a group whose
    /// rays share one origin travels together, other rays alone.
    fn intersect_coherent_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        self.coherent_in::<ClosestHits>(rays, hits);
    }

    /// Packets of [`PACKET`] consecutive rays ([`Wbvh::occluded_packet`]), as
    /// `intersect_coherent_into`.
    fn occluded_coherent_into(&self, rays: &[Ray], out: &mut [bool]) {
        self.coherent_in::<AnyHits>(rays, out);
    }

    fn traces_packets(&self) -> bool {
        true
    }

    /// `IN_FLIGHT` (2) rays interleaved per thread (stream.rs) where
    /// `interleave=` says so (by default, when the batch does not look coherent and the
    /// tree is at least [`INTERLEAVE_MIN_BYTES`]), else one
    /// after the other on one stack.
    fn intersect_stream_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        let interleaved = self.params.interleave.applies(rays, self.memory_bytes());
        with_tree!(self, t => t.closest_stream(rays, hits, interleaved))
    }

    /// As `intersect_stream_into`; batches that look coherent and are walked one ray
    /// after the other test the last occluder's leaf first where `occluder_cache=on`
    /// (the default).
    fn occluded_stream_into(&self, rays: &[Ray], out: &mut [bool]) {
        let how = if self.params.interleave.applies(rays, self.memory_bytes()) {
            AnyBatch::Interleaved
        } else if self.params.occluder_cache && looks_coherent(rays) {
            AnyBatch::EachCached
        } else {
            AnyBatch::Each
        };
        with_tree!(self, t => t.any_stream(rays, out, how))
    }

    /// Counts interior nodes visited and triangle lanes tested (4 per block, padding
    /// included: the work the kernel does).
    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        with_tree!(self, t => t.closest(ray, counts))
    }

    fn memory_bytes(&self) -> usize {
        with_tree!(self, t => t.nodes.len() * std::mem::size_of_val(&t.nodes[0]) + t.blocks.len() * std::mem::size_of::<TriBlock>())
    }

    fn stats(&self) -> AccelStats {
        let (shape, mut extra) = match with_tree!(self, t => t.shape()) {
            Ok(s) => (s, Vec::new()),
            Err(e) => (validate::WbvhShape::default(), vec![("invalid".to_string(), e.to_string())]),
        };
        extra.push(("width".into(), self.width().to_string()));
        extra.push(("kernel".into(), self.kernel().into()));
        extra.push(("interior_nodes".into(), shape.interior.to_string()));
        extra.push(("blocks".into(), shape.blocks.to_string()));
        extra.push(("filled_lanes".into(), format!("{:.1} %", 100.0 * shape.fill())));
        extra.push(("block_cost".into(), if self.params.block_cost { "on" } else { "off" }.into()));
        extra.push(("intersection_cost".into(), self.intersection_cost.to_string()));
        let huge = with_tree!(self, t => t.huge_pages);
        extra.push(("huge_pages".into(), if huge { "advised" } else { "off" }.into()));
        AccelStats {
            nodes: shape.interior + shape.leaves,
            leaves: shape.leaves,
            max_depth: shape.levels,
            primitive_refs: shape.triangles,
            leaf_sizes: shape.leaf_sizes.clone(),
            sah_cost: shape.sah_cost,
            memory_bytes: self.memory_bytes(),
            extra,
        }
    }

    fn validate(&self, mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        self.check_invariants(mesh).map_err(|e| InvalidStructure::new(self.name(), e))?;
        Ok(self.stats())
    }

    /// A refit: same tree, boxes and blocks recomputed from the moved vertices (refit.rs).
    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        match &mut self.tree {
            Tree::W4(t) => t.refit(mesh)?,
            Tree::W8(t) => t.refit(mesh)?,
        }
        #[cfg(debug_assertions)]
        if let Err(e) = self.check_invariants(mesh) {
            panic!("refit produced an invalid wide BVH: {e}");
        }
        Ok(())
    }

    fn update_refits(&self) -> bool {
        true
    }

    /// The root's box, then each child box one level below its node (outline.rs).
    fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        with_tree!(self, t => t.outline(max_depth, out))
    }
}

#[cfg(test)]
mod tests;
