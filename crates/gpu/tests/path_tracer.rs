//! The GPU path tracer (the wavefront's `path` mode, shaders/path_shade.wgsl) checked as
//! the CPU path tracer is: statistically, since its random numbers are its own (a
//! stateless hash per sample, depth and dimension) and its image cannot equal the CPU's
//! bit for bit.
//!
//! - Against Mitsuba 3: the references of `../shared/reference` (diffuse sphere on a
//!   plane under a point light, `max_depth` 2 and 8) and dynray's own Mitsuba statistics
//!   of `crates/render/tests/data/glass_metal.xml` (rough gold, glass, a smooth metal
//!   cube, a two-sided wall, an area light, a point light, a constant environment): each
//!   channel's image mean within 1 % of Mitsuba's, the 8×8-grid tile means within the
//!   bounds of [`assert_tiles`] (no tile past 4.5 σ, root mean square ≤ 1.5 σ), σ
//!   combining our noise (two renders with independent seeds: `(a − b)²/4` per pixel
//!   estimates the variance of their average) with the reference's. The sphere scenes
//!   render at 128×96, half the reference's size: a tile covers the same part of the
//!   image, so its expected mean is the same.
//! - Against the CPU path tracer: Mitsuba's Cornell box (`cbox.xml`, area light, depth 6)
//!   and examples/whitted.scn (the Phong mapping of scene-language materials, point
//!   lights) rendered by both; each channel's mean within 3 σ of the combined noise of the two,
//!   the tiles by the same bounds.
//! - The megakernel and hybrid strategies refuse the path tracer with a message.
//!
//! Seeds are fixed, so on a given device the tests are deterministic.

mod gpu_support;

use dynray_accel::{Bvh, BvhParams};
use dynray_gpu::{GpuContext, GpuIntegrator, GpuRenderOptions, GpuRenderer, GpuStrategy};
use dynray_render::{render, Film, IntegratorKind, RenderOptions};
use dynray_scene::{load_file, Color, Frame};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn shared(rel: &str) -> PathBuf {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared").join(rel);
    assert!(p.exists(), "{} is missing: the tests need the shared data beside the checkout", p.display());
    p
}

fn own_stats() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../render/tests/data/mitsuba_stats.json")
}

fn frame_of(xml: &Path, max_depth: Option<u32>, size: Option<(u32, u32)>) -> Frame {
    let mut frame = load_file(xml).unwrap().frame(0.0);
    if let Some(d) = max_depth {
        frame.settings.max_recursion_level = d - 1;
    }
    if let Some((w, h)) = size {
        frame.settings.width = w;
        frame.settings.height = h;
    }
    frame
}

fn gpu_render(ctx: &Arc<GpuContext>, frame: &Frame, spp: u32, seed: u64) -> Film {
    let bvh = Bvh::build(&frame.mesh, &BvhParams::default()).unwrap();
    let mut r = GpuRenderer::new(ctx.clone()).unwrap();
    let g = r.render(frame, &bvh, &GpuRenderOptions::path(spp, seed)).unwrap();
    eprintln!(
        "GPU path: {}x{} {spp} spp seed {seed}: {:.0} ms, {} shadow + {} secondary rays",
        frame.settings.width,
        frame.settings.height,
        g.timings.total * 1e3,
        g.stats.shadow_rays,
        g.stats.secondary_rays
    );
    g.film
}

fn cpu_render(frame: &Frame, spp: u32, seed: u64) -> Film {
    let bvh = Bvh::build(&frame.mesh, &BvhParams::default()).unwrap();
    render(frame, &bvh, &RenderOptions { spp, seed, integrator: IntegratorKind::Path, ..Default::default() }).0
}

fn ch(c: Color, k: usize) -> f64 {
    c.to_array()[k] as f64
}

/// An estimate from two independent renders: per channel the image mean and its
/// variance, and per 8×8-grid tile the same.
struct Estimate {
    mean: [f64; 3],
    mean_var: [f64; 3],
    /// `[row][column]`: (mean, variance of the mean) per channel.
    tiles: Vec<Vec<([f64; 3], [f64; 3])>>,
}

fn estimate(a: &Film, b: &Film) -> Estimate {
    let (w, h) = (a.width() as usize, a.height() as usize);
    assert!(w % 8 == 0 && h % 8 == 0, "{w}x{h} does not split into 8×8 tiles");
    let (pa, pb) = (a.pixels(), b.pixels());
    let stats = |xs: &mut dyn Iterator<Item = usize>| {
        let (mut sum, mut var, mut n) = ([0.0f64; 3], [0.0f64; 3], 0usize);
        for i in xs {
            for k in 0..3 {
                sum[k] += 0.5 * (ch(pa[i], k) + ch(pb[i], k));
                var[k] += (ch(pa[i], k) - ch(pb[i], k)).powi(2) / 4.0;
            }
            n += 1;
        }
        let n = n as f64;
        (sum.map(|s| s / n), var.map(|v| v / (n * n)))
    };
    let (mean, mean_var) = stats(&mut (0..w * h));
    let (tw, th) = (w / 8, h / 8);
    let tiles = (0..8)
        .map(|ty| {
            (0..8)
                .map(|tx| {
                    stats(&mut (ty * th..(ty + 1) * th).flat_map(|y| (tx * tw..(tx + 1) * tw).map(move |x| y * w + x)))
                })
                .collect()
        })
        .collect();
    Estimate { mean, mean_var, tiles }
}

/// How far the 8×8 tiles' means are from what they should be, in σ of their noise.
#[derive(Debug)]
struct TileDeviations {
    /// The largest deviation and its (row, column, channel).
    worst: f64,
    at: (usize, usize, usize),
    /// Root mean square of all of them: about 1 for an unbiased estimate with an
    /// honest noise estimate, larger where a bias spreads over many tiles.
    rms: f64,
    /// How many exceed 3 σ (of 192).
    over_3: usize,
}

/// `z(row, column, channel)`: one tile's deviation in σ.
fn tile_deviations(z: impl Fn(usize, usize, usize) -> f64) -> TileDeviations {
    let mut d = TileDeviations { worst: 0.0, at: (0, 0, 0), rms: 0.0, over_3: 0 };
    for ty in 0..8 {
        for tx in 0..8 {
            for k in 0..3 {
                let s = z(ty, tx, k);
                if s > d.worst {
                    d.worst = s;
                    d.at = (ty, tx, k);
                }
                d.rms += s * s;
                d.over_3 += usize::from(s > 3.0);
            }
        }
    }
    d.rms = (d.rms / 192.0).sqrt();
    d
}

/// The tile criterion. Issue 16's per-tile 3 σ is what the CPU tests assert; for 64
/// tiles of an unbiased renderer whose noise estimate is honest, one of them passes
/// 3 σ by chance about one render in six (the GPU's tiles spread as such: root mean
/// square 0.9 σ; measured worst 3.5 σ on sphere_d8 at 16 spp, 4.0 σ at 64 spp, in
/// tiles that change from one spp to the next). So: no tile past 4.5 σ (for normal
/// deviations a false alarm once in about 2,000 images of 64 tiles), and a root mean
/// square of at most 1.5 σ, which a bias spread over many tiles fails long before any
/// one tile does.
fn assert_tiles(name: &str, d: &TileDeviations) {
    eprintln!(
        "{name}: worst tile (row, column, channel) {:?} at {:.2} σ, rms {:.2} σ, {} of 192 over 3 σ",
        d.at, d.worst, d.rms, d.over_3
    );
    assert!(d.worst <= 4.5, "{name}: tile (row, column, channel) {:?} is {:.2} σ off", d.at, d.worst);
    assert!(d.rms <= 1.5, "{name}: the tiles are {:.2} σ off in root mean square", d.rms);
}

fn sigmas(dev: f64, sigma: f64) -> f64 {
    if sigma > 0.0 {
        dev / sigma
    } else if dev == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

/// Reference statistics of one Mitsuba image.
struct Reference {
    mean: [f64; 3],
    tiles: Vec<Vec<[f64; 3]>>,
    /// Variance of each tile mean.
    tile_var: Vec<Vec<[f64; 3]>>,
}

fn triple(v: &serde_json::Value) -> [f64; 3] {
    let a = v.as_array().expect("an RGB triple");
    [0, 1, 2].map(|i| a[i].as_f64().expect("a number"))
}

fn reference(stats: &Path, key: &str) -> Reference {
    let all: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(stats).unwrap()).unwrap();
    let s = &all[key];
    let grid = |v: &serde_json::Value| -> Vec<Vec<[f64; 3]>> {
        v.as_array().unwrap().iter().map(|row| row.as_array().unwrap().iter().map(triple).collect()).collect()
    };
    let tiles = grid(&s["tile_mean_rgb"]);
    let tile_var = match s.get("tile_stderr_rgb") {
        Some(e) => grid(e).into_iter().map(|r| r.into_iter().map(|t| t.map(|x| x * x)).collect()).collect(),
        None => {
            // The pixel noise over the reference's own pixels per tile.
            let std = triple(&s["rms_pixel_std_rgb"]);
            let n = (s["width"].as_f64().unwrap() / 8.0) * (s["height"].as_f64().unwrap() / 8.0);
            vec![vec![std.map(|x| x * x / n); 8]; 8]
        }
    };
    Reference { mean: triple(&s["mean_rgb"]), tiles, tile_var }
}

/// The GPU path tracer against a Mitsuba reference.
fn check_against_mitsuba(name: &str, frame: &Frame, reference: &Reference, spp: u32) {
    let Some(ctx) = gpu_support::device() else { return };
    let e = estimate(&gpu_render(&ctx, frame, spp, 1), &gpu_render(&ctx, frame, spp, 2));
    for k in 0..3 {
        let rel = e.mean[k] / reference.mean[k] - 1.0;
        eprintln!(
            "{name} channel {k}: GPU mean {:.6} (± {:.6}) vs Mitsuba {:.6} ({:+.3} %)",
            e.mean[k],
            e.mean_var[k].sqrt(),
            reference.mean[k],
            rel * 100.0
        );
        assert!(
            rel.abs() < 0.01,
            "{name} channel {k}: GPU mean {} vs Mitsuba {} ({:+.2} %)",
            e.mean[k],
            reference.mean[k],
            rel * 100.0
        );
    }
    let d = tile_deviations(|ty, tx, k| {
        let (got, var) = e.tiles[ty][tx];
        sigmas((got[k] - reference.tiles[ty][tx][k]).abs(), (var[k] + reference.tile_var[ty][tx][k]).sqrt())
    });
    assert_tiles(name, &d);
}

#[test]
fn sphere_direct_light_matches_mitsuba() {
    let xml = shared("reference/sphere/sphere_d2.xml");
    let r = reference(&shared("reference/stats.json"), "sphere_d2");
    check_against_mitsuba("sphere_d2", &frame_of(&xml, None, Some((128, 96))), &r, 16);
}

#[test]
fn sphere_interreflection_matches_mitsuba() {
    let xml = shared("reference/sphere/sphere_d8.xml");
    let r = reference(&shared("reference/stats.json"), "sphere_d8");
    check_against_mitsuba("sphere_d8", &frame_of(&xml, None, Some((128, 96))), &r, 16);
}

/// Conductors (rough and smooth), a dielectric, a two-sided BSDF, an area light, a point
/// light and the constant environment.
#[test]
fn glass_and_metal_match_mitsuba() {
    let xml = Path::new(env!("CARGO_MANIFEST_DIR")).join("../render/tests/data/glass_metal.xml");
    let r = reference(&own_stats(), "glass_metal_d6");
    check_against_mitsuba("glass_metal_d6", &frame_of(&xml, Some(6), None), &r, 64);
}

/// The GPU path tracer against the CPU's on `frame`: each channel's mean within 3 σ of
/// the two renderers' combined noise (and 2 %), the tiles by [`assert_tiles`].
fn check_against_cpu(name: &str, frame: &Frame, spp: u32) {
    let Some(ctx) = gpu_support::device() else { return };
    let gpu = estimate(&gpu_render(&ctx, frame, spp, 1), &gpu_render(&ctx, frame, spp, 2));
    let cpu = estimate(&cpu_render(frame, spp, 1), &cpu_render(frame, spp, 2));
    for k in 0..3 {
        let s = sigmas((gpu.mean[k] - cpu.mean[k]).abs(), (gpu.mean_var[k] + cpu.mean_var[k]).sqrt());
        eprintln!(
            "{name} channel {k}: GPU mean {:.6} vs CPU {:.6} ({:+.3} %, {s:.2} σ)",
            gpu.mean[k],
            cpu.mean[k],
            (gpu.mean[k] / cpu.mean[k] - 1.0) * 100.0
        );
        assert!(s <= 3.0, "{name} channel {k}: GPU mean {} vs CPU {} is {s:.2} σ apart", gpu.mean[k], cpu.mean[k]);
        assert!((gpu.mean[k] / cpu.mean[k] - 1.0).abs() < 0.02, "{name} channel {k}");
    }
    let d = tile_deviations(|ty, tx, k| {
        let ((g, gv), (c, cv)) = (gpu.tiles[ty][tx], cpu.tiles[ty][tx]);
        sigmas((g[k] - c[k]).abs(), (gv[k] + cv[k]).sqrt())
    });
    assert_tiles(&format!("{name} GPU vs CPU"), &d);
}

#[test]
fn cornell_box_agrees_with_the_cpu_path_tracer() {
    let xml = shared("scenes/cornell-box/mitsuba-cbox/cbox.xml");
    check_against_cpu("cbox_d6", &frame_of(&xml, Some(6), Some((64, 64))), 16);
}

/// The Phong mapping of the scene language's materials (Lambertian, normalised Phong,
/// mirror and dielectric lobes chosen by weight, two-sided) under point lights:
/// examples/whitted.scn, a mirror and a glass sphere over a tiled floor.
#[test]
fn scene_language_materials_agree_with_the_cpu_path_tracer() {
    let scn = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/whitted.scn");
    check_against_cpu("whitted.scn", &frame_of(&scn, Some(6), Some((64, 48))), 128);
}

#[test]
fn megakernel_and_hybrid_refuse_the_path_tracer() {
    let Some(ctx) = gpu_support::device() else { return };
    let frame = frame_of(&shared("reference/sphere/sphere_d2.xml"), None, Some((16, 12)));
    let bvh = Bvh::build(&frame.mesh, &BvhParams::default()).unwrap();
    let mut r = GpuRenderer::new(ctx).unwrap();
    for strategy in [GpuStrategy::Megakernel, GpuStrategy::Hybrid] {
        let options = GpuRenderOptions { strategy, integrator: GpuIntegrator::Path, ..GpuRenderOptions::path(1, 0) };
        let e = r.render(&frame, &bvh, &options).expect_err("only the wavefront runs the path tracer").to_string();
        assert!(e.contains("path integrator") && e.contains("wavefront"), "{strategy}: {e}");
    }
    // The wavefront renders it (the sphere's camera has clip planes, which the path
    // tracer's camera rays honour).
    r.render(&frame, &bvh, &GpuRenderOptions::path(1, 0)).unwrap();
}
