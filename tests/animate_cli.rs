//! `dynray animate` and the `--time`/`--frame` options through the binary, on the skinned
//! CesiumMan (glTF): frames move; shards together are a full run byte for byte; a run
//! killed part-way and resumed gives the same frames; timings and exported meshes hold
//! what they say; `trace-rays --time` answers for that instant's geometry; bad options
//! fail clearly.

mod support;

use dynray_scene::load_file;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use support::{dynray, ok, scenes_dir};

fn cesium_man() -> PathBuf {
    scenes_dir().join("CesiumMan/glTF/CesiumMan.gltf")
}

/// Runs `animate` on CesiumMan into `out` at 96×72, one sample per pixel.
fn animate(out: &Path, extra: &[&str]) -> std::process::Output {
    let scene = cesium_man();
    let mut args = vec!["animate", scene.to_str().unwrap(), "--out", out.to_str().unwrap()];
    args.extend_from_slice(&["--width", "96", "--height", "72", "--spp", "1"]);
    args.extend_from_slice(extra);
    dynray(&args)
}

fn frames_in(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap().to_string_lossy().starts_with("frame_"))
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
        .collect();
    v.sort();
    v
}

#[test]
fn shards_together_are_a_full_run_and_frames_move() {
    let tmp = tempfile::tempdir().unwrap();
    let full = tmp.path().join("full");
    let sharded = tmp.path().join("sharded");
    ok(animate(&full, &["--frames", "0..5"]));
    for k in 0..3 {
        ok(animate(
            &sharded,
            &["--frames", "0..5", "--shard", &format!("{k}/3"), "--accel", "bih", "--update", "refit"],
        ));
    }
    let a = frames_in(&full);
    assert_eq!(
        a.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>(),
        (0..6).map(|k| format!("frame_{k:04}.png")).collect::<Vec<_>>()
    );
    assert_eq!(a, frames_in(&sharded), "the shards' frames (another structure and policy) differ from a full run");
    assert_ne!(a[0].1, a[3].1, "frame 3 looks like frame 0: nothing moved");
    assert!(full.join("preview.gif").is_file());
    assert!(sharded.join("timings_shard_2_of_3.csv").is_file());
    // The last shard to finish completes the set and writes the preview.
    assert!(sharded.join("preview.gif").is_file());
    let gif = image::open(full.join("preview.gif")).unwrap();
    assert_eq!((gif.width(), gif.height()), (96, 72));
}

#[test]
fn timings_have_a_row_per_frame_and_meshes_are_the_frames() {
    let tmp = tempfile::tempdir().unwrap();
    ok(animate(tmp.path(), &["--frames", "2..4", "--export-meshes", "--update", "refit"]));
    let csv = std::fs::read_to_string(tmp.path().join("timings.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(
        csv.lines().next().unwrap(),
        "frame,time_s,pose_ms,update,update_ms,sah_ratio,render_ms,time_to_image_ms,rays"
    );
    assert_eq!(rows.iter().map(|r| r[0]).collect::<Vec<_>>(), ["2", "3", "4"]);
    assert_eq!(rows.iter().map(|r| r[3]).collect::<Vec<_>>(), ["rebuilt", "refit", "refit"]);
    assert!(rows.iter().all(|r| r[8].parse::<u64>().unwrap() >= 96 * 72));
    // mesh_0003.obj holds frame 3's world-space vertices, bit for bit.
    let mut scene = load_file(&cesium_man()).unwrap();
    scene.apply_shading().unwrap();
    let t: f32 = rows[1][1].parse().unwrap();
    assert_eq!(t, scene.animation.timeline.time_of(3));
    let frame = scene.frame(t);
    let obj = std::fs::read_to_string(tmp.path().join("mesh_0003.obj")).unwrap();
    let verts: Vec<[f32; 3]> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f32> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    assert_eq!(verts.len(), frame.mesh.positions.len());
    assert!(verts.iter().zip(&frame.mesh.positions).all(|(a, b)| a.map(f32::to_bits) == b.map(f32::to_bits)));
    assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), frame.mesh.triangle_count());
}

#[test]
fn a_killed_run_resumes_to_the_same_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let full = tmp.path().join("full");
    let resumed = tmp.path().join("resumed");
    ok(animate(&full, &["--frames", "0..7"]));
    // Kill a run once its first frame is on disk; frames are written whole or not at all.
    let scene = cesium_man();
    let mut child = Command::new(env!("CARGO_BIN_EXE_dynray"))
        .args(["animate", scene.to_str().unwrap(), "--out", resumed.to_str().unwrap(), "--frames", "0..7"])
        .args(["--width", "96", "--height", "72", "--spp", "1", "--threads", "1"])
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let first = resumed.join("frame_0000.png");
    let start = std::time::Instant::now();
    while !first.is_file() && start.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().ok();
    child.wait().unwrap();
    let out = ok(animate(&resumed, &["--frames", "0..7", "--resume"]));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("resuming") || frames_in(&resumed).len() == 8, "{stderr}");
    assert_eq!(frames_in(&full), frames_in(&resumed));
    // Every frame has exactly one timings row.
    let csv = std::fs::read_to_string(resumed.join("timings.csv")).unwrap();
    let mut frames: Vec<u32> = csv.lines().skip(1).map(|l| l.split(',').next().unwrap().parse().unwrap()).collect();
    frames.sort();
    frames.dedup();
    assert!(frames.len() <= 8);
}

#[test]
fn render_at_a_frame_is_render_at_its_time() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = cesium_man();
    let s = scene.to_str().unwrap();
    let (a, b) = (tmp.path().join("a.png"), tmp.path().join("b.png"));
    let size = ["--width", "64", "--height", "48", "--spp", "1"];
    ok(dynray(&[&["render", s, "-o", a.to_str().unwrap(), "--frame", "12"][..], &size].concat()));
    ok(dynray(&[&["render", s, "-o", b.to_str().unwrap(), "--time", "0.5"][..], &size].concat()));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let c = tmp.path().join("c.png");
    ok(dynray(&[&["render", s, "-o", c.to_str().unwrap(), "--time", "0"][..], &size].concat()));
    assert_ne!(std::fs::read(&a).unwrap(), std::fs::read(&c).unwrap());
}

#[test]
fn bad_animate_options_fail_clearly() {
    let tmp = tempfile::tempdir().unwrap();
    let o = animate(tmp.path(), &["--frames", "5..2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("the first frame is after the last"));
    let o = animate(tmp.path(), &["--shard", "3/3"]);
    assert_eq!(o.status.code(), Some(2));
    let o = animate(tmp.path(), &["--frames", "0..100000"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("goes past the last frame"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = animate(tmp.path(), &["--clip", "no such clip"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no clip named `no such clip`"));
    let o = animate(tmp.path(), &["--update", "sometimes"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(frames_in(tmp.path()).is_empty(), "a failed run left frames");
}

#[test]
fn trace_rays_answers_for_the_geometry_at_the_time_asked() {
    use dynray_accel::{Accel, Brute};
    use dynray_geom::{Ray, Vec3};
    use npyz::WriterBuilder;
    let tmp = tempfile::tempdir().unwrap();
    // Rays across CesiumMan's legs, which move between 0 s and 1 s.
    let rows: Vec<[f32; 8]> = (0..400)
        .map(|i| {
            let x = -0.4 + 0.8 * (i % 20) as f32 / 19.0;
            let y = 0.05 + 0.7 * (i / 20) as f32 / 19.0;
            [x, y, 2.0, 0.0, 0.0, -1.0, 0.0, f32::INFINITY]
        })
        .collect();
    let rays_path = tmp.path().join("rays.npy");
    let mut w = npyz::WriteOptions::<f32>::new()
        .default_dtype()
        .shape(&[rows.len() as u64, 8])
        .writer(std::fs::File::create(&rays_path).unwrap())
        .begin_nd()
        .unwrap();
    w.extend(rows.iter().flatten().copied()).unwrap();
    w.finish().unwrap();
    let scene_path = cesium_man();
    let scene = dynray_scene::load_file_unshaded(&scene_path).unwrap().scene;
    let mut prims_at = Vec::new();
    for t in ["0", "1"] {
        let out = tmp.path().join(format!("hits_{t}.npz"));
        ok(dynray(&[
            "trace-rays",
            scene_path.to_str().unwrap(),
            "--rays",
            rays_path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--time",
            t,
        ]));
        let mut npz = npyz::npz::NpzArchive::open(&out).unwrap();
        let tv: Vec<f32> = npz.by_name("t").unwrap().unwrap().into_vec().unwrap();
        let prim: Vec<i64> = npz.by_name("prim").unwrap().unwrap().into_vec().unwrap();
        let frame = scene.frame(t.parse().unwrap());
        let brute = Brute::build(&frame.mesh).unwrap();
        for (i, r) in rows.iter().enumerate() {
            let h = brute.intersect(&Ray::with_interval(
                Vec3::new(r[0], r[1], r[2]),
                Vec3::new(r[3], r[4], r[5]),
                r[6],
                r[7],
            ));
            let want = if h.is_hit() { h.prim as i64 } else { -1 };
            assert_eq!((prim[i], tv[i].to_bits()), (want, h.t.to_bits()), "ray {i} at t = {t}");
        }
        prims_at.push(prim);
    }
    assert_ne!(prims_at[0], prims_at[1], "the legs did not move between 0 s and 1 s");
}

/// BART's robots: a static room and 221 rigidly moving parts. The split layout is the
/// flat one bit for bit (world-space parts, exact hits); the instanced one moves
/// instances only after the first frame, and `render --frame K` draws its frame K.
#[test]
fn scene_layouts_of_the_robots() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = scenes_dir().join("bart/robot/aff/Robot.aff");
    let s = scene.to_str().unwrap();
    let size = ["--width", "64", "--height", "48", "--spp", "1"];
    let run = |layout: &str| {
        let out = tmp.path().join(layout);
        let o = ok(dynray(
            &[&["animate", s, "--out", out.to_str().unwrap(), "--frames", "0..2", "--scene-accel", layout][..], &size]
                .concat(),
        ));
        (out, String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (flat, flat_log) = run("flat");
    let (split, split_log) = run("split");
    let (inst, inst_log) = run("instanced");
    assert!(flat_log.contains("flat"), "{flat_log}");
    assert!(split_log.contains("split: 221 parts, 221 instances"), "{split_log}");
    assert!(inst_log.contains("instanced: 23 parts, 221 instances"), "{inst_log}");
    assert_eq!(frames_in(&flat), frames_in(&split), "the split layout must draw the flat one's frames");
    assert_eq!(frames_in(&inst).len(), 3);
    let timings = std::fs::read_to_string(inst.join("timings.csv")).unwrap();
    let actions: Vec<&str> = timings.lines().skip(1).map(|l| l.split(',').nth(3).unwrap()).collect();
    assert_eq!(actions, ["rebuilt", "moved", "moved"], "{timings}");
    let one = tmp.path().join("one.png");
    ok(dynray(&[&["render", s, "-o", one.to_str().unwrap(), "--frame", "2"][..], &size].concat()));
    assert_eq!(std::fs::read(&one).unwrap(), std::fs::read(inst.join("frame_0002.png")).unwrap());
    let o = dynray(&[&["render", s, "-o", one.to_str().unwrap(), "--scene-accel", "layered"][..], &size].concat());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("layered"));
}

/// Regression (issue 43): `--fps 5e9` makes a timeline of 2^32 frames; `animate` listed
/// them all and aborted on an 8 GiB allocation. It refuses with the count and the way
/// out, before creating anything, and a range of that timeline still renders.
#[test]
fn a_timeline_of_billions_of_frames_is_refused_not_an_abort() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("frames");
    let o = animate(&out, &["--fps", "5e9"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("more than 1000000") && err.contains("--frames A..B"), "{err}");
    assert!(!err.contains("panicked") && !out.exists(), "{err}");
    ok(animate(&out, &["--fps", "5e9", "--frames", "1000..1001"]));
    assert_eq!(frames_in(&out).len(), 2);
}

/// Regression (issue 43): `--resume` took a 0-byte frame for a rendered one.
#[test]
fn resume_renders_an_empty_frame_again() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("frames");
    ok(animate(&out, &["--frames", "0..1"]));
    let want = frames_in(&out);
    std::fs::write(out.join("frame_0001.png"), b"").unwrap();
    let o = ok(animate(&out, &["--frames", "0..1", "--resume"]));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("resuming: 1 of 2 frames already there"), "{err}");
    assert_eq!(frames_in(&out), want);
}

/// Issue 48: a run whose stderr is a log, not a terminal, is never silent: the frame
/// count up front, an estimate after the first frame, a line per frame when asked for
/// every one (`DYNRAY_PROGRESS_SECONDS=0`) — and none of it with the default gap on a
/// run this short, but for the count and the estimate.
#[test]
fn a_logged_run_says_how_far_it_is() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = cesium_man();
    let run = |out: &Path, gap: Option<&str>| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_dynray"));
        c.args(["animate", scene.to_str().unwrap(), "--out", out.to_str().unwrap(), "--frames", "0..2"]);
        c.args(["--width", "32", "--height", "24", "--spp", "1"]).env_remove("DYNRAY_PROGRESS_SECONDS");
        if let Some(gap) = gap {
            c.env("DYNRAY_PROGRESS_SECONDS", gap);
        }
        let o = ok(c.output().unwrap());
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let every = run(&tmp.path().join("every"), Some("0"));
    assert!(every.contains("CesiumMan.gltf: 3 frames to render"), "{every}");
    assert!(every.contains("the first frame took") && every.contains("all 3 should take about"), "{every}");
    for k in 1..=3 {
        assert!(every.contains(&format!("frame {k}/3 (")), "frame {k}: {every}");
    }
    assert!(every.contains("frame 1/3") && every.contains("left"), "an estimate of what is left: {every}");
    let quiet = run(&tmp.path().join("quiet"), None);
    assert!(quiet.contains("3 frames to render") && quiet.contains("the first frame took"), "{quiet}");
    assert!(!quiet.contains("frame 1/3"), "a 3-frame run lasts less than the 5 s gap: {quiet}");
}
