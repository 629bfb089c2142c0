//! The f32 kernels (what adapters without 64-bit floats run), forced on whatever device
//! this machine has: the rule of docs/gpu.md — the same triangle as brute force except at
//! ties within rounding of an edge, `t` within 1e-5 relative, any-hit agreeing likewise.
//! On the random set (no rays aimed at edges) that is 2 of 100,000 rays on lavapipe; rays
//! aimed exactly at shared edges and vertices pick the neighbour about 1.5 % of the time.

mod gpu_support;
#[path = "../../accel/tests/support/mod.rs"]
mod support;

use dynray_accel::{BatchQuery, Bvh, BvhParams};
use dynray_gpu::{GpuBvh, GpuOptions, Precision};
use support::*;

#[test]
fn f32_kernels_keep_the_documented_rule_on_the_bunny() {
    let Some(ctx) = gpu_support::device_with(&GpuOptions { force_f32: true, ..Default::default() }) else { return };
    assert_eq!(ctx.precision(), Precision::F32);
    let mesh = bunny();
    let rays = random_rays(&mesh, 100_000, 1);
    let bvh = Bvh::build(&mesh, &BvhParams::default()).unwrap();
    let gpu = GpuBvh::upload(ctx, &bvh).unwrap();
    let want = brute_hits(&mesh, &rays);
    let got = gpu.intersect_batch(&rays);
    let occ = gpu.occluded_batch(&rays);
    let n = rays.len();
    let other = (0..n).filter(|&i| got[i].prim != want[i].prim).count();
    let occ_other = (0..n).filter(|&i| occ[i] != want[i].is_hit()).count();
    let worst = (0..n)
        .filter(|&i| got[i].prim == want[i].prim && want[i].is_hit())
        .map(|i| ((got[i].t - want[i].t) / want[i].t).abs())
        .fold(0.0f32, f32::max);
    eprintln!("f32 kernels: {other} of {n} other triangle, {occ_other} other any-hit, worst relative t {worst:e}");
    assert!(other * 1000 <= n, "{other} of {n} rays hit another triangle");
    assert!(occ_other * 1000 <= n, "{occ_other} of {n} any-hit answers differ");
    assert!(worst < 1e-5, "t differs by {worst:e} relative");
}
