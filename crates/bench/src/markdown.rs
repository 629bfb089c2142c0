//! `report.md`: the header (version, commit, CPU, threads, date) and one table per scene,
//! one row per structure, then the presets' tables.

use crate::format::{bytes, num, thousands, with_ratio};
use crate::presets::dynamic::Dynamic;
use crate::presets::experiment::markdown_of;
use crate::presets::path::PathTracer;
use crate::presets::seed000::Seed000;
use crate::presets::seed000_physics::Seed000PhysicsRun;
use crate::presets::seed001::Seed001;
use crate::presets::seed002::Seed002;
use crate::presets::seed003::Seed003;
use crate::presets::seed004::Seed004;
use crate::presets::seed004_renderers::Seed004RenderersRun;
use crate::report::Report;
use std::fmt::Write;

/// The "Side by side" tables of a scene (feature `compare`): our reference structure, then
/// every competitor with its figures and, in brackets, ours/theirs (> 1: ours is better).
fn side_by_side(s: &mut String, sc: &crate::results::SceneResult, rays: &[String]) {
    if sc.competitors.is_empty() {
        return;
    }
    let ours_name = sc.competitors.iter().find_map(|c| c.ours.clone());
    let _ = writeln!(
        s,
        "\nSide by side (same rays, same run; in brackets ours/theirs against our `{}`: \
         > 1 means ours is better — their ms or bytes over ours, our Mrays/s over theirs):\n",
        ours_name.as_deref().unwrap_or("bvh (not measured: no ratios)")
    );
    let mut head = "| library | variant | build ms | memory |".to_string();
    let mut rule = "|---|---|--:|--:|".to_string();
    for k in rays {
        let _ = write!(head, " {k} Mrays/s |");
        rule.push_str("--:|");
    }
    let _ = writeln!(s, "{head}\n{rule}");
    if let Some(o) = ours_name.as_ref().and_then(|n| sc.structures.iter().find(|st| &st.accel == n)) {
        let _ = write!(s, "| dynray (ours) | {} | {} | {} |", o.accel, num(o.build_ms), bytes(o.memory_bytes));
        for k in rays {
            let v = o.kinds.iter().find(|x| &x.kind == k).map(|x| num(x.mrays_per_s)).unwrap_or_else(|| "—".into());
            let _ = write!(s, " {v} |");
        }
        let _ = writeln!(s);
        // Our packet path, which packet variants are compared with.
        if let Some(p) = &o.primary_packets {
            let _ = write!(s, "| dynray (ours) | {} packets | | |", o.accel);
            for k in rays {
                let v = if k == "primary" { num(p.mrays_per_s) } else { "—".into() };
                let _ = write!(s, " {v} |");
            }
            let _ = writeln!(s);
        }
    }
    for c in &sc.competitors {
        let _ = write!(
            s,
            "| {} | {} | {} | {} |",
            c.name,
            c.variant,
            with_ratio(num(c.build_ms), c.ours_over_theirs_build),
            with_ratio(c.memory_bytes.map(bytes).unwrap_or_else(|| "—".into()), c.ours_over_theirs_memory)
        );
        for k in rays {
            let v = match c.kinds.iter().find(|x| &x.kind == k) {
                Some(x) => with_ratio(num(x.mrays_per_s), x.ours_over_theirs_speed),
                None => "—".into(),
            };
            let _ = write!(s, " {v} |");
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(
        s,
        "\nTheir answers against brute force on the checked rays: same triangle (shadow: same `occluded`) / \
         checked, and the largest relative `t` difference where the triangle is the same:\n"
    );
    let mut head = "| library | variant |".to_string();
    let mut rule = "|---|---|".to_string();
    for k in rays {
        let _ = write!(head, " {k} same / checked | {k} max rel. Δt |");
        rule.push_str("--:|--:|");
    }
    let _ = writeln!(s, "{head}\n{rule}");
    for c in &sc.competitors {
        let _ = write!(s, "| {} | {} |", c.name, c.variant);
        for k in rays {
            match c.kinds.iter().find(|x| &x.kind == k) {
                Some(x) => {
                    let _ = write!(
                        s,
                        " {} / {} ({:.3} %) | {:.1e} |",
                        thousands(x.same_answer as u64),
                        thousands(x.checked as u64),
                        100.0 * x.agreement,
                        x.max_rel_t_diff
                    );
                }
                None => s.push_str(" — | — |"),
            }
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s);
    for c in &sc.competitors {
        let _ = writeln!(s, "- {} {}: {}", c.name, c.variant, c.describe);
    }
}

/// The framing as the report's header states it.
fn framing_text(framing: &str) -> String {
    match framing {
        "scene" => "scene: the scene's camera; a bare mesh seen from the front with room around it \
                    (`--framing tight` fills the image)"
            .into(),
        "tight" => "tight: a bare mesh fills the image (a scene's own camera is kept)".into(),
        other => other.into(),
    }
}

/// The share of `kind`'s rays that hit (closest hit) or were occluded (shadow), as
/// `37.5 % hit` / `12.0 % occluded`: the same for every exact structure, so read off the
/// first that traced the kind.
fn hit_rate(sc: &crate::results::SceneResult, kind: &str) -> Option<String> {
    let k = sc.structures.iter().find_map(|st| st.kinds.iter().find(|x| x.kind == kind && x.rays > 0))?;
    let word = if kind == "shadow" { "occluded" } else { "hit" };
    Some(format!("{:.1} % {word}", 100.0 * k.hits as f64 / k.rays as f64))
}

/// The whole report as Markdown.
pub fn render(r: &Report, png: bool) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# dynray bench\n");
    let _ = writeln!(s, "| | |\n|---|---|");
    let _ = writeln!(s, "| dynray | {} |", r.dynray_version);
    let _ = writeln!(s, "| commit | {} |", r.commit.as_deref().unwrap_or("unknown"));
    let _ = writeln!(s, "| CPU | {} ({} logical cores, {}) |", r.machine.cpu, r.machine.logical_cores, r.machine.os);
    let _ = writeln!(s, "| threads | {} |", r.threads);
    let _ = writeln!(s, "| date | {} – {} |", r.started_utc, r.finished_utc);
    let c = &r.config;
    let _ = writeln!(s, "| image | {}×{} |", c.width, c.height);
    let _ = writeln!(s, "| framing | {} |", framing_text(&c.framing));
    let _ = writeln!(s, "| repeat | {} timed after 1 warm-up (medians) |", c.repeat);
    let verify = c.verify_sample.map(|n| format!("{n} rays per kind")).unwrap_or_else(|| "every ray".into());
    let _ = writeln!(s, "| checked against brute force | {verify} |");
    let _ = writeln!(s, "| presets | {} |", c.presets.join(", "));
    if let Some(g) = &r.gpu {
        let _ = writeln!(
            s,
            "| GPU | {} ({}, {}, {}; {} test; tree built on: {}) |",
            g.adapter, g.device_type, g.backend, g.driver, g.precision, g.build
        );
    }
    let _ = writeln!(s);
    if r.mismatches.is_empty() {
        let _ =
            writeln!(s, "All checked rays agree with brute force (same triangle, same `t` bits; same `occluded`).\n");
    } else {
        let _ = writeln!(s, "**{} disagreement(s) with brute force** (first 20):\n", r.mismatches.len());
        let _ = writeln!(s, "| scene | structure | kind | ray | expected | got |\n|---|---|---|---|---|---|");
        for m in r.mismatches.iter().take(20) {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} |",
                m.scene, m.accel, m.kind, m.ray_index, m.expected, m.got
            );
        }
        let _ = writeln!(s);
    }
    for n in &r.notes {
        let _ = writeln!(s, "> {n}\n");
    }

    for sc in &r.scenes {
        let counts: Vec<String> = sc
            .ray_counts
            .iter()
            .map(|k| match hit_rate(sc, &k.kind) {
                Some(rate) => format!("{} {} ({rate})", k.kind, thousands(k.rays as u64)),
                None => format!("{} {}", k.kind, thousands(k.rays as u64)),
            })
            .collect();
        let _ = writeln!(
            s,
            "## {} — {} triangles\n\n`{}`; rays: {}\n",
            sc.name,
            thousands(sc.triangles as u64),
            sc.path,
            counts.join(", ")
        );
        let mut head = "| structure | build ms | memory | nodes | leaves | depth | SAH |".to_string();
        let mut rule = "|---|--:|--:|--:|--:|--:|--:|".to_string();
        for k in &c.rays {
            // Throughput depends on how many rays hit: a miss that leaves at the root is cheap.
            match hit_rate(sc, k) {
                Some(rate) => {
                    let _ = write!(head, " {k} Mrays/s ({rate}) |");
                }
                None => {
                    let _ = write!(head, " {k} Mrays/s |");
                }
            }
            rule.push_str("--:|");
        }
        head.push_str(" time to image ms |");
        rule.push_str("--:|");
        let _ = writeln!(s, "{head}\n{rule}");
        for st in &sc.structures {
            let _ = write!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} |",
                st.accel,
                num(st.build_ms),
                bytes(st.memory_bytes),
                thousands(st.nodes as u64),
                thousands(st.leaves as u64),
                st.max_depth,
                st.sah_cost.map(num).unwrap_or_else(|| "—".into())
            );
            for k in &c.rays {
                let v =
                    st.kinds.iter().find(|x| &x.kind == k).map(|x| num(x.mrays_per_s)).unwrap_or_else(|| "—".into());
                let _ = write!(s, " {v} |");
            }
            let _ = writeln!(s, " {} |", st.time_to_image_ms.map(num).unwrap_or_else(|| "—".into()));
        }
        for st in &sc.structures {
            if let (Some(p), Some(single)) = (&st.primary_packets, st.kinds.iter().find(|k| k.kind == "primary")) {
                let ratio = (single.mrays_per_s > 0.0).then(|| p.mrays_per_s / single.mrays_per_s);
                let _ = writeln!(
                    s,
                    "\n`{}` primary rays in packets of 8 (one origin): {} Mrays/s, {} of its single rays; {} checked.",
                    st.accel,
                    num(p.mrays_per_s),
                    ratio.map(|r| format!("{}×", num(r))).unwrap_or_else(|| "—".into()),
                    thousands(p.verified as u64)
                );
            }
        }
        let _ = writeln!(s, "\nWork per ray (counted pass: nodes visited / triangles tested), hits, rays checked:\n");
        let mut head = "| structure |".to_string();
        let mut rule = "|---|".to_string();
        for k in &c.rays {
            let _ = write!(head, " {k} nodes / tris | {k} hits | {k} checked |");
            rule.push_str("--:|--:|--:|");
        }
        let _ = writeln!(s, "{head}\n{rule}");
        for st in &sc.structures {
            let _ = write!(s, "| {} |", st.accel);
            for k in &c.rays {
                match st.kinds.iter().find(|x| &x.kind == k) {
                    Some(x) => {
                        let _ = write!(
                            s,
                            " {} / {} | {} | {} |",
                            num(x.nodes_per_ray),
                            num(x.triangles_per_ray),
                            thousands(x.hits as u64),
                            thousands(x.verified as u64)
                        );
                    }
                    None => s.push_str(" — | — | — |"),
                }
            }
            let _ = writeln!(s);
        }
        side_by_side(&mut s, sc, &c.rays);
        crate::gpu::standard::markdown(sc, &c.rays, &mut s);
        if png {
            let maps: Vec<String> = sc
                .structures
                .iter()
                .filter_map(|st| st.heatmap.as_ref().map(|h| format!("[{}]({h})", st.accel)))
                .collect();
            if !maps.is_empty() {
                let _ = writeln!(s, "\nHeat maps: {}", maps.join(", "));
            }
        }
        let _ = writeln!(s);
    }
    if !r.scenes.is_empty() {
        let ext = if png { "png" } else { "svg" };
        let _ = writeln!(s, "![build time vs triangles](build-vs-triangles.{ext})\n\n![Mrays/s](mrays.{ext})\n");
    }

    markdown_of::<Seed000>(&r.seed000, png, &mut s);
    markdown_of::<Seed000PhysicsRun>(&r.seed000_physics, png, &mut s);
    markdown_of::<Seed001>(&r.seed001, png, &mut s);
    markdown_of::<Seed002>(&r.seed002, png, &mut s);
    markdown_of::<Seed004>(&r.seed004, png, &mut s);
    markdown_of::<Seed004RenderersRun>(&r.seed004_renderers, png, &mut s);
    markdown_of::<Seed003>(&r.seed003, png, &mut s);
    markdown_of::<PathTracer>(&r.path, png, &mut s);

    markdown_of::<Dynamic>(&r.dynamic, png, &mut s);
    s
}
