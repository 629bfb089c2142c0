//! The start-up check behind [`crate::GpuContext::exactness`]: the device's BVH kernel
//! against the CPU's brute force on rays where rounding decides the answer.

use crate::{Exactness, GpuBvh, GpuContext};
use dynray_accel::{Accel, Brute, Bvh, BvhParams};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use std::sync::Arc;

/// A bumpy grid of quads sharing edges and vertices, plus slivers and a triangle a
/// million units away, and rays at its vertices, along its edges and through its slivers:
/// any fused multiply-add or inexact division on the device changes some of these hits.
fn hard_case() -> (TriangleMesh, Vec<Ray>) {
    let n = 12u32;
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    let h = |i: u32, j: u32| ((i * 7 + j * 13) % 5) as f32 * 0.037;
    for j in 0..=n {
        for i in 0..=n {
            pos.push([i as f32 * 0.31 + 0.1, h(i, j), j as f32 * 0.29 - 0.2]);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            idx.push([a, a + 1, a + n + 2]);
            idx.push([a, a + n + 2, a + n + 1]);
        }
    }
    let base = pos.len() as u32;
    pos.extend([[1.0e6, 0.5, -1.0], [1.0e6 + 3.0, 0.5, -1.0], [1.0e6, 0.5, 2.0]]);
    pos.extend([[0.0, 2.0, 0.0], [4.0, 2.0 + 1e-6, 0.0], [2.0, 2.0, 1e-5]]);
    idx.push([base, base + 1, base + 2]);
    idx.push([base + 3, base + 4, base + 5]);
    let mesh = TriangleMesh::new(pos.clone(), idx.clone());

    let mut rays = Vec::new();
    let mut seed = 0x9e37_79b9u32;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed as f32 / u32::MAX as f32
    };
    for (k, p) in pos.iter().enumerate() {
        let target = Vec3::from_array(*p);
        let o = Vec3::new(rnd() * 4.0 - 0.5, 3.0 + rnd(), rnd() * 4.0 - 0.5);
        rays.push(Ray::new(o, target - o));
        // Along the grid's edges, and grazing.
        let next = Vec3::from_array(pos[(k + 1) % pos.len()]);
        let mid = target + (next - target) * rnd();
        rays.push(Ray::new(o, mid - o));
        rays.push(Ray::new(Vec3::new(-1.0, mid.y, mid.z), Vec3::new(1.0, 1e-7 * rnd(), 0.0)));
    }
    for _ in 0..512 {
        let o = Vec3::new(1.0e6 + rnd() * 3.0, 3.0, rnd() * 3.0 - 1.0);
        rays.push(Ray::new(o, Vec3::new(rnd() - 0.5, -1.0, rnd() - 0.5)));
    }
    (mesh, rays)
}

pub(crate) fn self_check(ctx: &Arc<GpuContext>) -> Exactness {
    let (mesh, rays) = hard_case();
    let brute = Brute::build(&mesh).expect("a valid mesh");
    let bvh = Bvh::build(&mesh, &BvhParams::default()).expect("a valid mesh");
    // A device error counts every ray as a mismatch: nothing it returned can be trusted.
    let mismatches = match GpuBvh::upload(ctx.clone(), &bvh) {
        Ok(gpu) => {
            let mut hits = vec![dynray_geom::Hit::MISS; rays.len()];
            match gpu.try_intersect_into(&rays, &mut hits) {
                Ok(()) => rays.iter().zip(&hits).filter(|(r, h)| !h.same_as(&brute.intersect(r))).count(),
                Err(_) => rays.len(),
            }
        }
        Err(_) => rays.len(),
    };
    Exactness { rays: rays.len(), mismatches }
}
