//! `dynray bench --backend gpu` through the binary: the standard run measures the GPU
//! backend on the CPU's rays (same hits as the CPU rows, every ray checked against brute
//! force, with the tree built on the CPU and on the device), and `--preset seed003` adds
//! the seed's GPU tables (three strategies per level and sweep point, Table 4.9's
//! builds), each figure consistent with the others. Skips without an adapter unless
//! `DYNRAY_REQUIRE_GPU=1` (CI).

mod support;

use serde_json::Value;
use std::path::Path;
use support::{dynray, gpu_present, ok};

fn bench(out: &Path, extra: &[&str]) -> Value {
    let mut args = vec!["bench", "--quick", "--backend", "gpu", "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    ok(dynray(&args));
    let report: Value = serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["mismatches"].as_array().map(Vec::len), Some(0), "{}", report["mismatches"]);
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("| GPU | "), "report.md names no GPU");
    report
}

fn num(v: &Value) -> f64 {
    v.as_f64().filter(|x| x.is_finite()).unwrap_or(f64::NAN)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

#[test]
fn the_standard_run_measures_the_gpu_on_the_same_rays() {
    if !gpu_present() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    for build in ["cpu", "lbvh"] {
        let out = tmp.path().join(build);
        // `bvh2`, the binary tree the GPU traverses, so the CPU's row is the uploaded tree.
        let r = bench(&out, &["--scenes", "dragon-res4", "--accels", "bvh2", "--gpu-build", build]);
        assert_eq!(r["gpu"]["build"], build);
        assert!(r["gpu"]["adapter"].as_str().is_some_and(|a| !a.is_empty()), "{}", r["gpu"]);
        assert!(matches!(r["gpu"]["precision"].as_str(), Some("f64" | "f32")), "{}", r["gpu"]);
        let sc = &r["scenes"][0];
        let (cpu, gpu) = (&sc["structures"][0], &sc["gpu"][0]);
        assert_eq!(sc["gpu"].as_array().map(Vec::len), Some(1), "{build}: {}", sc["gpu"]);
        assert_eq!(gpu["accel"], "bvh2");
        assert!(num(&gpu["build_ms"]) > 0.0 && num(&gpu["time_to_image_ms"]) > 0.0, "{build}: {gpu}");
        assert!(gpu["nodes"].as_u64().is_some_and(|n| n > 0));
        if build == "cpu" {
            // The CPU's tree, uploaded: the same shape.
            assert_eq!(gpu["nodes"], cpu["nodes"]);
        }
        let extra = gpu["extra"].as_array().unwrap();
        assert!(extra.iter().any(|e| e[0] == "backend" && e[1] == "gpu"), "{build}: {extra:?}");
        let kinds = gpu["kinds"].as_array().unwrap();
        assert_eq!(kinds.len(), r["config"]["rays"].as_array().unwrap().len());
        for (g, c) in kinds.iter().zip(cpu["kinds"].as_array().unwrap()) {
            assert_eq!(g["kind"], c["kind"]);
            // Exact hits: the GPU finds what the CPU finds, and --quick checks every ray.
            assert_eq!(g["hits"], c["hits"], "{build} {}", g["kind"]);
            assert_eq!(g["verified"], g["rays"], "{build} {}", g["kind"]);
            assert!(num(&g["mrays_per_s"]) > 0.0 && num(&g["nodes_per_ray"]) > 0.0, "{build}: {g}");
        }
    }
}

#[test]
fn seed003_gains_the_gpu_tables() {
    if !gpu_present() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let r = bench(tmp.path(), &["--preset", "seed003", "--scenes", "cornell-box"]);
    let s = &r["seed003"];
    assert_eq!(s["gpu_adapter"], r["gpu"]["adapter"]);
    let strategies = |runs: &Value, single: f64, what: &str| {
        let runs = runs.as_array().unwrap();
        let names: Vec<&str> = runs.iter().filter_map(|x| x["strategy"].as_str()).collect();
        assert_eq!(names, ["wavefront", "megakernel", "hybrid"], "{what}");
        for x in runs {
            let ms = num(&x["ms"]);
            assert!(ms > 0.0 && close(num(&x["speedup"]), single / ms), "{what}: {x}");
            assert!(x["images_agree"] == true && num(&x["max_abs_diff"]) < 1e-3, "{what}: {x}");
            assert!(x["rays"].as_u64().is_some_and(|n| n > 0), "{what}: {x}");
        }
    };
    let sc = &s["scenes"][0];
    let levels = sc["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 10);
    for l in levels {
        strategies(&l["gpu"], num(&l["accel_single_ms"]), &format!("level {}", l["level"]));
    }
    for q in s["sweeps"]["lights"].as_array().unwrap().iter().chain(s["sweeps"]["resolution"].as_array().unwrap()) {
        strategies(&q["gpu"], num(&q["single_ms"]), &format!("sweep {q}"));
    }
    let cpu = num(&sc["cpu_single_build_ms"]);
    assert!(cpu > 0.0, "{sc}");
    let builds = sc["gpu_builds"].as_array().unwrap();
    let names: Vec<&str> = builds.iter().filter_map(|b| b["build"].as_str()).collect();
    assert_eq!(names, ["sah", "lbvh", "cpu"]);
    for b in builds {
        let ms = num(&b["ms"]);
        assert!(ms > 0.0 && close(num(&b["cpu_over_this"]), cpu / ms), "{b}");
        assert!(b["nodes"].as_u64().is_some_and(|n| n > 0) && num(&b["sah_cost"]) > 0.0, "{b}");
        assert!(!b["stages"].as_array().unwrap().is_empty(), "{b}");
    }
}

#[test]
fn seed001_measures_the_field_on_the_device_with_the_cpus_answers() {
    if !gpu_present() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let r = bench(tmp.path(), &["--preset", "seed001"]);
    let s = &r["seed001"];
    assert_eq!(s["gpu_adapter"], r["gpu"]["adapter"]);
    for f in s["runs"].as_array().unwrap() {
        let (cpu, gpu) = (f["locate_cpu"].as_array().unwrap(), f["locate_gpu"].as_array().unwrap());
        assert_eq!(gpu.len(), 3, "{f}");
        for (c, g) in cpu.iter().zip(gpu) {
            // Point location is integer work: the same points cost the same probes.
            assert_eq!(c["search"], g["search"]);
            assert_eq!(c["probes_per_lookup"], g["probes_per_lookup"], "{c} / {g}");
            assert!(num(&g["ms"]) > 0.0, "{g}");
        }
        let march = f["march_gpu"].as_array().unwrap();
        assert!(march.len() == 3 && march.iter().all(|m| num(&m["mega_per_s"]) > 0.0), "{f}");
        let rays = (s["width"].as_u64().unwrap() * s["height"].as_u64().unwrap()) as f64;
        let differ = f["gpu_differences"].as_u64().expect("compared with the CPU") as f64;
        assert!(differ <= 1e-3 * rays, "{differ} of {rays} device answers differ from the CPU's");
    }
}
