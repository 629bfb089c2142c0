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
//! 1.5 % fails the mean test (the image mean's standard error is ≈ 0.1 %). σ is at
//! least [`FLOAT_FLOOR`] of the tile's value, for tiles without noise.
//!
//! The OBJ Cornell box (issue 48) is compared the same way with statistics of Mitsuba
//! rendering that OBJ (`tools/reference/cornell_obj.py`, `tests/data/mitsuba_obj_cbox.json`),
//! and by its share of fireflies ([`firefly_fraction`]).

use dynray_accel::AccelSpec;
use dynray_render::{render, Film, IntegratorKind, RenderOptions};
use dynray_scene::{load_file, Color};
use std::path::{Path, PathBuf};

/// Relative rounding between the two renderers' colours, a floor on a tile's σ.
const FLOAT_FLOOR: f64 = 1e-4;

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

fn render_scene(file: &Path, max_depth: Option<u32>, size: Option<(u32, u32)>, spp: u32, seed: u64) -> Film {
    let scene = load_file(file).unwrap();
    let mut frame = scene.frame(0.0);
    if let Some(d) = max_depth {
        frame.settings.max_recursion_level = d - 1;
    }
    if let Some((w, h)) = size {
        (frame.settings.width, frame.settings.height) = (w, h);
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

/// dynray's renders `a` and `b` (independent seeds) against `reference`.
fn compare(a: &Film, b: &Film, reference: &Reference) -> Comparison {
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
                // A noise-free tile (the background alone) still differs by the two
                // renderers' rounding: Mitsuba turns rgb(0.05) into 0.0499995.
                let sigma = (var[k] / (n * n) + ref_err).sqrt().max(want[k].abs() * FLOAT_FLOOR);
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
    let (a, b) = (render_scene(xml, max_depth, None, spp, 1), render_scene(xml, max_depth, None, spp, 2));
    assert_agrees(name, &a, &b, reference, 3.0);
}

/// The criteria of the module docs on two renders with independent seeds, every tile
/// within `max_sigma`.
fn assert_agrees(name: &str, a: &Film, b: &Film, reference: &Reference, max_sigma: f64) {
    let c = compare(a, b, reference);
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
        c.worst_tile_sigma <= max_sigma,
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

/// The firefly measure that `tools/reference/cornell_obj.py` also applies to Mitsuba's
/// images (its module docs): a pixel is a firefly when its luminance
/// `Y = 0.2126 R + 0.7152 G + 0.0722 B` exceeds `FIREFLY_RATIO` × the median of the nine
/// luminances of its 3×3 neighbourhood (itself included, the image's edge repeated
/// outwards) by more than `FIREFLY_FLOOR`. The reference file records both constants, and
/// the test checks that they are these.
const FIREFLY_RATIO: f64 = 4.0;
const FIREFLY_FLOOR: f64 = 0.05;
/// The firefly fraction issue 48 reported for the point-light stand-in (0.65 %).
const OLD_FIREFLIES: f64 = 0.0065;
/// What "comparable to Mitsuba" allows beyond twice its fraction: 0.05 % is 10 pixels of
/// a 160×120 image (Mitsuba's own count at 64 spp is about 5, so doubling alone would
/// let Poisson noise of a few pixels decide).
const FIREFLY_SLACK: f64 = 0.0005;

/// Share of `pixels` (row-major, `width` wide) that are fireflies.
fn firefly_fraction(pixels: &[Color], width: usize) -> f64 {
    let height = pixels.len() / width;
    let lum: Vec<f64> =
        pixels.iter().map(|c| 0.2126 * c.x as f64 + 0.7152 * c.y as f64 + 0.0722 * c.z as f64).collect();
    let at = |x: usize, y: usize, dx: usize, dy: usize| {
        let x = (x + dx).saturating_sub(1).min(width - 1);
        let y = (y + dy).saturating_sub(1).min(height - 1);
        lum[y * width + x]
    };
    let mut flies = 0usize;
    for y in 0..height {
        for x in 0..width {
            let mut around: [f64; 9] = std::array::from_fn(|k| at(x, y, k % 3, k / 3));
            around.sort_by(f64::total_cmp);
            if lum[y * width + x] > FIREFLY_RATIO * around[4] + FIREFLY_FLOOR {
                flies += 1;
            }
        }
    }
    flies as f64 / pixels.len() as f64
}

/// The measure itself: one bright pixel on a flat image is one firefly, and so is one on
/// the image's edge; a 2×2 cluster is four (specks of up to four pixels are what it
/// finds); a bright band three pixels tall across the image (an edge between regions) is
/// none, nor is the flat background; the threshold is `4 × median + 0.05`.
#[test]
fn firefly_fraction_counts_isolated_specks() {
    let (w, h) = (10, 8);
    let mut img = vec![Color::splat(0.2); w * h];
    assert_eq!(firefly_fraction(&img, w), 0.0);
    img[3 * w + 4] = Color::splat(5.0);
    assert_eq!(firefly_fraction(&img, w), 1.0 / 80.0);
    img[w - 1] = Color::new(0.0, 2.0, 0.0);
    assert_eq!(firefly_fraction(&img, w), 2.0 / 80.0);
    for (x, y) in [(4, 3), (5, 3), (4, 4), (5, 4)] {
        img[y * w + x] = Color::splat(5.0);
    }
    assert_eq!(firefly_fraction(&img, w), 5.0 / 80.0);
    let mut band = vec![Color::splat(0.2); w * h];
    band[2 * w..5 * w].fill(Color::splat(5.0));
    assert_eq!(firefly_fraction(&band, w), 0.0);
    // Just above 4 × 0.2 + 0.05 counts, just below does not.
    let mut img = vec![Color::splat(0.2); w * h];
    img[3 * w + 3] = Color::splat(0.86);
    img[5] = Color::splat(0.84);
    assert_eq!(firefly_fraction(&img, w), 1.0 / 80.0);
}

/// Issue 48: the OBJ Cornell box's MTL `Ke` lamp was a point light (Whitted's stand-in)
/// under the path tracer too, 1 mm below the lamp: hard shadows, and the ceiling beside
/// it so bright that paths bouncing off it made fireflies (0.65 % of the pixels at 64
/// spp, 640×480). Now the lamp is an area light, sampled with MIS, and the image is
/// Mitsuba's: statistics of Mitsuba 3.9.1 rendering the same OBJ (one two-sided diffuse
/// BSDF per MTL material, the `Ke` faces as area emitters, dynray's default environment
/// and camera, max_depth 11) at 2 × 1024 spp, written by `tools/reference/cornell_obj.py`
/// into `tests/data/mitsuba_obj_cbox.json`, which also holds the firefly fraction of
/// three 64-spp Mitsuba renders.
#[test]
fn obj_cornell_box_lamp_is_an_area_light_like_mitsubas() {
    let obj = shared("scenes/cornell-box/mcguire-obj/CornellBox-Original.obj");
    let stats = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba_obj_cbox.json");
    let reference = reference(&stats, "obj_cbox");
    let all: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let fly = &all["obj_cbox"]["firefly"];
    assert_eq!((fly["ratio"].as_f64(), fly["floor"].as_f64()), (Some(FIREFLY_RATIO), Some(FIREFLY_FLOOR)));
    assert_eq!(fly["spp"].as_u64(), Some(64));
    let per_seed: Vec<f64> = fly["fraction_per_seed"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let mitsuba = per_seed.iter().sum::<f64>() / per_seed.len() as f64;

    // The camera is dynray's default view, chosen at 640×480; 160×120 keeps its aspect.
    let size = Some((160, 120));
    let (a, b) = (render_scene(&obj, None, size, 64, 1), render_scene(&obj, None, size, 64, 2));
    let ours = [&a, &b].map(|f| firefly_fraction(&f.pixels(), f.width() as usize));
    let mean = (ours[0] + ours[1]) / 2.0;
    eprintln!(
        "obj_cbox: firefly fraction at 64 spp {:.3} % ({:.3} %, {:.3} %), Mitsuba's {:.3} % ({per_seed:?})",
        mean * 100.0,
        ours[0] * 100.0,
        ours[1] * 100.0,
        mitsuba * 100.0
    );
    assert!(
        mean < OLD_FIREFLIES / 4.0,
        "{:.3} % fireflies: not well below the old {} %",
        mean * 100.0,
        OLD_FIREFLIES * 100.0
    );
    assert!(
        mean <= 2.0 * mitsuba + FIREFLY_SLACK,
        "{:.3} % fireflies against Mitsuba's {:.3} % at the same spp",
        mean * 100.0,
        mitsuba * 100.0
    );
    // 4 σ rather than 3: 192 tile channels at 64 spp, whose noise has a heavy tail (rare
    // paths through the lamp's neighbourhood). With seed pairs (1, 2), (3, 4), (5, 6) and
    // (7, 8) the worst tile was 2.86, 3.92, 2.61 and 3.14 σ off, a different tile each
    // time, and 5–12 tile channels beyond 2 σ (a normal distribution expects 9): noise,
    // not a difference between the renderers. The means agree within 0.06 %.
    assert_agrees("obj_cbox", &a, &b, &reference, 4.0);
}

/// The same criterion on the scene as the path tracer saw it before issue 48 (the lamp's
/// material emitting nothing, its point-light stand-in sampled as an ordinary light):
/// it fails, so the test above can.
#[test]
fn obj_cornell_box_point_light_stand_in_had_fireflies() {
    let obj = shared("scenes/cornell-box/mcguire-obj/CornellBox-Original.obj");
    let mut scene = load_file(&obj).unwrap();
    for m in &mut scene.materials {
        m.emission = Color::ZERO;
    }
    for l in &mut scene.lights {
        l.emitter_stand_in = false;
    }
    let mut frame = scene.frame(0.0);
    (frame.settings.width, frame.settings.height) = (160, 120);
    let accel = "bvh".parse::<AccelSpec>().unwrap().build(&frame.mesh, None).unwrap();
    let options = RenderOptions { spp: 64, seed: 1, integrator: IntegratorKind::Path, ..Default::default() };
    let film = render(&frame, accel.as_ref(), &options).0;
    let old = firefly_fraction(&film.pixels(), 160);
    eprintln!("obj_cbox with the point light: firefly fraction at 64 spp {:.3} %", old * 100.0);
    assert!(old > OLD_FIREFLIES / 4.0, "{:.3} % fireflies would pass", old * 100.0);
}
