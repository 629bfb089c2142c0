//! Closest-point query: the point of the mesh nearest to a query point, through the BVH
//! (nearest box first, boxes farther than the best distance culled). Distance fields
//! (`dynray-adf`) sample it at every voxel.

use super::Bvh;
use dynray_geom::{Aabb, Triangle, Vec3};

/// The point of a mesh nearest to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPoint {
    /// The nearest point on the surface.
    pub point: Vec3,
    /// Squared distance from the query point to `point`.
    pub dist_sq: f32,
    /// Mesh index of the triangle `point` lies on (ties go to the lower index).
    pub prim: u32,
}

impl Bvh {
    /// The surface point nearest to `p`, or `None` for a tree without triangles. Equal
    /// distances go to the lower triangle index, so the answer is brute force's
    /// ([`closest_point_brute`]).
    pub fn closest_point(&self, p: Vec3) -> Option<ClosestPoint> {
        let nodes = self.nodes();
        let root = nodes.first()?;
        let mut best: Option<ClosestPoint> = None;
        let mut stack: Vec<(u32, f32)> = Vec::with_capacity(64);
        stack.push((0, box_dist_sq(&root.bounds(), p)));
        while let Some((i, d)) = stack.pop() {
            if best.is_some_and(|b| d > b.dist_sq) {
                continue;
            }
            let node = &nodes[i as usize];
            if node.is_leaf() {
                let range = node.index as usize..(node.index + node.count) as usize;
                for (tri, &id) in self.triangles()[range.clone()].iter().zip(&self.triangle_ids()[range]) {
                    let q = closest_on_triangle(tri, p);
                    let d2 = (q - p).length_squared();
                    if best.is_none_or(|b| d2 < b.dist_sq || (d2 == b.dist_sq && id < b.prim)) {
                        best = Some(ClosestPoint { point: q, dist_sq: d2, prim: id });
                    }
                }
            } else {
                let (l, r) = (node.index, node.index + 1);
                let dl = box_dist_sq(&nodes[l as usize].bounds(), p);
                let dr = box_dist_sq(&nodes[r as usize].bounds(), p);
                // Far child pushed first, so the near one is searched first and culls more.
                if dl <= dr {
                    stack.extend([(r, dr), (l, dl)]);
                } else {
                    stack.extend([(l, dl), (r, dr)]);
                }
            }
        }
        best
    }
}

/// The oracle of [`Bvh::closest_point`]: every triangle of `tris` (mesh order) scanned.
pub fn closest_point_brute(tris: &[Triangle], p: Vec3) -> Option<ClosestPoint> {
    let mut best: Option<ClosestPoint> = None;
    for (id, tri) in tris.iter().enumerate() {
        let q = closest_on_triangle(tri, p);
        let d2 = (q - p).length_squared();
        if best.is_none_or(|b| d2 < b.dist_sq) {
            best = Some(ClosestPoint { point: q, dist_sq: d2, prim: id as u32 });
        }
    }
    best
}

/// Squared distance from `p` to the box (0 inside).
fn box_dist_sq(b: &Aabb, p: Vec3) -> f32 {
    let d = (b.min - p).max(Vec3::ZERO).max(p - b.max);
    d.length_squared()
}

/// The point of triangle `t` nearest to `p` (Ericson, Real-Time Collision Detection
/// §5.1.5: Voronoi regions of vertices, then edges, then the face). A degenerate
/// triangle falls in a vertex or edge region, so the answer stays finite.
pub fn closest_on_triangle(t: &Triangle, p: Vec3) -> Vec3 {
    let (a, b, c) = (t.p0, t.p1, t.p2);
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if denom == 0.0 || !denom.is_finite() {
        // A degenerate face that slipped past the region tests: nearest vertex.
        return [a, b, c]
            .into_iter()
            .min_by(|x, y| (*x - p).length_squared().total_cmp(&(*y - p).length_squared()))
            .unwrap_or(a);
    }
    let (v, w) = (vb / denom, vc / denom);
    a + ab * v + ac * w
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BvhParams;
    use dynray_geom::TriangleMesh;
    use rand::{rngs::SmallRng, Rng, SeedableRng};

    fn random_mesh(rng: &mut SmallRng, n: usize) -> TriangleMesh {
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        for i in 0..n as u32 {
            let c = Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
            for _ in 0..3 {
                let d = Vec3::new(rng.gen_range(-0.2..0.2), rng.gen_range(-0.2..0.2), rng.gen_range(-0.2..0.2));
                positions.push((c + d).to_array());
            }
            indices.push([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        TriangleMesh::new(positions, indices)
    }

    #[test]
    fn closest_point_matches_brute_force() {
        let mut rng = SmallRng::seed_from_u64(7);
        let mesh = random_mesh(&mut rng, 500);
        let bvh = Bvh::build(&mesh, &BvhParams::default()).unwrap();
        let tris: Vec<Triangle> = (0..mesh.triangle_count()).map(|i| mesh.triangle(i)).collect();
        for _ in 0..2000 {
            let p = Vec3::new(rng.gen_range(-2.0..2.0), rng.gen_range(-2.0..2.0), rng.gen_range(-2.0..2.0));
            let got = bvh.closest_point(p).unwrap();
            let want = closest_point_brute(&tris, p).unwrap();
            assert_eq!(got, want, "at {p}");
        }
    }

    #[test]
    fn closest_on_triangle_regions() {
        let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        // Face, vertex, edge and vertex regions, then the hypotenuse (face points go
        // through barycentric division: equal to rounding).
        let near = |p: Vec3, want: Vec3| {
            let got = closest_on_triangle(&t, p);
            assert!((got - want).length() < 1e-6, "{p}: {got}, expected {want}");
        };
        near(Vec3::new(0.2, 0.2, 3.0), Vec3::new(0.2, 0.2, 0.0));
        assert_eq!(closest_on_triangle(&t, Vec3::new(-1.0, -1.0, 0.0)), Vec3::ZERO);
        near(Vec3::new(0.5, -1.0, 0.0), Vec3::new(0.5, 0.0, 0.0));
        assert_eq!(closest_on_triangle(&t, Vec3::new(2.0, 0.0, 1.0)), Vec3::X);
        near(Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.5, 0.5, 0.0));
        // Degenerate (collinear) triangle: still a point on it.
        let d = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::X * 2.0);
        let q = closest_on_triangle(&d, Vec3::new(1.5, 1.0, 0.0));
        assert!(q.is_finite() && q.y == 0.0 && (0.0..=2.0).contains(&q.x), "{q}");
    }
}
