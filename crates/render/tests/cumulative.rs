//! Seed 004's cumulative integrator against the recursive Whitted tracer it unrolls: equal
//! images when every bounce is expanded, convergence to Whitted's image over passes when
//! paths choose, and images that depend neither on threads nor on tiles.

use dynray_accel::{Bvh, BvhParams};
use dynray_render::{
    render, render_with, Cumulative, Film, IntegratorKind, IntegratorParams, RenderOptions, RenderStats,
    SceneIntersector,
};
use dynray_scene::{load_file, Frame};
use std::path::Path;

/// examples/whitted.scn (a mirror sphere, a glass sphere, a checkerboard;
/// `max_recursion_level 8`) at `w × h`.
fn whitted_scene(w: u32, h: u32) -> Frame {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/whitted.scn");
    let mut frame = load_file(&path).unwrap().frame(0.0);
    frame.settings.width = w;
    frame.settings.height = h;
    frame
}

fn bvh(frame: &Frame) -> Bvh {
    Bvh::build(&frame.mesh, &BvhParams::default()).unwrap()
}

fn run(frame: &Frame, accel: &Bvh, integrator: IntegratorKind, k: u32, passes: u32, spp: u32) -> (Film, RenderStats) {
    let params = IntegratorParams { branch_depth: k };
    render(frame, accel, &RenderOptions { integrator, params, passes, spp, seed: 7, ..Default::default() })
}

/// Root-mean-square difference over every channel of every pixel.
fn rmse(a: &Film, b: &Film) -> f64 {
    let (pa, pb) = (a.pixels(), b.pixels());
    let sq: f64 = pa.iter().zip(&pb).flat_map(|(x, y)| (*x - *y).to_array()).map(|d| (d as f64) * (d as f64)).sum();
    (sq / (3 * pa.len()) as f64).sqrt()
}

/// Largest per-channel difference relative to the larger magnitude (floored at 1e-3,
/// where absolute and relative differences meet for display values).
fn max_rel_diff(a: &Film, b: &Film) -> f32 {
    a.pixels()
        .iter()
        .zip(&b.pixels())
        .flat_map(|(x, y)| x.to_array().into_iter().zip(y.to_array()))
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()).max(1e-3))
        .fold(0.0, f32::max)
}

/// With `--branch-depth ≥ max_recursion_level − 1` no choice is ever made: the paths are
/// Whitted's ray tree. The sum is taken in another order (`I₀ + R₁I₁ + (R₁R₂)I₂` against
/// Whitted's nested `I₀ + R₁(I₁ + R₂I₂)`), so pixels agree to a few f32 ulps per term,
/// not bit for bit: 2e-6 relative bounds 8 levels × up to 2^7 terms of positive
/// radiance (each reassociation errs by ≤ 2^-24 of the sum). Ray counts are equal.
#[test]
fn full_branch_depth_is_whitted() {
    let frame = whitted_scene(96, 72);
    let accel = bvh(&frame);
    let (want, ws) = run(&frame, &accel, IntegratorKind::Whitted, 0, 1, 1);
    for k in [7, 8, 30] {
        let (got, cs) = run(&frame, &accel, IntegratorKind::Cumulative, k, 1, 1);
        let d = max_rel_diff(&got, &want);
        eprintln!("K = {k}: largest relative difference to Whitted {d:e}, RMSE {:e}", rmse(&got, &want));
        assert!(d <= 2e-6, "K = {k}: largest relative difference {d:e}");
        assert_eq!(cs, ws, "K = {k}: ray counts");
        assert_eq!(got.to_srgb8().len(), want.to_srgb8().len());
    }
    assert!(ws.secondary_rays > 2_000, "the scene reflects and refracts: {ws:?}");
}

/// One level short of full expansion, the last hits of the glass choose: the image is no
/// longer Whitted's (the choice is exercised), but still close to it.
#[test]
fn branch_depth_below_the_limit_chooses() {
    let frame = whitted_scene(96, 72);
    let accel = bvh(&frame);
    let (want, ws) = run(&frame, &accel, IntegratorKind::Whitted, 0, 1, 1);
    let (got, cs) = run(&frame, &accel, IntegratorKind::Cumulative, 0, 1, 1);
    assert!(max_rel_diff(&got, &want) > 1e-2, "K = 0 must choose somewhere");
    assert!(cs.secondary_rays < ws.secondary_rays, "choosing traces fewer rays: {cs:?} vs {ws:?}");
}

/// K = 0: the error against Whitted's image falls as passes accumulate, as 1/√N for an
/// unbiased estimator (a biased one would level off). Deterministic seeds, and the bound
/// is loose (0.6 per 4× passes where 0.5 is expected, and 0.3 over 16×) so it cannot
/// flake yet fails for an estimator that does not converge to Whitted's image.
#[test]
fn passes_converge_to_whitted() {
    let frame = whitted_scene(64, 48);
    let accel = bvh(&frame);
    let (want, _) = run(&frame, &accel, IntegratorKind::Whitted, 0, 1, 1);
    let scene = SceneIntersector::triangles(&frame, &accel);
    let cumulative = Cumulative::new(&frame, &scene, 0);
    let errors = std::sync::Mutex::new(Vec::new());
    let record = |pass: u32, film: &Film| {
        if [1, 4, 16].contains(&pass) {
            errors.lock().unwrap().push(rmse(film, &want));
        }
    };
    let options = RenderOptions { passes: 16, seed: 3, pass_done: Some(&record), ..Default::default() };
    let (film, stats) = render_with(&frame, &cumulative, &options);
    let e = errors.into_inner().unwrap();
    assert_eq!(e.len(), 3);
    eprintln!("K = 0, RMSE against Whitted after 1, 4, 16 passes: {e:?}");
    assert!(e[0] > 1e-3, "one pass must be noisy: {e:?}");
    assert!(e[1] < 0.6 * e[0] && e[2] < 0.6 * e[1] && e[2] < 0.3 * e[0], "RMSE by passes 1, 4, 16: {e:?}");
    assert_eq!(film.weight(0, 0), Some(16.0));
    assert_eq!(stats.primary_rays, 64 * 48 * 16);
}

/// Neither the thread count nor the tile size (hence the batches the render loop hands
/// over) changes a bit of the image, with choices, several samples and passes.
#[test]
fn image_is_independent_of_threads_and_tiles() {
    let frame = whitted_scene(40, 30);
    let accel = bvh(&frame);
    let go = |threads: usize, tile_size: u32| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let options = RenderOptions {
            integrator: IntegratorKind::Cumulative,
            params: IntegratorParams { branch_depth: 1 },
            tile_size,
            spp: 3,
            passes: 2,
            ..Default::default()
        };
        let (film, stats) = pool.install(|| render(&frame, &accel, &options));
        let bits: Vec<u32> = film.pixels().iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect();
        (bits, (stats.shadow_rays, stats.secondary_rays))
    };
    let base = go(1, 16);
    for (threads, tile) in [(2, 16), (2, 5), (1, 1)] {
        let (bits, rays) = go(threads, tile);
        assert!(bits == base.0, "{threads} threads, {tile}-pixel tiles: the image differs");
        assert_eq!(rays, base.1, "{threads} threads, {tile}-pixel tiles: ray counts");
    }
}
