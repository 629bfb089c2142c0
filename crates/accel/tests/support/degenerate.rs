//! Degenerate scenes shared by the structure tests, and rays that reach them where
//! `random_rays` cannot (a box of zero size). Each test asserts its own structure's bounds
//! on top of the oracle check.

use dynray_geom::{Ray, TriangleMesh, Vec3};
use rand::{rngs::SmallRng, Rng, SeedableRng};

/// Rays from a sphere around the box's centre aimed at random points of the box, and
/// (every fourth) axis-parallel ones through it: usable for a box of zero size.
pub fn rays_at(lo: Vec3, hi: Vec3, n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = SmallRng::seed_from_u64(seed);
    let c = (lo + hi) * 0.5;
    let r = (hi - lo).length().max(1.0) * 2.0;
    (0..n)
        .map(|i| {
            let target = Vec3::new(rng.gen::<f32>(), rng.gen::<f32>(), rng.gen::<f32>()) * (hi - lo) + lo;
            if i % 4 == 3 {
                let mut d = Vec3::ZERO;
                d[i % 3] = 1.0;
                Ray::new(target - d * r, d)
            } else {
                let o = c + Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)) * r;
                Ray::new(o, target - o)
            }
        })
        .collect()
}

/// A jittered 100×100 sheet of quads (20,000 triangles), all in the plane y = 0.5.
pub fn coplanar_sheet() -> TriangleMesh {
    let mut rng = SmallRng::seed_from_u64(5);
    let n = 100;
    let mut pos = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            pos.push([i as f32 + rng.gen_range(-0.3..0.3), 0.5, j as f32 + rng.gen_range(-0.3..0.3)]);
        }
    }
    let mut idx = Vec::new();
    let v = |i: u32, j: u32| i * (n + 1) + j;
    for i in 0..n {
        for j in 0..n {
            idx.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            idx.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    TriangleMesh::new(pos, idx)
}

/// 20k small triangles strung along x over [0, 1e6], 1 unit thick, plus one 1000 long
/// across them. (Not 1e6 long: at such coordinates `Triangle::intersect` itself reports
/// hits far outside the triangle's box, which no box- or plane-culling structure can
/// reproduce; see dynray-geom's `hits_stay_inside_the_triangle_box_at_large_coordinates`.)
pub fn million_to_one_strip() -> TriangleMesh {
    let mut rng = SmallRng::seed_from_u64(61);
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for k in 0..20_000u32 {
        let x = rng.gen_range(0.0..1.0e6f32);
        let (y, z) = (rng.gen_range(0.0..1.0f32), rng.gen_range(0.0..1.0f32));
        pos.extend([[x, y, z], [x + 0.5, y, z + 0.3], [x + 0.2, y + 0.6, z]]);
        idx.push([3 * k, 3 * k + 1, 3 * k + 2]);
    }
    let base = pos.len() as u32;
    pos.extend([[0.0, 0.5, -1.0], [1.0e3, 0.5, -1.0], [0.0, 0.5, 2.0]]);
    idx.push([base, base + 1, base + 2]);
    TriangleMesh::new(pos, idx)
}
