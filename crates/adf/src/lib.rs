//! Adaptively sampled distance fields (seed 001, Bastos 2008, chapter 3): a full octree
//! over the unit cube built from a mesh (or any exact distance source), stored as the
//! seed's three tables — a voxel texture of 3×3×3 blocks shared by each group of 8
//! siblings, a cell table H of internal cells only, and a perfect-hash offset table Φ
//! with the seed's per-entry modulus `w` — located without a stack or pointers, and
//! sphere traced as a [`dynray_render::Geometry`].
//!
//! Files, one concept each: `field.rs` (distance sources), `sign.rs` (a mesh as a source:
//! closest point and the ray-parity sign vote), `build.rs` (Frisken subdivision),
//! `crack.rs` (the T-junction rule and the Lipschitz bound), `blocks.rs` (voxel texture),
//! `hash.rs` (H and Φ), `locate.rs` (linear, coherent linear and binary level search),
//! `reconstruct.rs` (trilinear lookup and gradient), `trace.rs` (sphere tracing),
//! `file.rs` (the `.adf` format), `stats.rs` (memory figures). See docs/adf.md.
//!
//! ```
//! use dynray_adf::{Adf, BuildParams, Search, SphereSource};
//! use dynray_geom::{Aabb, Vec3};
//!
//! let sphere = SphereSource { centre: Vec3::ZERO, radius: 1.0 };
//! let bounds = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
//! let adf = Adf::build(&sphere, bounds, &BuildParams { max_level: 6, epsilon: 1e-3 }, &|_, _| {})?;
//! // Inside the cube around the bounds (1/16 margin): 0.05 outside the sphere.
//! let d = adf.distance(Vec3::new(0.0, 0.0, 1.05), Search::CoherentLinear).unwrap();
//! assert!((d - 0.05).abs() < 0.01);
//! # Ok::<(), dynray_adf::AdfError>(())
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod blocks;
mod build;
mod crack;
mod error;
mod field;
mod file;
mod geometry;
mod hash;
mod locate;
mod reconstruct;
mod sign;
mod stats;
mod trace;

pub use blocks::VoxelTexture;
pub use error::{AdfError, FileError};
pub use field::{DistanceSource, SphereSource};
pub use file::{FORMAT_VERSION, MAGIC};
pub use geometry::AdfGeometry;
pub use hash::{key_high_id, key_id, key_of_id, CellEntry, HashVariant, PerfectHash, PhiEntry};
pub use locate::{Located, Search};
pub use sign::{MeshSource, Topology, SIGN_RAYS};
pub use stats::MemoryFigures;
pub use trace::{MarchStats, MAX_MARCH_STEPS};

use dynray_geom::{Aabb, TriangleMesh, Vec3};
use std::time::Instant;

/// The deepest tree level the format addresses. Up to level 10 the keys of internal
/// cells (components below 1024) fit the seed's 4-byte identifiers of H; deeper trees
/// add a second identifier word per slot (`hash.rs`). 16 keeps a finest cell 256 f32
/// ulps wide at the cube's far side.
pub const MAX_LEVEL: u32 = 16;

/// Build parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildParams {
    /// Deepest level, `1..=MAX_LEVEL` (cells of edge `cube / 2^max_level`; near the
    /// surface every cell reaches it). 8 is a good default for scanned models.
    pub max_level: u32,
    /// Tolerance of the subdivision test, as a fraction of the cube's edge (scale-free):
    /// `1e-4 ..= 1e-2` is useful.
    pub epsilon: f32,
}

impl Default for BuildParams {
    fn default() -> Self {
        Self { max_level: 8, epsilon: 1e-3 }
    }
}

/// The cube the octree's unit cube maps to, in world space: the source's box, centred,
/// grown to a cube with 1/16 of its edge as margin on every side (so the field is
/// positive on the cube's boundary and a tracer enters it in free space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cube {
    /// World position of the unit cube's origin.
    pub origin: Vec3,
    /// Edge length in world units.
    pub size: f32,
}

impl Cube {
    /// The cube around `b` (non-empty, finite).
    pub fn around(b: &Aabb) -> Self {
        let size = (b.extent().max_element() * 1.125).max(1e-6);
        Self { origin: b.center() - Vec3::splat(size * 0.5), size }
    }

    /// World position of vertex `v` of the grid of resolution `2^res`.
    pub(crate) fn world(&self, v: [u32; 3], res: u32) -> Vec3 {
        let s = self.size as f64 / (1u64 << res) as f64;
        let o = self.origin.to_array();
        Vec3::new(
            (o[0] as f64 + v[0] as f64 * s) as f32,
            (o[1] as f64 + v[1] as f64 * s) as f32,
            (o[2] as f64 + v[2] as f64 * s) as f32,
        )
    }

    /// The cube as a box.
    pub fn bounds(&self) -> Aabb {
        Aabb::new(self.origin, self.origin + Vec3::splat(self.size))
    }
}

/// A camera to remember with the field, so `render FILE.adf` frames the view its source
/// mesh had.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Eye position.
    pub position: Vec3,
    /// Point looked at.
    pub look_at: Vec3,
    /// Up direction.
    pub up: Vec3,
    /// Perspective: vertical field of view in degrees, or parallel: the view height.
    pub projection: ViewProjection,
}

impl View {
    /// The view of a scene camera (its clip planes are not kept: a field's source is a
    /// mesh file, whose default view has none).
    pub fn of_camera(c: &dynray_scene::Camera) -> Self {
        let projection = match c.projection {
            dynray_scene::Projection::Perspective { fov_y_deg } => ViewProjection::Perspective(fov_y_deg),
            dynray_scene::Projection::Parallel { height } => ViewProjection::Parallel(height),
        };
        View { position: c.position, look_at: c.look_at, up: c.up, projection }
    }

    /// The scene camera this view stands for, without clip planes.
    pub fn camera(&self) -> dynray_scene::Camera {
        dynray_scene::Camera {
            position: self.position,
            look_at: self.look_at,
            up: self.up,
            projection: match self.projection {
                ViewProjection::Perspective(fov_y_deg) => dynray_scene::Projection::Perspective { fov_y_deg },
                ViewProjection::Parallel(height) => dynray_scene::Projection::Parallel { height },
            },
            clip: dynray_scene::Clip::NONE,
        }
    }
}

/// [`View`]'s projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ViewProjection {
    /// Vertical field of view, degrees.
    Perspective(f32),
    /// Height of the view window, world units.
    Parallel(f32),
}

/// What the build and the file record besides the tables.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct BuildInfo {
    /// Internal cells per level `0..=max_level`.
    pub internal_per_level: Vec<u64>,
    /// Leaves per level `0..=max_level`.
    pub leaves_per_level: Vec<u64>,
    /// Subdivision, T-junction rule and packing, milliseconds.
    pub build_ms: f32,
    /// Perfect-hash generation, milliseconds.
    pub hash_ms: f32,
    /// Samples the T-junction rule replaced.
    pub constrained_samples: u64,
    /// Triangles of the source mesh (0 for an analytic source).
    pub triangles: u64,
    /// The source's camera, when it had one.
    pub view: Option<View>,
}

/// An adaptively sampled distance field in the seed's GPU layout.
#[derive(Clone, Debug, PartialEq)]
pub struct Adf {
    pub(crate) max_level: u32,
    pub(crate) cube: Cube,
    /// The source's own box (world space).
    pub(crate) source_bounds: Aabb,
    /// Build tolerance, world units.
    pub(crate) epsilon: f32,
    /// Lipschitz bound of the reconstructed field (`crack.rs`).
    pub(crate) lipschitz: f32,
    /// Per internal cell (block order), the Lipschitz bound inside it: the sphere
    /// tracer's local step (`trace.rs`).
    pub(crate) cell_lipschitz: Vec<f32>,
    pub(crate) voxels: VoxelTexture,
    pub(crate) hash: PerfectHash,
    pub(crate) info: BuildInfo,
}

impl Adf {
    /// Builds the field of `src` over the cube around `bounds` (the source's box).
    /// `progress(levels_done, max_level)` reports the subdivision.
    pub fn build(
        src: &dyn DistanceSource,
        bounds: Aabb,
        params: &BuildParams,
        progress: &(dyn Fn(u32, u32) + Sync),
    ) -> Result<Self, AdfError> {
        if !(1..=MAX_LEVEL).contains(&params.max_level) {
            return Err(AdfError::LevelOutOfRange { level: params.max_level, max: MAX_LEVEL });
        }
        if !(params.epsilon.is_finite() && params.epsilon > 0.0) {
            return Err(AdfError::BadEpsilon(params.epsilon));
        }
        if bounds.is_empty() || !bounds.min.is_finite() || !bounds.max.is_finite() {
            return Err(AdfError::BadBounds(bounds));
        }
        Self::build_with(src, bounds, params, progress, true)
    }

    /// [`Adf::build`], the T-junction rule optional (tests show the cracks without it).
    pub(crate) fn build_with(
        src: &dyn DistanceSource,
        bounds: Aabb,
        params: &BuildParams,
        progress: &(dyn Fn(u32, u32) + Sync),
        t_junction_rule: bool,
    ) -> Result<Self, AdfError> {
        let t0 = Instant::now();
        let cube = Cube::around(&bounds);
        let eps = params.epsilon * cube.size;
        let mut tree = build::build_tree(src, &cube, params.max_level, eps, progress);
        if tree.cells.len() > u32::MAX as usize / 2 {
            return Err(AdfError::TooManyCells { cells: tree.cells.len() });
        }
        let map = crack::cell_map(&tree);
        let constrained = if t_junction_rule { crack::constrain_t_junctions(&mut tree, &map) } else { 0 };
        let cell_lipschitz = crack::lipschitz(&tree, &map, cube.size);
        let lipschitz = cell_lipschitz.first().copied().unwrap_or(1.0);
        let voxels = VoxelTexture::pack(&tree.blocks);
        let build_ms = t0.elapsed().as_secs_f32() * 1e3;

        let t1 = Instant::now();
        let keys: Vec<[u32; 3]> = tree.cells.iter().map(|c| c.index.map(|i| (1 << c.level) + i)).collect();
        let hash = PerfectHash::generate(&keys, HashVariant::Modified)?;
        let hash_ms = t1.elapsed().as_secs_f32() * 1e3;
        Ok(Self {
            max_level: params.max_level,
            cube,
            source_bounds: bounds,
            epsilon: eps,
            lipschitz,
            cell_lipschitz,
            voxels,
            hash,
            info: BuildInfo {
                internal_per_level: tree.internal_per_level,
                leaves_per_level: tree.leaves_per_level,
                build_ms,
                hash_ms,
                constrained_samples: constrained as u64,
                triangles: 0,
                view: None,
            },
        })
    }

    /// Builds the field of a triangle mesh (signed by the vote of `sign.rs`), and says
    /// how closed the mesh is (an open or non-manifold mesh still builds).
    pub fn from_mesh(
        mesh: &TriangleMesh,
        params: &BuildParams,
        progress: &(dyn Fn(u32, u32) + Sync),
    ) -> Result<(Self, Topology), AdfError> {
        if mesh.triangle_count() == 0 {
            return Err(AdfError::EmptyMesh);
        }
        let topology = Topology::of(mesh);
        let src = MeshSource::new(mesh)?;
        let t0 = Instant::now();
        let mut adf = Self::build(&src, mesh.bounds(), params, progress)?;
        // The BVH build counts as build time too.
        adf.info.build_ms = adf.info.build_ms.max(t0.elapsed().as_secs_f32() * 1e3 - adf.info.hash_ms);
        adf.info.triangles = mesh.triangle_count() as u64;
        Ok((adf, topology))
    }

    /// Remembers the camera the source was seen through.
    pub fn set_view(&mut self, view: Option<View>) {
        self.info.view = view;
    }

    /// Deepest level.
    pub fn max_level(&self) -> u32 {
        self.max_level
    }

    /// The world cube of the octree.
    pub fn cube(&self) -> Cube {
        self.cube
    }

    /// The source's own box.
    pub fn source_bounds(&self) -> Aabb {
        self.source_bounds
    }

    /// The build tolerance in world units.
    pub fn epsilon(&self) -> f32 {
        self.epsilon
    }

    /// The Lipschitz bound of the reconstructed field, over the whole cube.
    pub fn lipschitz(&self) -> f32 {
        self.lipschitz
    }

    /// The Lipschitz bound inside each internal cell (block order).
    pub fn cell_lipschitz(&self) -> &[f32] {
        &self.cell_lipschitz
    }

    /// What the build recorded.
    pub fn info(&self) -> &BuildInfo {
        &self.info
    }

    /// The voxel texture.
    pub fn voxels(&self) -> &VoxelTexture {
        &self.voxels
    }

    /// H and Φ.
    pub fn hash(&self) -> &PerfectHash {
        &self.hash
    }

    /// Internal cells (the entries of H).
    pub fn internal_cells(&self) -> u64 {
        self.info.internal_per_level.iter().sum()
    }

    /// Every cell of the full tree (internal and leaves).
    pub fn cells(&self) -> u64 {
        self.internal_cells() + self.info.leaves_per_level.iter().sum::<u64>()
    }
}

#[cfg(test)]
mod tests;
