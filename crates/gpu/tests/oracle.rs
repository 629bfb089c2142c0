//! GPU BVH traversal against the CPU's brute force: the same hit (triangle, `t`, `u`, `v`
//! bits) on real models and adversarial rays, closest and any-hit, where the device has
//! 64-bit floats; on an f32-only device the documented rule instead (docs/gpu.md).

mod gpu_support;
#[path = "../../accel/tests/support/mod.rs"]
mod support;

use dynray_accel::{BatchQuery, Bvh, BvhParams};
use dynray_geom::{Hit, Ray, TriangleMesh};
use dynray_gpu::{GpuBvh, Precision};
use support::*;

fn check(mesh: &TriangleMesh, rays: &[Ray], label: &str) {
    let Some(ctx) = gpu_support::device() else { return };
    let bvh = Bvh::build(mesh, &BvhParams::default()).unwrap();
    let gpu = GpuBvh::upload(ctx.clone(), &bvh).unwrap();
    let want = brute_hits(mesh, rays);
    let got = gpu.intersect_batch(rays);
    let occ = gpu.occluded_batch(rays);
    let bits = |h: &Hit| (h.prim, h.t.to_bits(), h.u.to_bits(), h.v.to_bits());
    match ctx.precision() {
        Precision::F64 => {
            let bad: Vec<usize> = (0..rays.len()).filter(|&i| bits(&got[i]) != bits(&want[i])).collect();
            let bad_occ: Vec<usize> = (0..rays.len()).filter(|&i| occ[i] != want[i].is_hit()).collect();
            let show = |v: &[usize]| {
                v.iter()
                    .take(4)
                    .map(|&i| format!("\n  ray {i} {:?}: gpu {:?}, brute {:?}", rays[i], got[i], want[i]))
                    .collect::<String>()
            };
            assert!(
                bad.is_empty() && bad_occ.is_empty(),
                "{label} on {}: {} of {} closest hits and {} any-hits differ from brute force{}{}",
                ctx.adapter().name,
                bad.len(),
                rays.len(),
                bad_occ.len(),
                show(&bad),
                show(&bad_occ)
            );
        }
        Precision::F32 => {
            // The f32 rule (docs/gpu.md): the same triangle but for edge ties, t close.
            let same = (0..rays.len()).filter(|&i| got[i].prim == want[i].prim).count();
            assert!(same as f64 >= 0.999 * rays.len() as f64, "{label}: only {same} of {} same triangle", rays.len());
            for i in 0..rays.len() {
                if got[i].prim == want[i].prim && want[i].is_hit() {
                    let rel = ((got[i].t - want[i].t) / want[i].t).abs();
                    assert!(rel < 1e-4, "{label}: ray {i} t {} vs {}", got[i].t, want[i].t);
                }
            }
        }
    }
    assert!(want.iter().any(|h| h.is_hit()) && want.iter().any(|h| !h.is_hit()), "{label}: a set that tests nothing");
}

#[test]
fn bunny_random_and_adversarial_rays_match_brute_force() {
    let mesh = bunny();
    // The set every CPU structure is checked on: its brute-force answers are cached.
    check(&mesh, &bunny_rays(&mesh), "bunny");
}

#[test]
fn dragon_202k_matches_brute_force() {
    let mesh = dragon_res2();
    // Not yet the far rays (support::far_rays, 10^5–10^10 units away): on lavapipe the
    // device BVH misses about 550 of them that the CPU's BVH finds (open: issue 44).
    check(&mesh, &dragon_near_rays(&mesh), "dragon res2");
}

#[test]
fn degenerate_meshes_match_brute_force() {
    for (name, mesh) in
        [("coplanar sheet", degenerate::coplanar_sheet()), ("1e6:1 strip", degenerate::million_to_one_strip())]
    {
        let b = mesh.bounds();
        let mut rays = degenerate::rays_at(b.min, b.max, 4_000, 9);
        rays.extend(random_rays(&mesh, 4_000, 10));
        check(&mesh, &rays, name);
    }
}

#[test]
fn the_start_up_self_check_passes() {
    let Some(ctx) = gpu_support::device() else { return };
    let e = ctx.exactness();
    assert!(e.rays > 1000);
    if ctx.precision() == Precision::F64 {
        assert!(e.is_exact(), "{} of {} self-check rays differ on {}", e.mismatches, e.rays, ctx.adapter().name);
    }
}

#[test]
fn empty_and_chunked_batches_keep_ray_order() {
    let Some(ctx) = gpu_support::device() else { return };
    let mesh = bunny();
    let bvh = Bvh::build(&mesh, &BvhParams::default()).unwrap();
    let gpu = GpuBvh::upload(ctx, &bvh).unwrap();
    assert!(gpu.intersect_batch(&[]).is_empty());
    let rays = random_rays(&mesh, 3_001, 77);
    let cpu = bvh.intersect_batch(&rays);
    let got = gpu.intersect_batch(&rays);
    assert!(got.iter().zip(&cpu).all(|(a, b)| a.prim == b.prim));
}
