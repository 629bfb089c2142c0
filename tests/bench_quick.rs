//! `dynray bench --quick --preset all`, the command `.ci/run`'s smoke test relies on: it
//! succeeds, and the `report.json` it writes is complete and consistent with the schema
//! of docs/bench.md (every section, every structure on every ray kind, counts that add
//! up, ratios that name measured structures, no disagreement with brute force).

mod support;

use serde_json::Value;
use std::path::Path;
use std::process::Command;

const PRESETS: [&str; 8] = ["standard", "seed000", "seed001", "seed002", "seed003", "seed004", "dynamic", "path"];

/// Problems found in a report; empty when it is complete and consistent.
fn check_report(r: &Value) -> Vec<String> {
    let mut p = Vec::new();
    need(&mut p, r["schema"] == 1, "schema is not 1".into());
    need(&mut p, r["machine"]["cpu"].is_string(), "machine.cpu missing".into());
    need(&mut p, r["threads"].as_u64().is_some_and(|t| t > 0), "threads missing".into());
    for k in ["started_utc", "finished_utc", "dynray_version"] {
        need(&mut p, r[k].as_str().is_some_and(|s| !s.is_empty()), format!("{k} missing"));
    }
    let presets: Vec<&str> =
        r["config"]["presets"].as_array().into_iter().flatten().filter_map(Value::as_str).collect();
    need(&mut p, presets == PRESETS, format!("config.presets is {presets:?}"));
    need(&mut p, r["mismatches"].as_array().is_some_and(Vec::is_empty), "disagreements with brute force".into());
    let repeat = r["config"]["repeat"].as_u64().unwrap_or(0) as usize;
    let rays: Vec<&str> = r["config"]["rays"].as_array().into_iter().flatten().filter_map(Value::as_str).collect();
    let accels = r["config"]["accels"].as_array().map_or(0, Vec::len);

    let scenes = r["scenes"].as_array().cloned().unwrap_or_default();
    need(&mut p, !scenes.is_empty(), "standard: no scene".into());
    check_seed001(&r["seed001"], &mut p);
    check_seed000_physics(&r["seed000_physics"], &mut p);
    for sc in &scenes {
        check_scene(sc, &rays, repeat, true, &mut p);
        let n = sc["structures"].as_array().map_or(0, Vec::len);
        need(&mut p, n == accels, format!("standard {}: {n} structures, config names {accels}", sc["name"]));
        // The wide BVH traces primary rays in packets too (docs/bench.md, "Packets").
        let packets = sc["structures"].as_array().into_iter().flatten().filter(|s| !s["primary_packets"].is_null());
        need(&mut p, packets.count() > 0, format!("standard {}: no structure measured in packets", sc["name"]));
    }
    for preset in ["seed000", "seed002", "seed004"] {
        let s = &r[preset];
        let kinds: Vec<&str> = s["rays"].as_array().into_iter().flatten().filter_map(Value::as_str).collect();
        let Some(scenes) = s["scenes"].as_array().filter(|v| !v.is_empty()) else {
            p.push(format!("{preset}: missing or empty"));
            continue;
        };
        for sc in scenes {
            check_scene(sc, &kinds, repeat, preset == "seed000", &mut p);
        }
        let ratios = s["ratios"].as_array().cloned().unwrap_or_default();
        need(&mut p, !ratios.is_empty(), format!("{preset}: no ratio"));
        for q in &ratios {
            let sc = scenes.iter().find(|sc| sc["name"] == q["scene"]);
            let has = |label: &Value| {
                sc.and_then(|sc| sc["structures"].as_array()).is_some_and(|v| v.iter().any(|s| s["accel"] == *label))
            };
            need(
                &mut p,
                has(&q["baseline"]) && has(&q["candidate"]),
                format!("{preset}: ratio names unknown structures: {q}"),
            );
            let (b, c, x) = (num(&q["baseline_value"]), num(&q["candidate_value"]), num(&q["speedup"]));
            need(
                &mut p,
                b > 0.0 && c > 0.0 && ((b / c) - x).abs() <= 1e-9 * x,
                format!("{preset}: inconsistent ratio {q}"),
            );
        }
    }
    // seed004's renderer comparison: cumulative against recursive Whitted per structure.
    let rr = &r["seed004_renderers"];
    let runs = rr["runs"].as_array().cloned().unwrap_or_default();
    let accels: Vec<&str> = runs.iter().filter_map(|x| x["accel"].as_str()).collect();
    need(
        &mut p,
        accels == ["apit:resolution=64", "abuffer:resolution=64", "bvh"],
        format!("seed004_renderers: structures {accels:?}"),
    );
    for x in &runs {
        let ok = x["images_identical"] == true
            && num(&x["full_branch_max_rel_diff"]) <= 1e-5
            && [&x["whitted_ms"], &x["full_branch_ms"], &x["pass_ms"], &x["build_ms"], &x["rmse"]]
                .iter()
                .all(|v| num(v) > 0.0)
            && x["pass_rays"].as_u64().is_some_and(|n| n > 0)
            && x["whitted_rays"].as_u64().is_some_and(|n| n > 0);
        need(&mut p, ok, format!("seed004_renderers: inconsistent run {x}"));
    }
    let conv: Vec<f64> = rr["convergence"].as_array().into_iter().flatten().map(|q| num(&q["rmse"])).collect();
    let passes = rr["passes"].as_u64().unwrap_or(0) as usize;
    need(
        &mut p,
        passes > 1 && conv.len() == passes && conv.iter().all(|e| *e > 0.0) && conv[passes - 1] < conv[0],
        format!("seed004_renderers: convergence {conv:?} over {passes} passes"),
    );
    check_path(&r["path"], &mut p);
    match r["seed003"]["scenes"].as_array() {
        Some(scenes) if !scenes.is_empty() => {
            for sc in scenes {
                let levels = sc["levels"].as_array().cloned().unwrap_or_default();
                need(&mut p, levels.len() == 10, format!("seed003 {}: {} levels", sc["name"], levels.len()));
                for (i, l) in levels.iter().enumerate() {
                    need(&mut p, l["level"] == i + 1, format!("seed003: level {} out of order", l["level"]));
                    need(
                        &mut p,
                        l["images_identical"] == true,
                        format!("seed003 {} level {}: images differ", sc["name"], i + 1),
                    );
                    let (s1, sn, sp) = (num(&l["accel_single_ms"]), num(&l["accel_parallel_ms"]), num(&l["speedup"]));
                    need(
                        &mut p,
                        sn > 0.0 && ((s1 / sn) - sp).abs() <= 1e-9 * sp,
                        format!("seed003: inconsistent SP {l}"),
                    );
                    need(&mut p, l["rays"].as_u64().is_some_and(|n| n > 0), format!("seed003: no rays {l}"));
                }
            }
        }
        _ => p.push("seed003: missing or empty".into()),
    }
    // The lights and image-size sweeps (quick: 1 and 4 lights, 48² and 64²).
    let sweeps = &r["seed003"]["sweeps"];
    let points = |k: &str| sweeps[k].as_array().cloned().unwrap_or_default();
    let lights: Vec<u64> = points("lights").iter().filter_map(|q| q["lights"].as_u64()).collect();
    need(&mut p, lights == [1, 4], format!("seed003 sweeps: light counts {lights:?}"));
    let sides: Vec<(u64, u64)> =
        points("resolution").iter().filter_map(|q| Some((q["width"].as_u64()?, q["height"].as_u64()?))).collect();
    need(&mut p, sides == [(48, 48), (64, 64)], format!("seed003 sweeps: image sizes {sides:?}"));
    for q in points("lights").iter().chain(&points("resolution")) {
        let (s1, sn, sp) = (num(&q["single_ms"]), num(&q["parallel_ms"]), num(&q["speedup"]));
        need(&mut p, sn > 0.0 && ((s1 / sn) - sp).abs() <= 1e-9 * sp, format!("seed003 sweep: inconsistent SP {q}"));
        need(&mut p, q["images_identical"] == true, format!("seed003 sweep: images differ {q}"));
    }
    // More lights, more shadow rays: every light adds one per primary hit.
    let rays: Vec<u64> = points("lights").iter().filter_map(|q| q["rays"].as_u64()).collect();
    need(&mut p, rays.len() == 2 && rays[0] < rays[1], format!("seed003 sweeps: rays by lights {rays:?}"));
    let frames = r["dynamic"]["frames"].as_u64().unwrap_or(0) as usize;
    match r["dynamic"]["runs"].as_array() {
        Some(runs) if !runs.is_empty() && frames > 0 => {
            for run in runs {
                for series in ["rebuild_ms", "update_ms", "trace_ms", "fresh_trace_ms", "time_to_image_ms"] {
                    let v = run[series].as_array().cloned().unwrap_or_default();
                    need(
                        &mut p,
                        v.len() == frames && v.iter().all(|x| num(x) >= 0.0),
                        format!(
                            "dynamic {} {}: {series} has {} of {frames} frames",
                            run["scene"],
                            run["accel"],
                            v.len()
                        ),
                    );
                }
                need(
                    &mut p,
                    run["verified"].as_u64().is_some_and(|n| n > 0),
                    format!("dynamic {}: nothing verified", run["accel"]),
                );
                // Refitting structures (BVH, BIH) report their drift every frame.
                let sah = run["sah_ratio"].as_array().cloned().unwrap_or_default();
                let want = if run["refits"] == true { frames } else { 0 };
                need(
                    &mut p,
                    sah.len() == want && sah.iter().all(|x| num(x) > 0.0),
                    format!("dynamic {} {}: sah_ratio has {} of {want} frames", run["scene"], run["accel"], sah.len()),
                );
                need(
                    &mut p,
                    matches!(run["motion"].as_str(), Some("wave" | "animation")),
                    format!("dynamic {}: motion {}", run["scene"], run["motion"]),
                );
            }
        }
        _ => p.push("dynamic: missing or empty".into()),
    }
    // Layouts and policies (quick: the small carousel and BART's robots, every structure
    // in both layouts, the refitting ones under three policies).
    match r["dynamic"]["layouts"].as_array() {
        Some(runs) if !runs.is_empty() => {
            for run in runs {
                let what =
                    format!("dynamic layouts {} {} {} {}", run["scene"], run["accel"], run["layout"], run["policy"]);
                for series in ["update_ms", "trace_ms", "time_to_image_ms", "actions", "cost_ratio"] {
                    let n = run[series].as_array().map_or(0, |v| v.len());
                    need(&mut p, n == frames, format!("{what}: {series} has {n} of {frames} frames"));
                }
                let actions = run["actions"].as_array().cloned().unwrap_or_default();
                need(
                    &mut p,
                    actions.iter().all(|a| matches!(a.as_str(), Some("kept" | "refit" | "rebuilt" | "moved"))),
                    format!("{what}: actions {actions:?}"),
                );
                need(&mut p, run["verified"].as_u64().is_some_and(|n| n > 0), format!("{what}: nothing verified"));
                need(
                    &mut p,
                    matches!(run["layout"].as_str(), Some("flat" | "instanced")),
                    format!("{what}: unknown layout"),
                );
            }
            // The carousel's eight moving copies share one part: instances only move.
            let carousel = runs.iter().find(|r| {
                r["scene"] == "carousel-small"
                    && r["accel"] == "bvh"
                    && r["layout"] == "instanced"
                    && r["policy"] == "refit"
            });
            match carousel {
                Some(c) => {
                    need(
                        &mut p,
                        c["parts"] == 2 && c["instances"] == 9,
                        format!("carousel: {} parts, {} instances", c["parts"], c["instances"]),
                    );
                    let moved = c["actions"].as_array().map_or(0, |a| a.iter().filter(|x| *x == "moved").count());
                    need(&mut p, moved + 1 == frames, format!("carousel: {moved} frames of moved instances"));
                }
                None => p.push("dynamic layouts: no instanced bvh run of carousel-small".into()),
            }
        }
        _ => p.push("dynamic layouts: missing or empty".into()),
    }
    p
}

/// `--preset seed001`: every field's tables, memory, three searches on each measurement
/// with the same answers' costs consistent (probes per lookup ≥ 1 on the march, binary
/// never above linear on random points), positive speeds and finite errors.
fn check_seed001(s: &Value, p: &mut Vec<String>) {
    let Some(runs) = s["runs"].as_array().filter(|v| !v.is_empty()) else {
        p.push("seed001: missing or empty".into());
        return;
    };
    for f in runs {
        let what = format!("seed001 {} level {}", f["scene"], f["max_level"]);
        let bytes: Vec<u64> = f["bytes"].as_array().into_iter().flatten().filter_map(Value::as_u64).collect();
        need(
            p,
            bytes.len() == 5 && bytes[..4].iter().all(|&b| b > 0) && bytes[..4].iter().sum::<u64>() == bytes[4],
            format!("{what}: bytes {bytes:?} do not add up"),
        );
        need(
            p,
            num(&f["build_ms"]) > 0.0 && num(&f["hash_ms"]) > 0.0 && f["internal_cells"].as_u64() < f["cells"].as_u64(),
            format!("{what}: build figures {f}"),
        );
        for key in ["locate_cpu", "march_cpu"] {
            let costs = f[key].as_array().cloned().unwrap_or_default();
            let names: Vec<&str> = costs.iter().filter_map(|c| c["search"].as_str()).collect();
            need(p, names == ["linear", "binary", "coherent"], format!("{what}: {key} searches {names:?}"));
            need(
                p,
                costs
                    .iter()
                    .all(|c| num(&c["ms"]) > 0.0 && num(&c["mega_per_s"]) > 0.0 && num(&c["probes_per_lookup"]) > 0.0),
                format!("{what}: {key} figures {costs:?}"),
            );
        }
        let e: Vec<f64> = f["error_near"].as_array().into_iter().flatten().map(num).collect();
        need(p, e.len() == 3 && e[0] <= e[1] && e[1] <= e[2] && e[2].is_finite(), format!("{what}: errors {e:?}"));
        need(p, f["hits"].as_u64().is_some_and(|h| h > 0), format!("{what}: no primary ray hits the field"));
    }
}

/// `--preset seed000`'s dynamic scenario: ten structures, every series one entry per
/// frame, time to image = physics + update + render, totals that add up, rays checked.
fn check_seed000_physics(s: &Value, p: &mut Vec<String>) {
    let frames = s["frames"].as_u64().unwrap_or(0) as usize;
    let physics: Vec<f64> = s["physics_ms"].as_array().into_iter().flatten().map(num).collect();
    need(
        p,
        frames > 0 && physics.len() == frames,
        format!("seed000 physics: {} physics times for {frames} frames", physics.len()),
    );
    let runs = s["runs"].as_array().cloned().unwrap_or_default();
    need(p, runs.len() == 10, format!("seed000 physics: {} structures, not 10", runs.len()));
    for r in &runs {
        let what = format!("seed000 physics {}", r["accel"]);
        let series = |k: &str| -> Vec<f64> { r[k].as_array().into_iter().flatten().map(num).collect() };
        let (up, render, tti) = (series("update_ms"), series("render_ms"), series("time_to_image_ms"));
        let lens = [up.len(), series("trace_ms").len(), render.len(), tti.len()];
        need(p, lens.iter().all(|&n| n == frames), format!("{what}: series lengths {lens:?}"));
        let adds_up = (0..tti.len().min(up.len()).min(render.len()).min(physics.len()))
            .all(|i| (tti[i] - (physics[i] + up[i] + render[i])).abs() <= 1e-6 * tti[i].max(1.0));
        let total = (num(&r["total_time_to_image_ms"]) - tti.iter().sum::<f64>()).abs()
            <= 1e-6 * num(&r["total_time_to_image_ms"]);
        need(p, adds_up && total, format!("{what}: time to image does not add up"));
        need(p, r["verified"].as_u64().is_some_and(|v| v > 0), format!("{what}: no ray checked"));
    }
}

/// Records `what` when `ok` is false.
/// `--preset path`: every structure's image identical, speeds and errors positive, the
/// convergence at 1, 2, 4, … spp with its error falling and Mitsuba's estimate beside it.
fn check_path(path: &Value, p: &mut Vec<String>) {
    let Some(scenes) = path["scenes"].as_array().filter(|v| !v.is_empty()) else {
        p.push("path: missing or empty".into());
        return;
    };
    for sc in scenes {
        let name = &sc["name"];
        let runs = sc["runs"].as_array().cloned().unwrap_or_default();
        need(p, !runs.is_empty(), format!("path {name}: no run"));
        for x in &runs {
            let ok = x["image_identical"] == true
                && [&x["build_ms"], &x["render_ms"], &x["samples_per_s"], &x["mrays_per_s"], &x["rmse"]]
                    .iter()
                    .all(|v| num(v) > 0.0)
                && x["rays"].as_u64().is_some_and(|n| n > 0);
            need(p, ok, format!("path {name}: inconsistent run {x}"));
        }
        let conv = sc["convergence"].as_array().cloned().unwrap_or_default();
        let spp: Vec<u64> = conv.iter().filter_map(|q| q["spp"].as_u64()).collect();
        let want: Vec<u64> = (0..conv.len() as u32).map(|k| 1 << k).collect();
        need(p, conv.len() > 1 && spp == want, format!("path {name}: convergence spp {spp:?}"));
        let err: Vec<f64> = conv.iter().map(|q| num(&q["rmse"])).collect();
        need(
            p,
            err.iter().all(|e| *e > 0.0) && err.last() < err.first() && conv.iter().all(|q| num(&q["ms"]) > 0.0),
            format!("path {name}: convergence errors {err:?}"),
        );
        need(p, conv.iter().all(|q| num(&q["mitsuba_ms"]) > 0.0), format!("path {name}: Mitsuba's times missing"));
        let m = &sc["mitsuba"];
        need(
            p,
            m["spp"] == 4096 && num(&m["render_s"]) > 0.0 && num(&m["rms_pixel_std"]) > 0.0,
            format!("path {name}: Mitsuba's figures {m}"),
        );
    }
}

fn need(p: &mut Vec<String>, ok: bool, what: String) {
    if !ok {
        p.push(what);
    }
}

fn num(v: &Value) -> f64 {
    v.as_f64().filter(|x| x.is_finite()).unwrap_or(f64::NAN)
}

/// One scene of the standard run or a study: every structure measured on every `kinds`,
/// counts consistent with the scene's ray counts, repetitions as configured.
fn check_scene(sc: &Value, kinds: &[&str], repeat: usize, time_to_image: bool, p: &mut Vec<String>) {
    let name = sc["name"].as_str().unwrap_or("?");
    let counts: Vec<(&str, u64)> = sc["ray_counts"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|c| Some((c["kind"].as_str()?, c["rays"].as_u64()?)))
        .collect();
    if counts.iter().map(|c| c.0).collect::<Vec<_>>() != kinds {
        p.push(format!("{name}: ray kinds {counts:?}, expected {kinds:?}"));
    }
    if sc["triangles"].as_u64().unwrap_or(0) == 0 {
        p.push(format!("{name}: no triangles"));
    }
    for s in sc["structures"].as_array().into_iter().flatten() {
        let label = format!("{name} / {}", s["accel"]);
        let brute = s["accel"] == "brute";
        if !(num(&s["build_ms"]) >= 0.0 && s["build_ms_runs"].as_array().is_some_and(|v| v.len() == repeat)) {
            p.push(format!("{label}: build times"));
        }
        if s["memory_bytes"].as_u64().unwrap_or(0) == 0 {
            p.push(format!("{label}: no memory figure"));
        }
        if time_to_image != (num(&s["time_to_image_ms"]) > 0.0) {
            p.push(format!("{label}: time to image {} (expected: {time_to_image})", s["time_to_image_ms"]));
        }
        let measured: Vec<&Value> = s["kinds"].as_array().into_iter().flatten().collect();
        if measured.len() != counts.len() {
            p.push(format!("{label}: {} ray kinds measured of {}", measured.len(), counts.len()));
        }
        for (k, (kind, rays)) in measured.iter().zip(&counts) {
            // The hitting and escaping rays' mean work, weighted by their numbers, is the
            // mean over every ray. (A shadow ray is occluded exactly when its closest-hit
            // query, which the counted pass runs, finds a hit.)
            let split = |w: &Value| (!w.is_null()).then(|| (num(&w["nodes"]), num(&w["triangles"])));
            let (hw, ew) = (split(&k["hit_work"]), split(&k["escaped_work"]));
            let n = *rays as f64;
            let hitting = k["hits"].as_u64().map(|h| h as f64);
            let mean = (num(&k["nodes_per_ray"]), num(&k["triangles_per_ray"]));
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * b.abs().max(1.0);
            let weighted = |h: (f64, f64), e: (f64, f64), nh: f64| {
                close((h.0 * nh + e.0 * (n - nh)) / n, mean.0) && close((h.1 * nh + e.1 * (n - nh)) / n, mean.1)
            };
            let split_ok = match (hw, ew, hitting) {
                (Some(h), Some(e), Some(nh)) => nh > 0.0 && nh < n && weighted(h, e, nh),
                (Some(h), None, Some(nh)) => nh == n && weighted(h, (0.0, 0.0), nh),
                (None, Some(e), Some(nh)) => nh == 0.0 && weighted((0.0, 0.0), e, nh),
                (None, None, Some(_)) => n == 0.0,
                _ => false,
            };
            if !split_ok {
                p.push(format!("{label}: {kind} hit/escaped work does not add up to the mean: {k}"));
            }
            let ok = k["kind"] == *kind
                && k["rays"] == *rays
                && k["trace_ms_runs"].as_array().is_some_and(|v| v.len() == repeat)
                && num(&k["mrays_per_s"]) > 0.0
                && num(&k["nodes_per_ray"]) >= 0.0
                && num(&k["triangles_per_ray"]) >= 0.0
                && k["hits"].as_u64().is_some_and(|h| h <= *rays)
                && (brute || k["verified"] == *rays);
            if !ok {
                p.push(format!("{label}: inconsistent {kind} figures {k}"));
            }
        }
        // The packet pass: the primary rays again, the same hits, every ray checked.
        let pk = &s["primary_packets"];
        if !pk.is_null() {
            let primary = measured.iter().find(|k| k["kind"] == "primary");
            let ok = primary.is_some_and(|pr| {
                pk["kind"] == "primary-packet"
                    && pk["rays"] == pr["rays"]
                    && pk["hits"] == pr["hits"]
                    && pk["verified"] == pr["verified"]
                    && pk["trace_ms_runs"].as_array().is_some_and(|v| v.len() == repeat)
                    && num(&pk["mrays_per_s"]) > 0.0
            });
            if !ok {
                p.push(format!("{label}: inconsistent packet figures {pk}"));
            }
        }
    }
}

#[test]
fn quick_bench_of_every_preset_writes_a_complete_consistent_report() {
    let out = tempfile::tempdir().unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_dynray"))
        .args(["bench", "--quick", "--preset", "all", "--no-png", "--out"])
        .arg(out.path())
        .arg("--scenes-dir")
        .arg(support::scenes_dir())
        .status()
        .unwrap();
    assert!(status.success(), "dynray bench --quick --preset all failed: {status}");
    let json: Value = serde_json::from_slice(&std::fs::read(out.path().join("report.json")).unwrap()).unwrap();
    let problems = check_report(&json);
    assert!(problems.is_empty(), "report.json:\n{}", problems.join("\n"));
    // The checker sees damage to a real report: a wrong ratio, a lost ray kind, a frame,
    // hit/escaped work that no longer averages to the mean, a lost point of a sweep.
    let mut bad = json.clone();
    bad["seed004"]["ratios"][0]["speedup"] = 1e9.into();
    bad["scenes"][0]["structures"][0]["kinds"].as_array_mut().unwrap().pop();
    bad["dynamic"]["runs"][0]["trace_ms"].as_array_mut().unwrap().pop();
    let primary = &mut bad["scenes"][0]["structures"][1]["kinds"][0];
    let w = if primary["hit_work"].is_null() { "escaped_work" } else { "hit_work" };
    primary[w]["nodes"] = (primary[w]["nodes"].as_f64().unwrap() + 1.0).into();
    bad["seed003"]["sweeps"]["lights"].as_array_mut().unwrap().pop();
    let packets =
        bad["scenes"][1]["structures"].as_array_mut().unwrap().iter_mut().find(|s| !s["primary_packets"].is_null());
    packets.expect("a structure with packets")["primary_packets"]["hits"] = 0.into();
    bad["seed004_renderers"]["runs"][1]["images_identical"] = false.into();
    bad["path"]["scenes"][0]["convergence"].as_array_mut().unwrap().remove(1);
    bad["seed001"]["runs"][0]["bytes"][0] = 1.into();
    bad["seed000_physics"]["runs"][2]["render_ms"][0] = 1e9.into();
    bad["dynamic"]["layouts"][0]["actions"][1] = "teleported".into();
    let found = check_report(&bad).join("\n");
    for what in [
        "inconsistent ratio",
        "inconsistent packet figures",
        "ray kinds measured",
        "trace_ms has",
        "does not add up",
        "light counts",
        "inconsistent run",
        "convergence spp",
        "do not add up",
        "time to image does not add up",
        ": actions",
    ] {
        assert!(found.contains(what), "checker missed `{what}`:\n{found}");
    }
    let md = std::fs::read_to_string(out.path().join("report.md")).unwrap();
    for heading in [
        "## seed000",
        "### seed000: the dynamic scenario",
        "## seed001",
        "## seed002",
        "## seed003",
        "## seed004",
        "### seed004: cumulative",
        "## Preset dynamic",
        "### Scene layouts and update policies",
        "## Preset path",
    ] {
        assert!(md.contains(heading), "report.md lacks {heading}");
    }
    // Issue 48: throughput is read with the framing and the share of rays that hit.
    assert!(md.contains("| framing | scene: the scene's camera"), "{md}");
    assert!(md.contains("primary Mrays/s (") && md.contains("% hit) |"), "{md}");
    assert!(md.contains("% occluded"), "{md}");
    // --replot redraws from the JSON alone.
    std::fs::remove_file(out.path().join("report.md")).unwrap();
    std::fs::remove_file(out.path().join("seed004-speedup.svg")).unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_dynray"))
        .args(["bench", "--no-png", "--replot"])
        .arg(out.path())
        .status()
        .unwrap();
    assert!(status.success(), "--replot failed: {status}");
    assert_eq!(std::fs::read_to_string(out.path().join("report.md")).unwrap(), md, "--replot wrote another report.md");
    for chart in [
        "build-vs-triangles",
        "mrays",
        "seed000-sweep",
        "seed000-memory",
        "seed000-physics",
        "seed003-speedup",
        "seed004-speedup",
        "dynamic",
        "dynamic-layouts",
    ] {
        assert!(out.path().join(format!("{chart}.svg")).is_file(), "{chart}.svg missing");
    }
}

#[test]
fn the_checker_catches_an_incomplete_report() {
    let mut r: Value = serde_json::json!({"schema": 1, "scenes": []});
    assert!(check_report(&r).iter().any(|p| p.contains("standard: no scene")));
    r["schema"] = 2.into();
    assert!(check_report(&r).iter().any(|p| p.contains("schema")));
    assert!(Path::new(env!("CARGO_BIN_EXE_dynray")).is_file());
}
