//! The interface every acceleration structure implements.

use crate::{BuildError, TraversalCounts};
use dynray_geom::{Hit, Ray, TriangleMesh};

/// A ray-query structure over one triangle mesh.
///
/// Conventions shared by all implementations (see DESIGN.md): hits are those of
/// [`dynray_geom::Triangle::intersect`] with `ray.tmin <= t <= ray.tmax`; the closest hit
/// wins and equal `t` goes to the lower triangle index; triangle indices are the mesh's.
pub trait Accel: Send + Sync {
    /// Short name, as `--accel` spells it.
    fn name(&self) -> &'static str;

    /// Closest hit along the ray, or [`Hit::MISS`].
    fn intersect(&self, ray: &Ray) -> Hit;

    /// True when anything lies on the ray within `[tmin, tmax]` (shadow rays).
    fn occluded(&self, ray: &Ray) -> bool;

    /// [`Accel::intersect`] that also counts the nodes (or cells) visited and the
    /// triangles tested, for the bench and the heat maps. The plain path pays nothing.
    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit;

    /// Bytes of every array the structure owns (nodes, primitive references, triangles).
    fn memory_bytes(&self) -> usize;

    /// Shape of the structure, for `dynray info` and the bench.
    fn stats(&self) -> AccelStats;

    /// Brings the structure up to date with moved vertices (same triangles, same
    /// topology): a refit where the structure allows it, otherwise a rebuild.
    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError>;

    /// True when [`Accel::update`] refits (keeps the tree, recomputes its bounds) rather
    /// than rebuilding, so timing a rebuild separately tells something new.
    fn update_refits(&self) -> bool {
        false
    }
}

/// Shape and quality figures of a built structure.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AccelStats {
    /// All nodes (or cells), leaves included.
    pub nodes: usize,
    /// Leaves (or non-empty cells).
    pub leaves: usize,
    /// Depth of the deepest leaf (root = 0).
    pub max_depth: u32,
    /// Triangle references stored in leaves (> triangles for splitting structures).
    pub primitive_refs: usize,
    /// `leaf_sizes[k]` = number of leaves holding `k` triangles (last bucket: `k` or more).
    pub leaf_sizes: Vec<usize>,
    /// Surface-area-heuristic cost of the tree, where defined.
    pub sah_cost: Option<f64>,
    /// Bytes owned, as [`Accel::memory_bytes`].
    pub memory_bytes: usize,
    /// Structure-specific figures, as (name, value) for display.
    pub extra: Vec<(String, String)>,
}
