//! Phyxels through the volume of a closed mesh: a regular grid over the mesh's bounds at
//! the spacing that gives about the asked-for count, kept where the point is inside. The
//! inside test uses the engine's own ray queries (a BVH over the mesh): a point is inside
//! when most of several rays from it cross the surface an odd number of times, so a ray
//! grazing an edge (counted twice or not at all) or a small hole does not decide alone.

use dynray_accel::{Accel, BuildError, Bvh, BvhParams};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use glam::DVec3;

/// Signed volume enclosed by `mesh` (divergence theorem over its triangles); positive
/// for a closed mesh wound counter-clockwise seen from outside.
pub fn mesh_volume(mesh: &TriangleMesh) -> f64 {
    mesh.indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| DVec3::from(mesh.positions[i as usize].map(f64::from)));
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// Ray directions of the inside test: not along the axes, so that rays from grid points
/// do not run along the edges and faces of boxes.
const DIRECTIONS: [[f32; 3]; 5] = [
    [0.8677, 0.3469, 0.3559],
    [-0.4131, 0.8529, 0.3191],
    [-0.3313, -0.4467, 0.8311],
    [0.2761, -0.8717, -0.4049],
    [-0.7907, 0.1327, -0.5977],
];

/// Most surface crossings counted along one ray before it is given up (then it votes
/// "outside").
const MAX_CROSSINGS: u32 = 256;

/// Inside tests against one closed mesh.
pub struct InsideTest {
    bvh: Bvh,
    /// Step past a hit before looking for the next one, relative to the mesh size.
    eps: f32,
}

impl InsideTest {
    /// Builds the BVH over `mesh`.
    pub fn new(mesh: &TriangleMesh) -> Result<Self, BuildError> {
        let bvh = Bvh::build(mesh, &BvhParams::default())?;
        let eps = mesh.bounds().extent().max_element().max(1e-30) * 1e-6;
        Ok(Self { bvh, eps })
    }

    /// Whether `p` is inside (most of five fixed skew rays cross an odd number of times).
    pub fn contains(&self, p: DVec3) -> bool {
        let o = p.as_vec3();
        let odd = DIRECTIONS.iter().filter(|d| self.crossings(o, Vec3::from_array(**d)) % 2 == 1).count();
        odd * 2 > DIRECTIONS.len()
    }

    fn crossings(&self, o: Vec3, d: Vec3) -> u32 {
        let mut tmin = 0.0f32;
        for n in 0..MAX_CROSSINGS {
            let hit = self.bvh.intersect(&Ray::with_interval(o, d, tmin, f32::INFINITY));
            if !hit.is_hit() {
                return n;
            }
            tmin = hit.t + self.eps;
        }
        0
    }
}

/// Grid points inside `mesh` at spacing `(volume / count)^(1/3)`, and that spacing. The
/// grid is centred in the mesh's bounds; points come in x-fastest grid order.
pub fn sample_inside(mesh: &TriangleMesh, volume: f64, count: u32) -> Result<(Vec<DVec3>, f64), BuildError> {
    let test = InsideTest::new(mesh)?;
    let b = mesh.bounds();
    let (lo, ext) = (b.min.as_dvec3(), b.extent().as_dvec3());
    let mut s = (volume / count.max(1) as f64).cbrt();
    let mut points = Vec::new();
    // A thin or hollow mesh holds fewer points than its volume promises: halve the
    // spacing (a few times at most) until at least half the count is inside.
    for _ in 0..4 {
        points.clear();
        let n = (ext / s).floor().max(DVec3::ZERO);
        let start = lo + (ext - n * s) * 0.5 + DVec3::splat(s * 0.5);
        let (nx, ny, nz) = (n.x as u64 + 1, n.y as u64 + 1, n.z as u64 + 1);
        let candidates: Vec<DVec3> = (0..nz)
            .flat_map(|k| (0..ny).flat_map(move |j| (0..nx).map(move |i| (i, j, k))))
            .map(|(i, j, k)| start + DVec3::new(i as f64, j as f64, k as f64) * s)
            .filter(|p| p.cmple(lo + ext).all())
            .collect();
        use rayon::prelude::*;
        let inside: Vec<bool> = candidates.par_iter().map(|p| test.contains(*p)).collect();
        points.extend(candidates.iter().zip(&inside).filter(|(_, &i)| i).map(|(p, _)| *p));
        if points.len() * 2 >= count as usize {
            break;
        }
        s *= 0.5f64.cbrt();
    }
    Ok((points, s))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_cube() -> TriangleMesh {
        dynray_scene::shapes::cuboid(Vec3::ZERO, Vec3::ONE, Vec3::ZERO)
    }

    #[test]
    fn cube_volume_and_samples() {
        let m = unit_cube();
        let v = mesh_volume(&m);
        assert!((v - 1.0).abs() < 1e-6, "volume {v}");
        let (p, s) = sample_inside(&m, v, 1000).unwrap();
        assert_eq!(p.len(), 1000, "spacing {s}");
        assert!(p.iter().all(|q| q.abs().max_element() < 0.5));
    }

    #[test]
    fn sphere_samples_are_inside() {
        let m = dynray_scene::shapes::uv_sphere(Vec3::ZERO, 1.0, 16, 32);
        let v = mesh_volume(&m);
        let (p, s) = sample_inside(&m, v, 500).unwrap();
        assert!(p.iter().all(|q| q.length() < 1.0));
        // The grid fills the ball: count near volume / s³.
        let expect = v / (s * s * s);
        assert!((p.len() as f64 - expect).abs() < 0.15 * expect, "{} vs {expect}", p.len());
    }
}
