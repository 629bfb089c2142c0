//! The interface every acceleration structure implements.

use crate::{BuildError, OutlineBox, TraversalCounts};
use dynray_geom::{Hit, Ray, TriangleMesh, Vec3};

/// A ray-query structure over one triangle mesh.
///
/// Conventions shared by all implementations (see DESIGN.md): hits are those of
/// [`dynray_geom::Triangle::intersect`] with `ray.tmin <= t <= ray.tmax`; the closest hit
/// wins and equal `t` goes to the lower triangle index; triangle indices are the mesh's.
///
/// `Any` lets a caller holding a `&dyn Accel` reach the concrete structure (the GPU
/// backend uploads a [`crate::Bvh`]'s own arrays): `(accel as &dyn Any).downcast_ref::<Bvh>()`.
pub trait Accel: Send + Sync + std::any::Any {
    /// Short name, as `--accel` spells it.
    fn name(&self) -> &'static str;

    /// Closest hit along the ray, or [`Hit::MISS`].
    fn intersect(&self, ray: &Ray) -> Hit;

    /// True when anything lies on the ray within `[tmin, tmax]` (shadow rays).
    fn occluded(&self, ray: &Ray) -> bool;

    /// Closest hits of rays the caller expects to be coherent (camera rays of neighbouring
    /// pixels, in order): `hits[i]` is exactly [`Accel::intersect`] of `rays[i]` — the same
    /// triangle and the same `t`, `u`, `v` bits. Structures with packet traversal
    /// ([`Accel::traces_packets`]) trace groups of consecutive rays together; the default
    /// traces them one at a time. Runs on the calling thread (callers parallelise over
    /// batches, as [`crate::batch::Coherent`] does). Panics unless the lengths match.
    fn intersect_coherent_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        crate::batch::check_batch_lengths(rays.len(), hits.len());
        for (r, h) in rays.iter().zip(hits) {
            *h = self.intersect(r);
        }
    }

    /// [`Accel::occluded`] of rays the caller expects to be coherent (many rays from one
    /// point: towards the samples of a light, over a hemisphere, from a light towards
    /// surface points), exactly, as [`Accel::intersect_coherent_into`] for closest hits:
    /// packets where the structure has them, one ray at a time by default. Panics unless
    /// the lengths match.
    fn occluded_coherent_into(&self, rays: &[Ray], out: &mut [bool]) {
        crate::batch::check_batch_lengths(rays.len(), out.len());
        for (r, o) in rays.iter().zip(out) {
            *o = self.occluded(r);
        }
    }

    /// Closest hits of independent rays (any origins and directions) on the calling
    /// thread: `hits[i]` is exactly [`Accel::intersect`] of `rays[i]`. The default traces
    /// them one at a time; a structure may keep several rays in flight so that their
    /// memory waits overlap. Callers parallelise over batches, as the blanket
    /// [`crate::BatchQuery`] does. Panics unless the lengths match.
    fn intersect_stream_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        crate::batch::check_batch_lengths(rays.len(), hits.len());
        for (r, h) in rays.iter().zip(hits) {
            *h = self.intersect(r);
        }
    }

    /// [`Accel::occluded`] of every ray into `out`, as [`Accel::intersect_stream_into`].
    fn occluded_stream_into(&self, rays: &[Ray], out: &mut [bool]) {
        crate::batch::check_batch_lengths(rays.len(), out.len());
        for (r, o) in rays.iter().zip(out) {
            *o = self.occluded(r);
        }
    }

    /// True when [`Accel::intersect_coherent_into`] traces packets rather than one ray at
    /// a time (the bench measures the packet path only then).
    fn traces_packets(&self) -> bool {
        false
    }

    /// [`Accel::intersect`] that also counts the nodes (or cells) visited and the
    /// triangles tested, for the bench and the heat maps. The plain path pays nothing.
    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit;

    /// Bytes of every array the structure owns (nodes, primitive references, triangles).
    fn memory_bytes(&self) -> usize;

    /// Shape of the structure, for `dynray info` and the bench.
    fn stats(&self) -> AccelStats;

    /// The normalised SAH cost ([`AccelStats::sah_cost`]) alone, where the structure has
    /// one: what the `auto` update policy reads every frame. The default computes every
    /// statistic; structures override it with a cheaper walk.
    fn sah_cost(&self) -> Option<f64> {
        self.stats().sah_cost
    }

    /// Checks every invariant the traversal relies on (structure-specific: children inside
    /// parents, every triangle reachable, indices in range, depth within the traversal
    /// stack, …) and returns [`Accel::stats`]. `mesh` is the mesh of the last build or
    /// update; structures that keep copies of its triangles (bvh, brute) check them
    /// against it. Builds run the same checks under `debug_assertions`; tests always.
    fn validate(&self, mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure>;

    /// Brings the structure up to date with moved vertices (same triangles, same
    /// topology): a refit where the structure allows it, otherwise a rebuild.
    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError>;

    /// [`Accel::update`] for a view from `eye` (the camera position of the new frame).
    /// View-dependent structures (the A-PIT and the A-buffer, which centre their cube on
    /// the observer) move to it; every other structure ignores `eye` (the default).
    fn update_for_eye(&mut self, mesh: &TriangleMesh, eye: Vec3) -> Result<(), BuildError> {
        let _ = eye;
        self.update(mesh)
    }

    /// True when [`Accel::update`] refits (keeps the tree, recomputes its bounds) rather
    /// than rebuilding, so timing a rebuild separately tells something new.
    fn update_refits(&self) -> bool {
        false
    }

    /// The structure's boxes down to depth `max_depth` (the root is depth 0), pushed onto
    /// `out`: node bounds (BVH, wide BVH, BIH), cells (kd-trees, octrees, grid cells that hold
    /// triangles), ... Default: the structure draws no outline (pushes nothing).
    ///
    /// What the live viewer's "boxes" view draws. `out` is appended to, never cleared;
    /// boxes come parents before children. Each structure documents its own choice of
    /// boxes on its `outline.rs`.
    fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        let _ = (max_depth, out);
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
    /// `leaf_sizes[k]` = number of leaves holding `k` triangles; the last bucket counts
    /// `k` or more. Every structure fills it through [`LeafSizes`], so the convention
    /// (bucket count, trimming) is the same for all.
    pub leaf_sizes: Vec<usize>,
    /// Surface-area-heuristic cost of the tree, where defined.
    pub sah_cost: Option<f64>,
    /// Bytes owned, as [`Accel::memory_bytes`].
    pub memory_bytes: usize,
    /// Structure-specific figures, as (name, value) for display.
    pub extra: Vec<(String, String)>,
}

/// Builds [`AccelStats::leaf_sizes`] with the one convention every structure shares:
/// [`LeafSizes::BUCKETS`] buckets, bucket `k` = leaves (or non-empty-or-empty cells, as the
/// structure counts them) with `k` triangles, the last one `BUCKETS - 1` or more; trailing
/// empty buckets are dropped, so the last bucket printed is also "this many or more".
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LeafSizes(Vec<usize>);

impl LeafSizes {
    /// Buckets kept: sizes 0..=31 exactly, 32 and above together (leaf caps of the
    /// presets stay below 32, so real leaves are counted exactly).
    pub const BUCKETS: usize = 33;

    /// An empty histogram.
    pub fn new() -> Self {
        Self(vec![0; Self::BUCKETS])
    }

    /// Counts one leaf of `triangles` triangles.
    #[inline]
    pub fn add(&mut self, triangles: usize) {
        self.0[triangles.min(Self::BUCKETS - 1)] += 1;
    }

    /// The histogram, trailing empty buckets dropped.
    pub fn finish(mut self) -> Vec<usize> {
        let last = self.0.iter().rposition(|&c| c > 0).map_or(0, |i| i + 1);
        self.0.truncate(last);
        self.0
    }
}

impl Default for LeafSizes {
    fn default() -> Self {
        Self::new()
    }
}

impl FromIterator<usize> for LeafSizes {
    fn from_iter<I: IntoIterator<Item = usize>>(sizes: I) -> Self {
        let mut h = Self::new();
        sizes.into_iter().for_each(|n| h.add(n));
        h
    }
}

/// A structure that failed [`Accel::validate`]: which one, and its own description of
/// the first broken invariant (the structure's error type, e.g. [`crate::bvh2::InvalidBvh`],
/// is the source).
#[derive(Debug, thiserror::Error)]
#[error("{structure} failed validation: {source}")]
pub struct InvalidStructure {
    /// [`Accel::name`] of the structure.
    pub structure: &'static str,
    /// What is wrong, with the values involved.
    pub source: Box<dyn std::error::Error + Send + Sync>,
}

impl InvalidStructure {
    /// Wraps a structure's own error (or message).
    pub fn new(structure: &'static str, source: impl Into<Box<dyn std::error::Error + Send + Sync>>) -> Self {
        Self { structure, source: source.into() }
    }
}
