//! The 2:1-balanced octree of seed 002 (Portalez & Duguet 2016): leaves only, serialised
//! as 32-bit word records with explicit face-neighbour links, entered through a cube map
//! of boundary leaves and walked with Plücker tests ([`Octree`], `--accel octree`); and
//! the classic top-down parametric descent over the same leaves ([`OctreeDescent`],
//! `--accel octree-descent`), which uses a compact internal-node array kept beside the
//! records (also used for point location by the walk).
//!
//! Decisions the seed leaves open (see also each file's notes):
//! - The root is the scene box made cubic (largest extent) and padded by 2^-16 so every
//!   vertex is strictly inside; cell planes are computed so that shared faces are
//!   bit-identical across depths.
//! - Triangle–cell overlap is the exact SAT test in f64 on cells widened by 2^-17 of the
//!   scene's coordinate magnitude: touching counts, and the walk's rounding near edges
//!   can never skip a triangle (walk.rs explains why this matters).
//! - Split while `depth < max_depth` and `triangles > leaf_threshold`; a split in which a
//!   child keeps every triangle is allowed only twice per path and only if it at most
//!   doubles the references, plus a global budget (bounded memory on degenerate input).
//! - Balance is face-only 2:1 (only faces carry links): a leaf is split while a face
//!   neighbour is two or more levels deeper. On the bunny (depth 8, 12 per leaf) it adds
//!   24 % leaves (77k → 96k; the seed's Table 1: 69k → 83k, +20 %).
//! - Internal nodes (32 bytes each, ~14 % of the leaf count) are kept: the descent
//!   needs them, and the walk uses them for point location of rays starting inside the
//!   root and, in unbalanced trees, to cross faces with more than four neighbours.
//! - The cube map's resolution is the finest depth of any leaf touching the root boundary
//!   (2^8 on the bunny: 1.5 MB, as the seed's Table 3).
//! - Boxes are 32 bytes (both corners and the integer cell), not the seed's 16.
//! - Both traversals share one build; `memory_bytes` of either counts every array.
//!
//! Files: `params.rs`, `node.rs` (encodings), `tables.rs` (the seed's lookup tables and
//! their convention), `build.rs`, `walk.rs` (the seed's
//! traversal), `descent.rs` (Revelles et al. 2000), `validate.rs`, `outline.rs` (the viewer's
//! cells).

mod build;
mod descent;
mod node;
mod outline;
mod params;
mod tables;
mod validate;
mod walk;

pub use node::{InnerNode, LeafBox, LEAF_BIT, LOCATE};
pub use params::{OctreeParams, MAX_DEPTH_LIMIT};
pub use tables::{FACE_TO_NEIGHBOR_INDEX, OUT_FACES_LOOKUP};
pub use validate::InvalidOctree;

use crate::InvalidStructure;
use crate::StructureParams;
use crate::{Accel, AccelStats, BuildError, NoCount, OutlineBox, TraversalCounts};
use build::Frame;
use dynray_geom::{Aabb, Hit, Ray, Triangle, TriangleMesh};
use std::mem::size_of;

/// A leaf octree over one triangle mesh, traversed by the seed's neighbour walk.
pub struct Octree {
    /// Leaf records, word encoded (see [`node`]'s `REC_*`); leaf 0 at address 0.
    records: Vec<u32>,
    /// One box per leaf, indexed by the record's leaf index.
    boxes: Vec<LeafBox>,
    /// Triangles copied per leaf reference (each leaf owns a contiguous run).
    tris: Vec<Triangle>,
    /// Mesh triangle index of each entry of `tris`.
    prim_ids: Vec<u32>,
    /// Internal nodes, root first (empty when the root is a leaf).
    inner: Vec<InnerNode>,
    /// Root reference: internal node 0, or `LEAF_BIT | 0` for a single-leaf tree.
    root: u32,
    /// Boundary-leaf record addresses, `6 · R²` with `R = 2^cube_depth`.
    cube_map: Vec<u32>,
    cube_depth: u32,
    /// Depth of the deepest leaf: the resolution of point location.
    fine_depth: u32,
    frame: Frame,
    root_box: Aabb,
    params: OctreeParams,
    leaves_before_balance: usize,
    locate_faces: usize,
    mesh_triangles: usize,
}

impl Octree {
    /// Builds the octree over `mesh`.
    pub fn build(mesh: &TriangleMesh, params: &OctreeParams) -> Result<Self, BuildError> {
        params.validate()?;
        mesh.validate()?;
        let b = build::build(mesh, params)?;
        let oct = Self {
            records: b.records,
            boxes: b.boxes,
            tris: b.tris,
            prim_ids: b.prim_ids,
            inner: b.inner,
            root: b.root,
            cube_map: b.cube_map,
            cube_depth: b.cube_depth,
            fine_depth: b.fine_depth,
            root_box: b.frame.cell_box([0; 3], 0),
            frame: b.frame,
            params: *params,
            leaves_before_balance: b.leaves_before_balance,
            locate_faces: b.locate_faces,
            mesh_triangles: mesh.triangle_count(),
        };
        #[cfg(debug_assertions)]
        if let Err(e) = oct.check_invariants() {
            panic!("octree builder produced an invalid tree: {e}");
        }
        Ok(oct)
    }

    /// The parameters the tree was built with.
    pub fn params(&self) -> &OctreeParams {
        &self.params
    }

    /// Number of leaves.
    pub fn leaf_count(&self) -> usize {
        self.boxes.len()
    }

    /// Leaves the 2:1 balance added (0 for an unbalanced build).
    pub fn leaves_added_by_balance(&self) -> usize {
        self.boxes.len() - self.leaves_before_balance
    }

    /// Depth of the deepest leaf (root = 0).
    pub fn depth(&self) -> u32 {
        self.fine_depth
    }

    /// The leaf records (seed Eq. 3), e.g. for a GPU upload.
    pub fn records(&self) -> &[u32] {
        &self.records
    }

    /// The leaf boxes, indexed by a record's leaf index.
    pub fn boxes(&self) -> &[LeafBox] {
        &self.boxes
    }

    /// Bytes per array: leaf records, boxes, triangle references (copies and ids), cube
    /// map, internal nodes.
    pub fn memory_breakdown(&self) -> [(&'static str, usize); 5] {
        [
            ("leaf records", self.records.len() * 4),
            ("leaf boxes", self.boxes.len() * size_of::<LeafBox>()),
            ("triangle refs", self.tris.len() * size_of::<Triangle>() + self.prim_ids.len() * 4),
            ("cube map", self.cube_map.len() * 4),
            ("internal nodes", self.inner.len() * size_of::<InnerNode>()),
        ]
    }

    fn bytes(&self) -> usize {
        self.memory_breakdown().iter().map(|(_, b)| b).sum()
    }

    fn stats_named(&self) -> AccelStats {
        let mut sizes = crate::LeafSizes::new();
        let mut links = 0usize;
        let mut addr = 0;
        while addr < self.records.len() {
            let n = self.records[addr] as usize;
            sizes.add(n);
            let nc = self.records[addr + 3];
            let l = node::links_before(nc, 6);
            links += l;
            addr += 4 + l;
        }
        let mut extra = vec![
            ("internal nodes".to_string(), self.inner.len().to_string()),
            ("balanced".to_string(), self.params.balance.to_string()),
            ("leaves added by balance".to_string(), self.leaves_added_by_balance().to_string()),
            ("neighbour links per leaf".to_string(), format!("{:.2}", links as f64 / self.boxes.len() as f64)),
            ("faces crossed by point location".to_string(), self.locate_faces.to_string()),
            ("cube map resolution".to_string(), (1u32 << self.cube_depth).to_string()),
        ];
        extra.extend(self.memory_breakdown().iter().map(|(k, b)| (format!("{k} bytes"), b.to_string())));
        AccelStats {
            nodes: self.boxes.len() + self.inner.len(),
            leaves: self.boxes.len(),
            max_depth: self.fine_depth,
            primitive_refs: self.tris.len(),
            leaf_sizes: sizes.finish(),
            sah_cost: None,
            memory_bytes: self.bytes(),
            extra,
        }
    }

    fn rebuild(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        if mesh.triangle_count() != self.mesh_triangles {
            return Err(BuildError::TopologyChanged { built: self.mesh_triangles, given: mesh.triangle_count() });
        }
        // Leaf membership depends on positions: an octree is rebuilt, not refitted.
        *self = Self::build(mesh, &self.params)?;
        Ok(())
    }
}

impl Accel for Octree {
    fn validate(&self, _mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        self.check_invariants().map_err(|e| InvalidStructure::new(self.name(), e))?;
        Ok(self.stats())
    }

    fn name(&self) -> &'static str {
        "octree"
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        self.walk::<_, false>(ray, &mut NoCount)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.walk::<_, true>(ray, &mut NoCount).is_hit()
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        self.walk::<_, false>(ray, counts)
    }

    fn memory_bytes(&self) -> usize {
        self.bytes()
    }

    fn stats(&self) -> AccelStats {
        self.stats_named()
    }

    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        self.rebuild(mesh)
    }

    /// The cube's cells, leaves marked (outline.rs).
    fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        self.outline_cells(max_depth, out);
    }
}

/// The same octree traversed top-down from the root (Revelles et al. 2000), the seed's
/// natural "standard octree" baseline. It reads the internal nodes, the records'
/// triangle runs and the triangles; `memory_bytes` still counts the whole build (links,
/// boxes and cube map included), since both traversals share it.
pub struct OctreeDescent(pub Octree);

impl OctreeDescent {
    /// Builds the octree over `mesh`.
    pub fn build(mesh: &TriangleMesh, params: &OctreeParams) -> Result<Self, BuildError> {
        Octree::build(mesh, params).map(Self)
    }
}

impl Accel for OctreeDescent {
    fn validate(&self, _mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        self.0.check_invariants().map_err(|e| InvalidStructure::new(self.name(), e))?;
        Ok(self.stats())
    }

    fn name(&self) -> &'static str {
        "octree-descent"
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        self.0.descend::<_, false>(ray, &mut NoCount)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.0.descend::<_, true>(ray, &mut NoCount).is_hit()
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        self.0.descend::<_, false>(ray, counts)
    }

    fn memory_bytes(&self) -> usize {
        self.0.bytes()
    }

    fn stats(&self) -> AccelStats {
        self.0.stats_named()
    }

    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        self.0.rebuild(mesh)
    }

    /// The same cells as `octree` (outline.rs).
    fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        self.0.outline_cells(max_depth, out);
    }
}
