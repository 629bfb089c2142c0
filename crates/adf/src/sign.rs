//! A triangle mesh as a distance source: unsigned distance through the BVH's
//! closest-point query, sign by ray parity voted over several fixed directions.
//!
//! **The sign rule.** A point is inside when a majority of [`SIGN_RAYS`] rays from it
//! (fixed directions, none axis-aligned, so they do not graze the axis-aligned faces
//! scanned meshes often have) cross the surface an odd number of times. On a closed mesh
//! every ray agrees. On a mesh with small holes (the bunny's base) a ray leaving through a
//! hole miscounts, but a hole only captures the rays aimed at it, so the vote stays right
//! everywhere but in a thin region near the hole, where the field then closes the hole
//! with a smooth surface instead of leaving it open. Crossings at a shared edge or vertex
//! are counted once (the walk steps past each hit's `t`).

use crate::field::DistanceSource;
use dynray_accel::{Accel, Bvh, BvhParams};
use dynray_geom::{Ray, TriangleMesh, Vec3};

/// Rays voting on each point's sign (odd, so there is no tie).
pub const SIGN_RAYS: usize = 5;

/// The fixed directions of the vote (normalised at use): spread over the sphere, none
/// along an axis or a diagonal.
const DIRECTIONS: [[f32; 3]; SIGN_RAYS] = [
    [0.3371, 0.8312, 0.4421],
    [-0.7211, 0.2617, 0.6414],
    [0.5309, -0.6102, 0.5880],
    [-0.2876, -0.4119, -0.8648],
    [0.8493, 0.1288, -0.5118],
];

/// Most crossings counted along one ray: past this a ray is taken as inconclusive
/// (counted as "outside") rather than walked forever on a degenerate mesh.
const MAX_CROSSINGS: u32 = 10_000;

/// What the edges of a mesh say about its closedness (a warning, not an error: the sign
/// rule still gives a usable field).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Topology {
    /// Edges used by one triangle only (holes).
    pub boundary_edges: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
}

impl Topology {
    /// Counts the mesh's edges by use (edges compared by vertex index).
    pub fn of(mesh: &TriangleMesh) -> Self {
        let mut edges: Vec<(u32, u32)> = mesh
            .indices
            .iter()
            .flat_map(|&[a, b, c]| [(a, b), (b, c), (c, a)])
            .filter(|(a, b)| a != b)
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        edges.sort_unstable();
        let mut t = Topology::default();
        let mut i = 0;
        while i < edges.len() {
            let j = edges[i..].iter().position(|e| *e != edges[i]).map_or(edges.len(), |k| i + k);
            match j - i {
                1 => t.boundary_edges += 1,
                2 => {}
                _ => t.non_manifold_edges += 1,
            }
            i = j;
        }
        t
    }

    /// True when every edge has exactly two triangles.
    pub fn is_closed(&self) -> bool {
        self.boundary_edges == 0 && self.non_manifold_edges == 0
    }
}

/// A triangle mesh's exact signed distance (module docs for the sign).
pub struct MeshSource {
    bvh: Bvh,
    /// Distance past a hit where the parity walk resumes: relative to the mesh's size, so
    /// it steps over the hit triangle's neighbours at the same `t` but no real layer.
    step: f32,
}

impl MeshSource {
    /// The source of `mesh` (its BVH built here).
    pub fn new(mesh: &TriangleMesh) -> Result<Self, dynray_accel::BuildError> {
        let bvh = Bvh::build(mesh, &BvhParams::default())?;
        let step = mesh.bounds().extent().max_element().max(f32::MIN_POSITIVE) * 1e-6;
        Ok(Self { bvh, step })
    }

    /// Surface crossings along the ray from `p` in direction `dir`.
    fn crossings(&self, p: Vec3, dir: Vec3) -> u32 {
        let mut tmin = 0.0f32;
        let mut n = 0;
        while n < MAX_CROSSINGS {
            let hit = self.bvh.intersect(&Ray::with_interval(p, dir, tmin, f32::INFINITY));
            if !hit.is_hit() {
                return n;
            }
            n += 1;
            tmin = hit.t + self.step.max(hit.t * 1e-6);
        }
        0
    }
}

impl DistanceSource for MeshSource {
    fn unsigned_distance(&self, p: Vec3) -> f32 {
        self.bvh.closest_point(p).map_or(f32::INFINITY, |c| c.dist_sq.sqrt())
    }

    fn inside(&self, p: Vec3) -> bool {
        let (mut odd, mut even) = (0, 0);
        for d in DIRECTIONS {
            if self.crossings(p, Vec3::from_array(d).normalize()) % 2 == 1 {
                odd += 1;
            } else {
                even += 1;
            }
            // Stop once the vote is decided.
            if odd > SIGN_RAYS / 2 || even > SIGN_RAYS / 2 {
                break;
            }
        }
        odd > even
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube as 12 triangles, outward winding.
    pub(crate) fn cube() -> TriangleMesh {
        let p = (0..8).map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32]).collect();
        let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let idx = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
        TriangleMesh::new(p, idx)
    }

    #[test]
    fn cube_signs_and_distances() {
        let s = MeshSource::new(&cube()).unwrap();
        assert!(s.inside(Vec3::splat(0.5)));
        assert!(s.inside(Vec3::new(0.1, 0.9, 0.2)));
        assert!(!s.inside(Vec3::new(1.5, 0.5, 0.5)));
        assert!(!s.inside(Vec3::new(-0.1, 0.5, 0.5)));
        assert!((s.signed_distance(Vec3::splat(0.5)) + 0.5).abs() < 1e-6);
        assert!((s.signed_distance(Vec3::new(2.0, 0.5, 0.5)) - 1.0).abs() < 1e-6);
        assert!(Topology::of(&cube()).is_closed());
    }

    #[test]
    fn a_small_hole_keeps_the_sign_inside() {
        // The cube without one of its 12 triangles: rays through the hole miscount, the
        // vote does not.
        let mut open = cube();
        open.indices.remove(0);
        let t = Topology::of(&open);
        assert_eq!((t.boundary_edges, t.non_manifold_edges), (3, 0));
        let s = MeshSource::new(&open).unwrap();
        for p in [Vec3::splat(0.5), Vec3::new(0.3, 0.3, 0.2), Vec3::new(0.8, 0.7, 0.6)] {
            assert!(s.inside(p), "{p} should be inside");
        }
        assert!(!s.inside(Vec3::new(0.5, 0.5, -0.5)));
    }
}
