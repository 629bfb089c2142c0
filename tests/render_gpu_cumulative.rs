//! `dynray render --integrator cumulative --backend gpu`: seed 004's cumulative tracer in
//! the GPU wavefront (docs/gpu.md). At full branch depth it is Whitted's image; below it
//! the GPU hashes the CPU's numbers (`dynray_render::choice_random`) and picks the CPU's
//! children, so CPU and GPU cumulative images agree pass for pass, and the passes
//! converge to Whitted's image. Skips without an adapter unless `DYNRAY_REQUIRE_GPU=1`.

mod support;

use std::path::Path;
use support::{dynray, examples_dir, gpu_present, max_abs_difference, ok, read_exr_channels, refused_as_usage};

/// Largest per-channel difference allowed where CPU and GPU trace the same paths: f32
/// shading in another rounding (tests/render_gpu_cli.rs uses the same bound).
const TOLERANCE: f32 = 1e-4;

fn render_exr(scene: Option<&Path>, extra: &[&str], out: &Path) -> Vec<f32> {
    let mut args = vec!["render", "-o", out.to_str().unwrap(), "--width", "48", "--height", "36"];
    if let Some(s) = scene {
        args.insert(1, s.to_str().unwrap());
    }
    args.extend_from_slice(extra);
    if !extra.contains(&"--spp") {
        args.extend_from_slice(&["--spp", "1"]);
    }
    ok(dynray(&args));
    read_exr_channels(out)
}

fn rmse(a: &[f32], b: &[f32]) -> f64 {
    let s: f64 = a.iter().zip(b).map(|(x, y)| ((x - y) as f64).powi(2)).sum();
    (s / a.len() as f64).sqrt()
}

const GPU: [&str; 4] = ["--backend", "gpu", "--gpu-strategy", "wavefront"];

/// K ≥ the scenes' level limit: nothing is chosen, the GPU's image is Whitted's.
#[test]
fn full_branch_depth_on_the_gpu_is_whitteds_image() {
    if !gpu_present() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let whitted = examples_dir().join("whitted.scn");
    for (name, scene) in [("demo", None), ("whitted", Some(whitted.as_path()))] {
        let cpu = render_exr(scene, &[], &dir.path().join(format!("{name}-cpu.exr")));
        assert!(cpu.iter().any(|&v| v > 0.05), "{name}: the CPU image is black");
        let mut args = GPU.to_vec();
        args.extend_from_slice(&["--integrator", "cumulative", "--branch-depth", "30"]);
        let gpu = render_exr(scene, &args, &dir.path().join(format!("{name}-gpu.exr")));
        let w = max_abs_difference(&cpu, &gpu);
        eprintln!("{name}: GPU cumulative (K = 30) against CPU Whitted: largest channel difference {w:.3e}");
        assert!(w <= TOLERANCE, "{name}: largest channel difference {w}");
    }
}

/// K = 0, every glass hit chooses: the GPU draws the CPU's numbers, so its image is the
/// CPU cumulative's after 1 and 4 passes; and its error against Whitted's image falls
/// with passes (1/√N: 0.6× per 4× allowed where 0.5× is expected).
#[test]
fn choices_are_the_cpus_and_passes_converge() {
    if !gpu_present() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = examples_dir().join("whitted.scn");
    let scene = Some(scene.as_path());
    let whitted = render_exr(scene, &[], &dir.path().join("whitted.exr"));
    let mut errors = Vec::new();
    for passes in ["1", "4", "16"] {
        let c = ["--integrator", "cumulative", "--branch-depth", "0", "--passes", passes, "--seed", "3"];
        let gpu_args: Vec<&str> = GPU.iter().chain(&c).copied().collect();
        let gpu = render_exr(scene, &gpu_args, &dir.path().join(format!("gpu-{passes}.exr")));
        if passes != "16" {
            let cpu = render_exr(scene, &c, &dir.path().join(format!("cpu-{passes}.exr")));
            let w = max_abs_difference(&cpu, &gpu);
            eprintln!("K = 0, {passes} passes: GPU against CPU cumulative: largest channel difference {w:.3e}");
            assert!(w <= TOLERANCE, "{passes} passes: the GPU chose other children (difference {w})");
        }
        errors.push(rmse(&gpu, &whitted));
    }
    eprintln!("K = 0 on the GPU, RMSE against Whitted after 1, 4, 16 passes: {errors:?}");
    let e = errors;
    assert!(e[0] > 1e-3, "one pass must be noisy: {e:?}");
    assert!(e[1] < 0.6 * e[0] && e[2] < 0.6 * e[1], "RMSE by passes 1, 4, 16: {e:?}");
}

/// K = 1 with 2 samples per pixel and 2 passes: expanded paths are numbered `2·id + i`,
/// each sample of a pixel and each pass has its own key, and the GPU still picks the
/// CPU's children (the demo's glass and mirrors choose past the first bounce).
#[test]
fn expanded_paths_and_samples_choose_as_on_the_cpu() {
    if !gpu_present() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let whitted = examples_dir().join("whitted.scn");
    for (name, scene) in [("demo", None), ("whitted", Some(whitted.as_path()))] {
        let c = ["--integrator", "cumulative", "--branch-depth", "1", "--spp", "2", "--passes", "2"];
        let gpu_args: Vec<&str> = GPU.iter().chain(&c).copied().collect();
        let gpu = render_exr(scene, &gpu_args, &dir.path().join(format!("{name}-gpu.exr")));
        let cpu = render_exr(scene, &c, &dir.path().join(format!("{name}-cpu.exr")));
        let full = render_exr(scene, &["--spp", "2"], &dir.path().join(format!("{name}-whitted.exr")));
        let w = max_abs_difference(&cpu, &gpu);
        eprintln!("{name}, K = 1, 2 spp × 2 passes: GPU against CPU cumulative: largest difference {w:.3e}");
        assert!(max_abs_difference(&cpu, &full) > 1e-2, "{name}: K = 1 must choose somewhere");
        assert!(w <= TOLERANCE, "{name}: the GPU chose other children (difference {w})");
    }
}

#[test]
fn cumulative_on_other_strategies_is_refused() {
    if !gpu_present() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let o = out.to_str().unwrap();
    for strategy in ["megakernel", "hybrid"] {
        let args = ["render", "-o", o, "--backend", "gpu", "--gpu-strategy", strategy, "--integrator", "cumulative"];
        refused_as_usage(dynray(&args), "--gpu-strategy wavefront only");
    }
    assert!(!out.exists(), "a refused render left an image");
}
