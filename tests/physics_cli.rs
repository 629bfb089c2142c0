//! `dynray animate` and `dynray render --frame` on a physics scene (docs/physics.md):
//! the exported meshes move frame to frame and stay above the floor; a shard's frames
//! (re-simulated from time 0) are the full run's byte for byte; `render --frame K`
//! shows what `animate` shows at frame K.

mod support;

use std::path::Path;
use support::{dynray, ok};

const SCENE: &str = "examples/physics/soft_box_on_sphere.scn";

fn animate(out: &Path, extra: &[&str]) {
    let mut args = vec!["animate", SCENE, "--out", out.to_str().unwrap(), "--width", "48", "--height", "36"];
    args.extend_from_slice(&["--spp", "1", "--accel", "bih"]);
    args.extend_from_slice(extra);
    ok(dynray(&args));
}

/// The vertices of an exported OBJ.
fn vertices(path: &Path) -> Vec<[f32; 3]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f32> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

#[test]
fn frames_move_stay_above_the_floor_and_shards_match() {
    let tmp = tempfile::tempdir().unwrap();
    let full = tmp.path().join("full");
    animate(&full, &["--frames", "0..2", "--export-meshes"]);
    let meshes: Vec<Vec<[f32; 3]>> = (0..3).map(|k| vertices(&full.join(format!("mesh_{k:04}.obj")))).collect();
    // The soft box is the first actor: its vertices come first.
    let lowest = |m: &[[f32; 3]]| m.iter().map(|v| v[1]).fold(f32::INFINITY, f32::min);
    let moved =
        |a: &[[f32; 3]], b: &[[f32; 3]]| a.iter().zip(b).map(|(p, q)| (p[1] - q[1]).abs()).fold(0.0f32, f32::max);
    assert_eq!(meshes[0].len(), meshes[2].len());
    assert!(moved(&meshes[0], &meshes[1]) > 1e-3, "frame 1 is frame 0: nothing moved");
    assert!(moved(&meshes[1], &meshes[2]) > 1e-3, "frame 2 is frame 1: nothing moved");
    // The floor box's top is y = 0; its bottom (y = -0.1) is the lowest static vertex.
    for (k, m) in meshes.iter().enumerate() {
        assert!(lowest(m) >= -0.1 - 1e-6, "frame {k}: a vertex at y = {} is below the floor", lowest(m));
    }
    let fell = meshes[0].iter().zip(&meshes[2]).map(|(p, q)| p[1] - q[1]).fold(f32::MIN, f32::max);
    assert!(fell > 0.01, "the box did not fall: {fell}");

    // Frame 2 alone (a shard's or a resumed run's frame) is re-simulated from time 0.
    let shard = tmp.path().join("shard");
    animate(&shard, &["--frames", "0..2", "--shard", "2/3"]);
    assert_eq!(
        std::fs::read(full.join("frame_0002.png")).unwrap(),
        std::fs::read(shard.join("frame_0002.png")).unwrap()
    );
    let still = tmp.path().join("still.png");
    ok(dynray(&[
        "render",
        SCENE,
        "--frame",
        "2",
        "--width",
        "48",
        "--height",
        "36",
        "--spp",
        "1",
        "--accel",
        "bih",
        "-o",
        still.to_str().unwrap(),
    ]));
    assert_eq!(
        std::fs::read(full.join("frame_0002.png")).unwrap(),
        std::fs::read(&still).unwrap(),
        "render --frame 2 differs from animate's frame 2"
    );
}

/// Rays down onto the falling box from a grid over the scene, as an (N, 8) `.npy`.
fn rays_over_the_box(path: &Path) {
    let rows: Vec<[f32; 8]> = (0..900)
        .map(|i| {
            let x = -1.2 + 2.4 * (i % 30) as f32 / 29.0;
            let z = -1.2 + 2.4 * (i / 30) as f32 / 29.0;
            [x, 5.0, z, 0.01, -1.0, 0.02, 0.0, f32::INFINITY]
        })
        .collect();
    support::write_rays_npy(path, &rows);
}

/// Runs `trace-rays FILE` with `extra` and returns the archive's (t bits, prim, u bits, v bits).
fn traced(file: &Path, rays: &Path, out: &Path, extra: &[&str]) -> Vec<(u32, i64, u32, u32)> {
    let mut args = vec!["trace-rays", file.to_str().unwrap(), "--rays", rays.to_str().unwrap()];
    args.extend_from_slice(&["-o", out.to_str().unwrap()]);
    args.extend_from_slice(extra);
    ok(dynray(&args));
    let mut npz = npyz::npz::NpzArchive::open(out).unwrap();
    let mut floats = |name: &str| -> Vec<f32> { npz.by_name(name).unwrap().unwrap().into_vec().unwrap() };
    let (t, u, v) = (floats("t"), floats("u"), floats("v"));
    let prim: Vec<i64> = npz.by_name("prim").unwrap().unwrap().into_vec().unwrap();
    (0..t.len()).map(|i| (t[i].to_bits(), prim[i], u[i].to_bits(), v[i].to_bits())).collect()
}

/// Regression (issue 41): `trace-rays --time T` on a physics scene traced the
/// unsimulated mesh. It traces the simulated frame: exactly the hits of the mesh
/// `animate --export-meshes` wrote for that frame, and not frame 0's.
#[test]
fn trace_rays_at_a_time_traces_the_simulated_frame() {
    let tmp = tempfile::tempdir().unwrap();
    let full = tmp.path().join("full");
    animate(&full, &["--frames", "0..3", "--export-meshes"]);
    let rays = tmp.path().join("rays.npy");
    rays_over_the_box(&rays);
    let scene = Path::new(SCENE);
    let at_frame_3 = traced(scene, &rays, &tmp.path().join("scene.npz"), &["--frame", "3"]);
    let exported = traced(&full.join("mesh_0003.obj"), &rays, &tmp.path().join("mesh.npz"), &[]);
    assert!(at_frame_3.iter().filter(|h| h.1 >= 0).count() > 100, "the rays should hit the scene");
    assert_eq!(at_frame_3, exported, "trace-rays --frame 3 differs from the mesh animate exported for frame 3");
    // The same instant by its time gives the same answers.
    let timeline_rate = 24.0f32; // examples/physics/soft_box_on_sphere.scn: `fps 24`
    let t = format!("{}", 3.0 / timeline_rate);
    let at_time = traced(scene, &rays, &tmp.path().join("time.npz"), &["--time", &t]);
    assert_eq!(at_time, exported);
    let at_frame_0 = traced(scene, &rays, &tmp.path().join("zero.npz"), &[]);
    assert_ne!(at_frame_0, exported, "frame 3 traced like frame 0: the box did not move");
}
