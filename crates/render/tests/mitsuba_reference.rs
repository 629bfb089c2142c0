//! The path tracer against Mitsuba 3 on the same scene files: the references of
//! `../shared/reference` (a diffuse sphere on a plane under a point light, `max_depth` 2
//! and 8, 4096 spp) and statistics of our own Mitsuba 3.9.1 renders (1024 spp, box
//! filter) of the Cornell box (`cbox.xml`, spectral, at depths 2 and 6) and of a glass
//! and metal scene (`tests/data/glass_metal.xml`, depth 6), kept in
//! `tests/data/mitsuba_stats.json` as written by `tests/data/mitsuba_stats.py`.
//!
//! Criteria (issue 16): each channel's image mean within 1 % of Mitsuba's, and every
//! 8×8-grid tile mean within 3 σ, where σ combines dynray's own noise estimate for the
//! tile with the reference's. dynray's noise comes from two renders with independent
//! seeds: per pixel, `(a − b)² / 4` estimates the variance of their average, so a tile's
//! variance is the sum over its pixels divided by the pixel count squared. Seeds are
//! fixed, so the tests are deterministic; the spp are chosen so that a wrong factor of
//! 1.5 % fails the mean test (the image mean's standard error is ≈ 0.1 %).

use dynray_accel::AccelSpec;
use dynray_render::{render, Film, IntegratorKind, RenderOptions};
use dynray_scene::{load_file, Color};
use std::path::{Path, PathBuf};

fn shared(rel: &str) -> PathBuf {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared").join(rel);
    assert!(p.exists(), "{} is missing: the tests need the shared data beside the checkout", p.display());
    p
}

/// Reference statistics of one image.
struct Reference {
    mean: [f64; 3],
    /// `[row][column][channel]`, 8 × 8.
    tiles: Vec<Vec<[f64; 3]>>,
    /// Standard deviation of one pixel at the reference's spp, per channel.
    pixel_std: [f64; 3],
    /// Standard error of each tile mean, where the statistics give it (our own Mitsuba
    /// renders); otherwise `pixel_std / √(pixels per tile)`.
    tile_err: Option<Vec<Vec<[f64; 3]>>>,
}

fn triple(v: &serde_json::Value) -> [f64; 3] {
    let a = v.as_array().expect("an RGB triple");
    [0, 1, 2].map(|i| a[i].as_f64().expect("a number"))
}

fn reference(stats: &Path, key: &str) -> Reference {
    let text = std::fs::read_to_string(stats).unwrap();
    let all: serde_json::Value = serde_json::from_str(&text).unwrap();
    let s = &all[key];
    let grid = |v: &serde_json::Value| -> Vec<Vec<[f64; 3]>> {
        v.as_array().unwrap().iter().map(|row| row.as_array().unwrap().iter().map(triple).collect()).collect()
    };
    let tile_err = s.get("tile_stderr_rgb").map(grid);
    Reference {
        mean: triple(&s["mean_rgb"]),
        tiles: grid(&s["tile_mean_rgb"]),
        pixel_std: triple(&s["rms_pixel_std_rgb"]),
        tile_err,
    }
}

fn render_scene(xml: &Path, max_depth: Option<u32>, spp: u32, seed: u64) -> Film {
    let scene = load_file(xml).unwrap();
    let mut frame = scene.frame(0.0);
    if let Some(d) = max_depth {
        frame.settings.max_recursion_level = d - 1;
    }
    let accel = "bvh".parse::<AccelSpec>().unwrap().build(&frame.mesh, None).unwrap();
    render(&frame, accel.as_ref(), &RenderOptions { spp, seed, integrator: IntegratorKind::Path, ..Default::default() })
        .0
}

/// What the comparison found, for the failure message and the docs.
struct Comparison {
    mean: [f64; 3],
    worst_tile_sigma: f64,
    worst_tile: (usize, usize, usize),
}

fn compare(xml: &Path, max_depth: Option<u32>, reference: &Reference, spp: u32) -> Comparison {
    let (a, b) = (render_scene(xml, max_depth, spp, 1), render_scene(xml, max_depth, spp, 2));
    let (w, h) = (a.width() as usize, a.height() as usize);
    assert_eq!(reference.tiles.len(), 8);
    let (tw, th) = (w / 8, h / 8);
    let (pa, pb) = (a.pixels(), b.pixels());
    let ch = |c: Color, k: usize| c.to_array()[k] as f64;
    let mut mean = [0.0f64; 3];
    for (x, y) in pa.iter().zip(&pb) {
        for (k, m) in mean.iter_mut().enumerate() {
            *m += 0.5 * (ch(*x, k) + ch(*y, k));
        }
    }
    let mean = mean.map(|m| m / (w * h) as f64);
    let mut worst = (0.0f64, (0, 0, 0));
    for (ty, row) in reference.tiles.iter().enumerate() {
        for (tx, want) in row.iter().enumerate() {
            let n = (tw * th) as f64;
            let (mut sum, mut var) = ([0.0f64; 3], [0.0f64; 3]);
            for y in ty * th..(ty + 1) * th {
                for x in tx * tw..(tx + 1) * tw {
                    let (p, q) = (pa[y * w + x], pb[y * w + x]);
                    for k in 0..3 {
                        sum[k] += 0.5 * (ch(p, k) + ch(q, k));
                        var[k] += (ch(p, k) - ch(q, k)).powi(2) / 4.0;
                    }
                }
            }
            for k in 0..3 {
                let got = sum[k] / n;
                let ref_err = match &reference.tile_err {
                    Some(e) => e[ty][tx][k].powi(2),
                    None => reference.pixel_std[k].powi(2) / n,
                };
                let sigma = (var[k] / (n * n) + ref_err).sqrt();
                let dev = (got - want[k]).abs();
                let in_sigmas = if sigma > 0.0 {
                    dev / sigma
                } else if dev == 0.0 {
                    0.0
                } else {
                    f64::INFINITY
                };
                if in_sigmas > worst.0 {
                    worst = (in_sigmas, (ty, tx, k));
                }
            }
        }
    }
    Comparison { mean, worst_tile_sigma: worst.0, worst_tile: worst.1 }
}

fn check(name: &str, xml: &Path, max_depth: Option<u32>, reference: &Reference, spp: u32) {
    let c = compare(xml, max_depth, reference, spp);
    for k in 0..3 {
        let rel = c.mean[k] / reference.mean[k] - 1.0;
        eprintln!(
            "{name} channel {k}: mean {:.6} vs Mitsuba {:.6} ({:+.3} %)",
            c.mean[k],
            reference.mean[k],
            rel * 100.0
        );
        assert!(
            rel.abs() < 0.01,
            "{name} channel {k}: mean {} vs Mitsuba {} ({:+.2} %)",
            c.mean[k],
            reference.mean[k],
            rel * 100.0
        );
    }
    eprintln!("{name}: worst tile {:?} at {:.2} σ", c.worst_tile, c.worst_tile_sigma);
    assert!(
        c.worst_tile_sigma <= 3.0,
        "{name}: tile (row, column, channel) {:?} is {:.2} σ off Mitsuba's",
        c.worst_tile,
        c.worst_tile_sigma
    );
}

#[test]
fn sphere_direct_light_matches_mitsuba() {
    let stats = shared("reference/stats.json");
    check("sphere_d2", &shared("reference/sphere/sphere_d2.xml"), None, &reference(&stats, "sphere_d2"), 16);
}

#[test]
fn sphere_interreflection_matches_mitsuba() {
    let stats = shared("reference/stats.json");
    check("sphere_d8", &shared("reference/sphere/sphere_d8.xml"), None, &reference(&stats, "sphere_d8"), 16);
}

fn own_stats() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba_stats.json")
}

#[test]
fn cornell_box_direct_light_matches_mitsuba() {
    let xml = shared("scenes/cornell-box/mitsuba-cbox/cbox.xml");
    check("cbox_d2", &xml, Some(2), &reference(&own_stats(), "cbox_d2"), 8);
}

#[test]
fn cornell_box_six_segments_match_mitsuba() {
    let xml = shared("scenes/cornell-box/mitsuba-cbox/cbox.xml");
    check("cbox_d6", &xml, Some(6), &reference(&own_stats(), "cbox_d6"), 32);
}

/// Rough gold, glass, a smooth aluminium cube, a two-sided wall, an area light, a point
/// light and a constant environment (tests/data/glass_metal.xml). Its lamp has no BSDF:
/// Mitsuba gives it a black one, and before dynray did too, the lamp reflected light back
/// onto the floor and this scene came out 0.4–0.8 % too bright (its tiles up to 5.8 σ
/// off, found by removing emitters and objects one at a time: docs/results.md).
#[test]
fn glass_and_metal_match_mitsuba() {
    let xml = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/glass_metal.xml");
    check("glass_metal_d6", &xml, Some(6), &reference(&own_stats(), "glass_metal_d6"), 64);
}
