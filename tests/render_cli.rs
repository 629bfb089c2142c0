//! `dynray render`'s sampling and AOV options through the binary: `--spp 1` is the
//! library's one ray per pixel centre, the default is anti-aliased, and every AOV holds
//! exactly what the engine's own queries return for the pixel-centre rays.

mod support;

use dynray_accel::{Accel, Brute};
use dynray_render::{render, CameraRays, RenderOptions};
use dynray_scene::demo::demo_scene;
use dynray_scene::Frame;
use std::path::Path;
use support::{dynray, ok};

const W: u32 = 64;
const H: u32 = 48;

fn demo_frame() -> Frame {
    let mut frame = demo_scene().frame(0.0);
    frame.settings.width = W;
    frame.settings.height = H;
    frame
}

fn render_png(args: &[&str], out: &Path) -> Vec<u8> {
    let size = [W.to_string(), H.to_string()];
    let mut all = vec!["render", "-o", out.to_str().unwrap(), "--width", &size[0], "--height", &size[1]];
    all.extend_from_slice(args);
    ok(dynray(&all));
    image::open(out).unwrap().to_rgb8().into_raw()
}

/// Sum of absolute differences between horizontally and vertically adjacent channels: a
/// jagged edge has more of it than the same edge anti-aliased.
fn total_variation(rgb: &[u8]) -> u64 {
    let (w, h) = (W as usize, H as usize);
    let at = |x: usize, y: usize, c: usize| rgb[(y * w + x) * 3 + c] as i64;
    let mut tv = 0;
    for y in 0..h {
        for x in 0..w {
            for c in 0..3 {
                if x + 1 < w {
                    tv += (at(x + 1, y, c) - at(x, y, c)).unsigned_abs();
                }
                if y + 1 < h {
                    tv += (at(x, y + 1, c) - at(x, y, c)).unsigned_abs();
                }
            }
        }
    }
    tv
}

#[test]
fn one_sample_per_pixel_is_the_library_render_and_the_default_is_anti_aliased() {
    let dir = tempfile::tempdir().unwrap();
    let one = render_png(&["--spp", "1"], &dir.path().join("one.png"));
    let frame = demo_frame();
    let accel = dynray_accel::Bvh::build(&frame.mesh, &Default::default()).unwrap();
    let (film, _) = render(&frame, &accel, &RenderOptions::default());
    assert_eq!(one, film.to_srgb8(), "--spp 1 differs from one ray through each pixel centre");

    let aa = render_png(&[], &dir.path().join("aa.png"));
    let differ = one.chunks(3).zip(aa.chunks(3)).filter(|(a, b)| a != b).count();
    assert!(differ > 0, "the default render is the one-sample render");
    // Anti-aliasing softens the checkerboard's and the silhouettes' steps.
    let (tv1, tv_aa) = (total_variation(&one), total_variation(&aa));
    assert!(tv_aa * 100 < tv1 * 95, "anti-aliased variation {tv_aa} is not below the one-sample {tv1}");
    // Same seed, same image; another seed moves the samples.
    assert_eq!(aa, render_png(&[], &dir.path().join("aa2.png")));
    assert_ne!(aa, render_png(&["--seed", "7"], &dir.path().join("seed7.png")));
}

/// Reads a one-channel EXR AOV (row-major, y down).
fn read_scalar_exr(path: &Path, channel: &str) -> Vec<f32> {
    use exr::prelude::*;
    let image = read_all_flat_layers_from_file(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let layer = &image.layer_data[0];
    assert_eq!(layer.size, Vec2(W as usize, H as usize));
    let names: Vec<String> = layer.channel_data.list.iter().map(|c| c.name.to_string()).collect();
    assert_eq!(names, [channel], "channels of {}", path.display());
    layer.channel_data.list[0].sample_data.values_as_f32().collect()
}

#[test]
fn depth_and_prim_aovs_hold_the_centre_rays_hits() {
    let dir = tempfile::tempdir().unwrap();
    let size = [W.to_string(), H.to_string()];
    let depth_path = dir.path().join("depth.exr");
    let prim_path = dir.path().join("prim.exr");
    for (aov, path) in [("depth", &depth_path), ("prim", &prim_path)] {
        let p = path.to_str().unwrap();
        ok(dynray(&["render", "--aov", aov, "-o", p, "--width", &size[0], "--height", &size[1], "--accel", "bvh"]));
    }
    let depth = read_scalar_exr(&depth_path, "Z");
    let prim = read_scalar_exr(&prim_path, "prim");

    let frame = demo_frame();
    let brute = Brute::build(&frame.mesh).unwrap();
    let camera = CameraRays::new(&frame.camera, W, H);
    let (mut hits, mut misses) = (0, 0);
    for y in 0..H {
        for x in 0..W {
            let i = (y * W + x) as usize;
            let hit = brute.intersect(&camera.primary(x, y));
            if hit.is_hit() {
                hits += 1;
                assert_eq!(depth[i].to_bits(), hit.t.to_bits(), "depth at ({x}, {y})");
                assert_eq!(prim[i], hit.prim as f32, "prim at ({x}, {y})");
            } else {
                misses += 1;
                assert_eq!(depth[i], f32::INFINITY, "depth of a miss at ({x}, {y})");
                assert_eq!(prim[i], -1.0, "prim of a miss at ({x}, {y})");
            }
        }
    }
    // The demo shows sky above the floor: both cases are exercised.
    assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
}

#[test]
fn normal_and_albedo_aovs_are_rgb_exr() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    for aov in ["normal", "albedo"] {
        let path = dir.path().join(format!("{aov}.exr"));
        ok(dynray(&["render", "--aov", aov, "-o", path.to_str().unwrap(), "--width", "32", "--height", "24"]));
        let image = read_all_flat_layers_from_file(&path).unwrap();
        let layer = &image.layer_data[0];
        let mut names: Vec<String> = layer.channel_data.list.iter().map(|c| c.name.to_string()).collect();
        names.sort();
        assert_eq!(names, ["B", "G", "R"], "{aov}");
        let values: Vec<Vec<f32>> =
            layer.channel_data.list.iter().map(|c| c.sample_data.values_as_f32().collect()).collect();
        if aov == "normal" {
            // Every pixel is a unit normal or zero (sky).
            for (i, ((a, b), c)) in values[0].iter().zip(&values[1]).zip(&values[2]).enumerate() {
                let len = (a * a + b * b + c * c).sqrt();
                assert!(len == 0.0 || (len - 1.0).abs() < 1e-4, "pixel {i}: |n| = {len}");
            }
        } else {
            assert!(values.iter().flatten().all(|v| (0.0..=1.0).contains(v)), "albedo outside [0, 1]");
            assert!(values.iter().flatten().any(|v| *v > 0.1), "albedo is black everywhere");
        }
    }
}

#[test]
fn aovs_need_an_exr_output_and_names_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("depth.png");
    let o = dynray(&["render", "--aov", "depth", "-o", png.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    // An output type that cannot hold the AOV is an option refused before any work.
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("depth.png") && err.contains(".exr"), "{err}");
    assert!(!png.exists());
    for (flag, value, listed) in [("--aov", "uv", "albedo"), ("--integrator", "photon", "whitted"), ("--spp", "0", "1")]
    {
        let o = dynray(&["render", flag, value, "-o", png.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{flag} {value}: {err}");
        assert!(err.contains(listed), "{flag} {value}: {err}");
    }
}

/// `--integrator cumulative` with every bounce expanded is Whitted's image (to rounding
/// of 8-bit output: the two sum in different orders, a few f32 ulps apart), passes are
/// reported, and its flags are refused with another integrator.
#[test]
fn cumulative_at_full_branch_depth_is_whitted_and_its_flags_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c.png");
    let whitted = render_png(&["--spp", "1", "--max-depth", "4"], &out);
    let cumulative =
        render_png(&["--spp", "1", "--max-depth", "4", "--integrator", "cumulative", "--branch-depth", "4"], &out);
    let off = whitted.iter().zip(&cumulative).map(|(a, b)| a.abs_diff(*b)).max().unwrap();
    assert!(off <= 1, "cumulative at full branch depth differs from whitted by {off} levels");
    let o = ok(dynray(&[
        "render",
        "-o",
        out.to_str().unwrap(),
        "--width",
        "32",
        "--height",
        "24",
        "--integrator",
        "cumulative",
        "--branch-depth",
        "0",
        "--spp",
        "2",
        "--passes",
        "3",
    ]));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("2 spp × 3 passes"), "{err}");
    let png = out.to_str().unwrap();
    for (args, code, says) in [
        (vec!["--branch-depth", "2"], 2, "--branch-depth applies to --integrator cumulative only"),
        (vec!["--integrator", "path", "--passes", "2"], 2, "--passes applies to --integrator cumulative only"),
        (vec!["--integrator", "cumulative", "--passes", "0"], 2, "--passes"),
        (vec!["--integrator", "cumulative", "--branch-depth", "two"], 2, "--branch-depth"),
        (vec!["--integrator", "cumulative", "--passes", "40000", "--spp", "2"], 1, "more than 65536"),
    ] {
        let mut all = vec!["render", "-o", png];
        all.extend_from_slice(&args);
        let o = dynray(&all);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
}

/// Issue 48: in a log (stderr not a terminal) a render reports its tiles, with the
/// elapsed time, when asked for every step; with the default gap a render this short
/// stays quiet but for its summary.
#[test]
fn a_logged_render_reports_its_tiles() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("x.png");
    let run = |gap: Option<&str>| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_dynray"));
        c.args(["render", "-o", out.to_str().unwrap(), "--width", "64", "--height", "48", "--spp", "1"]);
        c.env_remove("DYNRAY_PROGRESS_SECONDS");
        if let Some(gap) = gap {
            c.env("DYNRAY_PROGRESS_SECONDS", gap);
        }
        String::from_utf8_lossy(&ok(c.output().unwrap()).stderr).into_owned()
    };
    let every = run(Some("0"));
    assert!(every.contains("built-in demo scene: 100% of the tiles ("), "{every}");
    assert!(every.lines().filter(|l| l.contains("% of the tiles")).count() > 1, "{every}");
    assert!(every.contains(" after ") && every.contains(" left"), "{every}");
    let quiet = run(None);
    assert!(!quiet.contains("of the tiles"), "{quiet}");
}
