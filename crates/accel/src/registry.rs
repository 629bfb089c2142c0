//! Choosing a structure by name (`--accel NAME`); [`AccelSpec`] adds its parameters,
//! [`crate::descriptor`] holds what is known of each kind.

use crate::{Accel, AccelSpec, BuildError};
use dynray_geom::{TriangleMesh, Vec3};

/// Every structure the engine offers, by the name `--accel` accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AccelKind {
    /// [`Brute`](crate::Brute): every triangle for every ray (the oracle).
    Brute,
    /// `bvh`, the default: [`Wbvh`](crate::Wbvh), the binned-SAH tree (block cost)
    /// collapsed to 4- or 8-wide nodes with 4-triangle SIMD leaf blocks, default
    /// [`WbvhParams`](crate::WbvhParams). The CPU's fastest structure.
    Bvh,
    /// `bvh2`: [`Bvh`](crate::Bvh), seed 003's binary binned-SAH bounding volume
    /// hierarchy: what the GPU backend uploads, and the tree the wide BVH collapses.
    Bvh2,
    /// [`Bih`](crate::Bih): Bounding Interval Hierarchy (seed 000), default [`BihParams`](crate::BihParams).
    Bih,
    /// [`Grid`](crate::Grid): uniform grid (seed 002's baseline), default [`GridParams`](crate::GridParams).
    Grid,
    /// [`KdTree`](crate::KdTree): SAH kd-tree, stack traversal.
    KdTree,
    /// [`KdTreeRopes`](crate::KdTreeRopes): SAH kd-tree, stackless Ropes++ traversal.
    KdTreeRopes,
    /// [`Octree`](crate::Octree): 2:1-balanced leaf octree walked by neighbour links (seed 002).
    Octree,
    /// [`OctreeDescent`](crate::OctreeDescent): the same octree, top-down parametric descent (Revelles 2000).
    OctreeDescent,
    /// [`Apit`](crate::Apit): A-buffers on a cube around the mesh centre with pseudo-interval trees.
    Apit,
    /// [`ABuffer`](crate::ABuffer): the same A-buffers with plain per-pixel lists (seed 004's baseline).
    ABuffer,
}

impl AccelKind {
    /// Whether the structure depends on the observer (the A-PIT and the A-buffer centre
    /// their cube on the eye), so a moving camera alone means an update.
    pub fn is_view_dependent(self) -> bool {
        self.descriptor().view_dependent
    }

    /// All kinds, in the order listings show them.
    pub const ALL: &'static [AccelKind] = &[
        AccelKind::Brute,
        AccelKind::Bvh,
        AccelKind::Bvh2,
        AccelKind::Bih,
        AccelKind::KdTree,
        AccelKind::KdTreeRopes,
        AccelKind::Octree,
        AccelKind::OctreeDescent,
        AccelKind::Grid,
        AccelKind::Apit,
        AccelKind::ABuffer,
    ];

    /// The `--accel` spelling.
    pub fn name(self) -> &'static str {
        self.descriptor().name
    }

    /// Builds the structure over `mesh` with its default parameters (shorthand for
    /// [`AccelSpec::build`] without parameters or eye).
    pub fn build(self, mesh: &TriangleMesh) -> Result<Box<dyn Accel>, BuildError> {
        AccelSpec::new(self).build(mesh, None)
    }

    /// Builds the structure for rendering a view from `eye`. The A-PIT and the A-buffer
    /// centre their cube of A-buffers there, as seed 004 does (primary rays then start at
    /// the observer); every other structure is view-independent and ignores `eye`.
    pub fn build_for_eye(self, mesh: &TriangleMesh, eye: Vec3) -> Result<Box<dyn Accel>, BuildError> {
        AccelSpec::new(self).build(mesh, Some(eye))
    }
}

impl std::str::FromStr for AccelKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        AccelKind::ALL.iter().copied().find(|k| k.name() == s).ok_or_else(|| {
            let names: Vec<_> = AccelKind::ALL.iter().map(|k| k.name()).collect();
            format!("unknown structure `{s}` (expected one of: {})", names.join(", "))
        })
    }
}

impl std::fmt::Display for AccelKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
