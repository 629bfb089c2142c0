//! `dynray view` in a real window under Xvfb (Debian's `xvfb`, presenting through
//! lavapipe): a still view after N frames is `render --spp N`'s image to the byte,
//! playing advances time, a scripted drag moves the camera, the heat map and the boxes
//! change the image where the structure is, and without a display the command fails at
//! once with a message. Skips without `xvfb-run` unless `DYNRAY_REQUIRE_DISPLAY=1` (CI).

mod support;

use std::path::Path;
use std::process::{Command, Output};
use support::{dynray, ok, root, skipped};

/// Runs `dynray view ARGS` under a fresh Xvfb server; `None` (skip) without xvfb-run.
fn view(args: &[&str]) -> Option<Output> {
    let has_xvfb = Command::new("sh").args(["-c", "command -v xvfb-run"]).output().is_ok_and(|o| o.status.success());
    if !has_xvfb {
        assert!(
            std::env::var("DYNRAY_REQUIRE_DISPLAY").map_or(true, |v| v != "1"),
            "xvfb-run is missing (Debian: apt-get install xvfb xauth)"
        );
        skipped("no xvfb-run (Debian: apt-get install xvfb xauth)");
        return None;
    }
    let runtime = tempfile::tempdir().unwrap();
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x1024x24", env!("CARGO_BIN_EXE_dynray"), "view"])
        .args(args)
        .current_dir(root())
        .env("XDG_RUNTIME_DIR", runtime.path())
        .output()
        .expect("run xvfb-run");
    Some(out)
}

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgb8()
}

/// Channels that differ between two images of one size.
fn differing(a: &image::RgbImage, b: &image::RgbImage) -> usize {
    assert_eq!(a.dimensions(), b.dimensions());
    a.as_raw().iter().zip(b.as_raw()).filter(|(x, y)| x != y).count()
}

#[test]
fn a_still_view_after_n_frames_is_render_spp_n_to_the_byte() {
    let dir = tempfile::tempdir().unwrap();
    let (shot, want) = (dir.path().join("view.png"), dir.path().join("render.png"));
    let size = ["--width", "96", "--height", "72", "--spp", "3", "--seed", "4"];
    let mut args: Vec<&str> = size.to_vec();
    let s = shot.to_str().unwrap();
    args.extend(["examples/whitted.scn", "--exit-after", "3", "--no-overlay", "--screenshot", s]);
    let Some(out) = view(&args) else { return };
    ok(out);
    let mut args: Vec<&str> = size.to_vec();
    args.extend(["render", "examples/whitted.scn", "-o", want.to_str().unwrap()]);
    args.rotate_left(size.len());
    ok(dynray(&args));
    let (a, b) = (rgb(&shot), rgb(&want));
    assert_eq!(differing(&a, &b), 0, "3 still frames against render --spp 3");

    // The same frames with the path tracer.
    let shot2 = dir.path().join("path.png");
    let args = [
        "examples/whitted.scn",
        "--integrator",
        "path",
        "--width",
        "64",
        "--height",
        "48",
        "--spp",
        "2",
        "--exit-after",
        "2",
        "--no-overlay",
        "--screenshot",
        shot2.to_str().unwrap(),
    ];
    ok(view(&args).unwrap());
    let want2 = dir.path().join("path-render.png");
    let w2 = want2.to_str().unwrap();
    ok(dynray(&[
        "render",
        "examples/whitted.scn",
        "--integrator",
        "path",
        "--width",
        "64",
        "--height",
        "48",
        "--spp",
        "2",
        "-o",
        w2,
    ]));
    assert_eq!(differing(&rgb(&shot2), &rgb(&want2)), 0, "path tracer, 2 frames against --spp 2");
}

#[test]
fn playing_advances_time_and_the_frames_differ() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("t.csv");
    let args = [
        "examples/animated.scn",
        "--width",
        "64",
        "--height",
        "48",
        "--spp",
        "1",
        "--play",
        "--exit-after",
        "6",
        "--timings",
        csv.to_str().unwrap(),
    ];
    let Some(out) = view(&args) else { return };
    ok(out);
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 6, "{text}");
    let times: Vec<f32> = rows.iter().map(|r| r[1].parse().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[1] > w[0]), "time advances every frame: {times:?}");
    let updates = rows.iter().filter(|r| !r[8].is_empty()).count();
    assert!(updates >= 5, "each new time updates the structure: {text}");
}

#[test]
fn a_scripted_drag_moves_the_camera() {
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("drag.txt");
    std::fs::write(&script, "# orbit to the right\nwait 1\ndrag 40 30 90 30\n").unwrap();
    let (still, dragged) = (dir.path().join("still.png"), dir.path().join("dragged.png"));
    let base = ["--width", "80", "--height", "60", "--spp", "1", "--exit-after", "3", "--no-overlay"];
    let mut a: Vec<&str> = base.to_vec();
    a.extend(["--screenshot", still.to_str().unwrap()]);
    let Some(out) = view(&a) else { return };
    ok(out);
    let mut b: Vec<&str> = base.to_vec();
    b.extend(["--screenshot", dragged.to_str().unwrap(), "--script", script.to_str().unwrap()]);
    ok(view(&b).unwrap());
    let changed = differing(&rgb(&still), &rgb(&dragged));
    assert!(changed > 80 * 60 * 3 / 10, "the drag turned the view: {changed} channels changed");
}

#[test]
fn heat_map_and_boxes_change_the_image_where_the_structure_is() {
    let dir = tempfile::tempdir().unwrap();
    let shoot = |show: &str| {
        let path = dir.path().join(format!("{}.png", show.replace(':', "-")));
        let p = path.to_str().unwrap();
        let args = [
            "--width",
            "160",
            "--height",
            "120",
            "--spp",
            "1",
            "--exit-after",
            "2",
            "--no-overlay",
            "--show",
            show,
            "--screenshot",
            p,
        ];
        view(&args).map(|o| {
            ok(o);
            rgb(&path)
        })
    };
    let Some(image) = shoot("image") else { return };
    let heat = shoot("heatmap").unwrap();
    let boxes = shoot("boxes:3").unwrap();
    let deeper = shoot("boxes:6").unwrap();
    let channels = 160 * 120 * 3;
    assert!(differing(&image, &heat) > channels / 2, "the heat map replaces the image");
    let drawn = differing(&image, &boxes);
    assert!(drawn > 300 && drawn < channels / 2, "boxes draw lines over part of the image: {drawn}");
    assert!(differing(&image, &deeper) > drawn, "deeper boxes draw more lines");
    // The sky above the scene holds no structure: no heat there beyond the empty-ray cost,
    // and no lines.
    let top_row_changed = (0..160).filter(|&x| image.get_pixel(x, 0) != boxes.get_pixel(x, 0)).count();
    assert_eq!(top_row_changed, 0, "no box reaches the top row of the demo's sky");
}

#[test]
fn without_a_display_it_fails_at_once_with_a_message() {
    let out = Command::new(env!("CARGO_BIN_EXE_dynray"))
        .args(["view", "--exit-after", "1"])
        .current_dir(root())
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no display") && err.contains("xvfb-run"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn outputs_are_checked_before_anything_opens() {
    for (args, want) in [
        (vec!["view", "--screenshot", "x.jpg"], "--screenshot writes a PNG"),
        (vec!["view", "--timings", "x.txt"], "--timings writes CSV"),
        (vec!["view", "--show", "wires"], "expected image, heatmap"),
        (vec!["view", "examples/whitted.scn", "--screenshot", "examples/whitted.scn"], "a PNG"),
        (vec!["view", "--camera", "perspective position <0, 1>"], "--camera"),
    ] {
        let out = dynray(&args);
        assert!(!out.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(want), "{args:?}: {err}");
    }
}

#[test]
fn on_the_gpu_the_heat_map_is_the_cpu_structures() {
    if !support::gpu_present() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shoot = |backend: &str| {
        let path = dir.path().join(format!("{backend}.png"));
        let p = path.to_str().unwrap();
        let args = [
            "--backend",
            backend,
            "--accel",
            "bvh2",
            "--width",
            "64",
            "--height",
            "48",
            "--spp",
            "1",
            "--exit-after",
            "2",
            "--no-overlay",
            "--show",
            "heatmap",
            "--screenshot",
            p,
        ];
        view(&args).map(|o| {
            ok(o);
            rgb(&path)
        })
    };
    let Some(cpu) = shoot("cpu") else { return };
    let gpu = shoot("gpu").unwrap();
    assert_eq!(differing(&cpu, &gpu), 0, "the GPU backend's heat map is drawn from the same bvh2 built on the CPU");
}

#[test]
fn the_gpu_backends_image_goes_to_the_window_on_the_device_and_matches_render() {
    if !support::gpu_present() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (shot, want, csv) = (dir.path().join("gpu.png"), dir.path().join("render.png"), dir.path().join("t.csv"));
    let size = ["--backend", "gpu", "--width", "96", "--height", "72", "--spp", "4"];
    let mut args: Vec<&str> = size.to_vec();
    args.extend(["--exit-after", "2", "--no-overlay", "--screenshot", shot.to_str().unwrap()]);
    args.extend(["--timings", csv.to_str().unwrap()]);
    let Some(out) = view(&args) else { return };
    ok(out);
    let mut args = vec!["render", "-o", want.to_str().unwrap()];
    args.extend(size);
    ok(dynray(&args));
    let (a, b) = (rgb(&shot), rgb(&want));
    // The device encodes sRGB with its own pow: at most one level from the CPU's.
    let worst = a.as_raw().iter().zip(b.as_raw()).map(|(x, y)| x.abs_diff(*y)).max().unwrap();
    assert!(worst <= 1, "the window's GPU image against render --backend gpu: {worst} levels");
    let text = std::fs::read_to_string(&csv).unwrap();
    let first = text.lines().nth(1).unwrap();
    assert!(first.ends_with(",device"), "resolved on the window's device, not read back: {first}");
}

#[test]
fn switching_the_structure_live_changes_no_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("switch.txt");
    // Three structures in turn (bvh -> bvh2 -> bih -> kdtree), each given 2 frames.
    std::fs::write(&script, "wait 2\nkey n\nwait 2\nkey n\nwait 2\nkey n\nwait 2\n").unwrap();
    let (still, switched, csv) =
        (dir.path().join("still.png"), dir.path().join("switched.png"), dir.path().join("t.csv"));
    let base = ["--width", "80", "--height", "60", "--spp", "2", "--no-overlay"];
    let mut a: Vec<&str> = base.to_vec();
    a.extend(["--exit-after", "2", "--screenshot", still.to_str().unwrap()]);
    let Some(out) = view(&a) else { return };
    ok(out);
    let mut b: Vec<&str> = base.to_vec();
    b.extend(["--exit-after", "9", "--script", script.to_str().unwrap()]);
    b.extend(["--screenshot", switched.to_str().unwrap(), "--timings", csv.to_str().unwrap()]);
    ok(view(&b).unwrap());
    assert_eq!(differing(&rgb(&still), &rgb(&switched)), 0, "every structure is exact: the image is the same");
    let text = std::fs::read_to_string(&csv).unwrap();
    let builds = text.lines().skip(1).filter(|l| l.split(',').nth(8) == Some("rebuild")).count();
    assert_eq!(builds, 4, "the first build and one per switch: {text}");
}

#[test]
fn record_keeps_every_frame_shown_and_scale_fixes_the_size() {
    let dir = tempfile::tempdir().unwrap();
    let (gif, csv) = (dir.path().join("rec.gif"), dir.path().join("t.csv"));
    let args = [
        "examples/animated.scn",
        "--width",
        "80",
        "--height",
        "60",
        "--spp",
        "1",
        "--scale",
        "0.5",
        "--play",
        "--exit-after",
        "5",
        "--no-overlay",
        "--record",
        gif.to_str().unwrap(),
        "--timings",
        csv.to_str().unwrap(),
    ];
    let Some(out) = view(&args) else { return };
    ok(out);
    let decoder =
        image::codecs::gif::GifDecoder::new(std::io::BufReader::new(std::fs::File::open(&gif).unwrap())).unwrap();
    let frames = image::AnimationDecoder::into_frames(decoder).collect_frames().unwrap();
    assert_eq!(frames.len(), 5, "one GIF frame per frame shown");
    assert_eq!(frames[0].buffer().dimensions(), (80, 60), "the window's size");
    assert_ne!(frames[0].buffer().as_raw(), frames[4].buffer().as_raw(), "the animation plays in the recording");
    let text = std::fs::read_to_string(&csv).unwrap();
    for row in text.lines().skip(1) {
        let f: Vec<&str> = row.split(',').collect();
        assert_eq!((f[3], f[4]), ("40", "30"), "--scale 0.5 renders half the size while playing: {row}");
    }
    for (args, want) in [(vec!["view", "--record", "x.mp4"], "animated GIF"), (vec!["view", "--scale", "2"], "--scale")]
    {
        let o = dynray(&args);
        assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains(want), "{args:?}");
    }
}
