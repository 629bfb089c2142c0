//! `dynray render --backend gpu --gpu-strategy S` through the binary: each of seed 003's
//! three strategies renders the demo and the example scenes as the CPU's Whitted
//! integrator does (linear EXR compared per channel), and what the GPU does not render
//! is refused with a message. Skips without an adapter unless `DYNRAY_REQUIRE_GPU=1` (CI).

mod support;

use std::path::Path;
use support::{dynray, examples_dir, gpu_present, max_abs_difference, ok, read_exr_channels, refused_as_usage};

/// Largest per-channel difference allowed: the strategies' f32 shading differs from the
/// CPU's by a few ulps (render_strategies.rs measures 2.44e-6 on its scene).
const TOLERANCE: f32 = 1e-4;

fn render_exr(scene: Option<&Path>, extra: &[&str], out: &Path) -> Vec<f32> {
    let mut args = vec!["render", "-o", out.to_str().unwrap(), "--width", "48", "--height", "36", "--spp", "2"];
    if let Some(s) = scene {
        args.insert(1, s.to_str().unwrap());
    }
    args.extend_from_slice(extra);
    ok(dynray(&args));
    read_exr_channels(out)
}

#[test]
fn every_strategy_renders_the_cpus_image() {
    if !gpu_present() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let whitted = examples_dir().join("whitted.scn");
    for (name, scene) in [("demo", None), ("whitted", Some(whitted.as_path()))] {
        let cpu = render_exr(scene, &[], &dir.path().join(format!("{name}-cpu.exr")));
        assert!(cpu.iter().any(|&v| v > 0.05), "{name}: the CPU image is black");
        for strategy in ["wavefront", "megakernel", "hybrid"] {
            let out = dir.path().join(format!("{name}-{strategy}.exr"));
            let gpu = render_exr(scene, &["--backend", "gpu", "--gpu-strategy", strategy], &out);
            assert_eq!(gpu.len(), cpu.len());
            let worst = max_abs_difference(&cpu, &gpu);
            assert!(worst <= TOLERANCE, "{name} / {strategy}: largest channel difference {worst}");
        }
        // Trees built on the device trace the same hits, so the image is the same.
        for build in ["sah", "lbvh"] {
            let out = dir.path().join(format!("{name}-{build}.exr"));
            let gpu =
                render_exr(scene, &["--backend", "gpu", "--gpu-strategy", "wavefront", "--gpu-build", build], &out);
            let worst = max_abs_difference(&cpu, &gpu);
            assert!(worst <= TOLERANCE, "{name} / {build}-built tree: largest channel difference {worst}");
        }
    }
}

#[test]
fn what_the_gpu_does_not_render_is_refused() {
    if !gpu_present() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let o = out.to_str().unwrap();
    let gpu = ["--backend", "gpu", "--width", "16", "--height", "12"];
    let with = |extra: &[&str]| {
        let mut args = vec!["render", "-o", o];
        args.extend_from_slice(&gpu);
        args.extend_from_slice(extra);
        dynray(&args)
    };
    for strategy in ["megakernel", "hybrid"] {
        refused_as_usage(with(&["--integrator", "path", "--gpu-strategy", strategy]), "--gpu-strategy wavefront only");
    }
    refused_as_usage(with(&["--accel", "bih"]), "the GPU backend traverses a BVH only");
    // The wide tree's parameters do not describe the binary tree the GPU traverses.
    refused_as_usage(with(&["--accel", "bvh:width=4"]), "as `bvh2:…`");
    assert!(!out.exists(), "a refused render left an image");
}

/// `--integrator path --backend gpu` through the binary. On Mitsuba's sphere at depth 2
/// (one point light, direct light only) the path tracer draws no number that matters
/// (one emitter to pick, no continuation), so the GPU's image is the CPU's up to f32
/// rounding: the same camera rays (the CPU sampler's positions), clip planes, BSDF and
/// shadow rays. The statistical checks of the rest are crates/gpu/tests/path_tracer.rs.
#[test]
fn the_path_tracer_renders_the_cpus_direct_light() {
    if !gpu_present() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = support::root().join("../shared/reference/sphere/sphere_d2.xml");
    let args = ["--integrator", "path"];
    let cpu = render_exr(Some(&scene), &args, &dir.path().join("cpu.exr"));
    let mut gpu_args = args.to_vec();
    gpu_args.extend_from_slice(&["--backend", "gpu", "--gpu-strategy", "wavefront"]);
    let gpu = render_exr(Some(&scene), &gpu_args, &dir.path().join("gpu.exr"));
    assert!(cpu.iter().any(|&v| v > 0.1), "the CPU image is black");
    let worst = max_abs_difference(&cpu, &gpu);
    eprintln!("sphere_d2, path: largest channel difference GPU vs CPU {worst:.2e}");
    assert!(worst <= 1e-3, "sphere_d2, path: largest channel difference {worst}");
}
