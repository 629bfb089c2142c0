//! `--preset seed002`: seed 002's experiment. The octree walked leaf to leaf through
//! neighbour links and the same octree descended top-down, each balanced (2:1) and
//! unbalanced, against the BVH, on primary rays at 1024×1024 (the layout of its Table 2:
//! Mrays/s and ms per frame), with its leaf counts (Table 1) and memory breakdown
//! (Table 3).
//!
//! Depths follow the seed: 8 on the bunny, 11 on the dragon (Armadillo, depth 10, is not
//! among our models). Scenes given on the command line use the default depth 8.

use super::experiment::{Experiment, Lab};
use super::study::{self, param, ratio, Metric, Study};
use crate::config::BenchConfig;
use crate::format::{bytes, num, thousands};
use crate::presets::study::{Ratio, StudyResult};
use crate::rays::RayKind;
use crate::results::{SceneResult, StructureResult};
use std::fmt::Write;

const BVH: &str = "bvh";

fn variants(depth: u32) -> Vec<dynray_accel::AccelSpec> {
    study::variants(
        "seed002",
        &format!(
            "octree:max_depth={depth},octree:max_depth={depth},balance=off,\
             octree-descent:max_depth={depth},octree-descent:max_depth={depth},balance=off,bvh"
        ),
    )
}

/// The experiment.
pub fn study(config: &BenchConfig) -> Study {
    let own = vec![("bunny".to_string(), variants(8)), ("dragon".to_string(), variants(11))];
    let mut plan = study::plan_or_given(config, own, &["dragon-res4"]);
    if !config.scenes.is_empty() || config.quick {
        for (_, v) in &mut plan {
            *v = variants(8);
        }
    }
    Study { preset: "seed002", plan, rays: vec![RayKind::Primary], size: (1024, 1024), time_to_image: false }
}

/// `octree walk, balanced` and so on, for our labels.
pub fn display_name(label: &str) -> String {
    let balance = if param(label, "balance") == Some("off") { "unbalanced" } else { "balanced" };
    if label.starts_with("octree-descent") {
        format!("octree top-down descent, {balance}")
    } else if label.starts_with("octree") {
        format!("octree neighbour walk, {balance}")
    } else {
        label.to_string()
    }
}

fn find<'a>(sc: &'a SceneResult, kind: &str, balanced: bool) -> Option<&'a StructureResult> {
    sc.structures
        .iter()
        .find(|s| s.accel.split(':').next() == Some(kind) && (param(&s.accel, "balance") == Some("off")) != balanced)
}

/// The octree variants against the BVH, the walk against the descent, balanced against
/// unbalanced (primary-ray trace time), and memory against the BVH.
pub fn ratios(r: &StudyResult) -> Vec<Ratio> {
    let primary = Metric::Trace(RayKind::Primary);
    let mut out = Vec::new();
    for sc in &r.scenes {
        for s in sc.structures.iter().filter(|s| s.accel.starts_with("octree")) {
            out.extend(ratio(sc, primary, BVH, &s.accel));
            out.extend(ratio(sc, Metric::Memory, BVH, &s.accel));
        }
        for balanced in [true, false] {
            if let (Some(walk), Some(descent)) = (find(sc, "octree", balanced), find(sc, "octree-descent", balanced)) {
                out.extend(ratio(sc, primary, &descent.accel, &walk.accel));
            }
        }
        for kind in ["octree", "octree-descent"] {
            if let (Some(b), Some(u)) = (find(sc, kind, true), find(sc, kind, false)) {
                out.extend(ratio(sc, primary, &u.accel, &b.accel));
            }
        }
    }
    out
}

fn extra<'a>(s: &'a StructureResult, key: &str) -> Option<&'a str> {
    s.extra.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

fn mib_of(s: &StructureResult, key: &str) -> String {
    extra(s, key).and_then(|v| v.parse::<usize>().ok()).map(bytes).unwrap_or_else(|| "—".into())
}

/// The preset's section of report.md.
pub fn markdown(r: &StudyResult, s: &mut String) {
    let _ = writeln!(
        s,
        "## seed002: octree walks against the BVH (seed 002, Tables 1–3)\n\n\
         {}×{} primary rays, medians of {} passes on {} threads. \"× BVH\" is BVH time / octree time: \
         above 1 the octree is faster.\n",
        r.width,
        r.height,
        r.repeat,
        rayon::current_num_threads()
    );
    let _ = writeln!(s, "### Traversal (Table 2 layout: Mrays/s / ms per frame)\n");
    let _ = writeln!(
        s,
        "| scene | structure | Mrays/s | ms/frame | × BVH | nodes/ray | triangles/ray |\n|---|---|--:|--:|--:|--:|--:|"
    );
    let primary = Metric::Trace(RayKind::Primary);
    for sc in &r.scenes {
        for st in &sc.structures {
            let Some(k) = st.kinds.iter().find(|k| k.kind == "primary") else { continue };
            let x =
                ratio(sc, primary, BVH, &st.accel).map(|q| format!("{:.2}", q.speedup)).unwrap_or_else(|| "—".into());
            let _ = writeln!(
                s,
                "| {} ({} tris) | {} | {} | {} | {x} | {} | {} |",
                sc.name,
                thousands(sc.triangles as u64),
                display_name(&st.accel),
                num(k.mrays_per_s),
                num(k.trace_ms),
                num(k.nodes_per_ray),
                num(k.triangles_per_ray)
            );
        }
    }
    let _ = writeln!(s, "\n### Leaves with and without the 2:1 constraint (Table 1 layout)\n");
    let _ = writeln!(s, "| scene | depth | unconstrained | constrained | ratio |\n|---|--:|--:|--:|--:|");
    for sc in &r.scenes {
        if let (Some(b), Some(u)) = (find(sc, "octree", true), find(sc, "octree", false)) {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.0} % |",
                sc.name,
                b.max_depth,
                thousands(u.leaves as u64),
                thousands(b.leaves as u64),
                100.0 * b.leaves as f64 / u.leaves.max(1) as f64
            );
        }
    }
    let _ = writeln!(s, "\n### Memory of the balanced octree (Table 3 layout)\n");
    let _ = writeln!(
        s,
        "| scene | cube map | internal nodes + leaf records | triangles | leaf boxes | total | BVH total |\n\
         |---|--:|--:|--:|--:|--:|--:|"
    );
    for sc in &r.scenes {
        let Some(b) = find(sc, "octree", true) else { continue };
        let nodes: usize = ["internal nodes bytes", "leaf records bytes"]
            .iter()
            .filter_map(|k| extra(b, k).and_then(|v| v.parse::<usize>().ok()))
            .sum();
        let bvh = sc.structures.iter().find(|s| s.accel == BVH).map(|s| bytes(s.memory_bytes));
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} |",
            sc.name,
            mib_of(b, "cube map bytes"),
            bytes(nodes),
            mib_of(b, "triangle refs bytes"),
            mib_of(b, "leaf boxes bytes"),
            bytes(b.memory_bytes),
            bvh.unwrap_or_else(|| "—".into())
        );
    }
    let _ = writeln!(s);
}

/// `--preset seed002`: the study, its ratios, its section and charts.
pub struct Seed002;

impl Experiment for Seed002 {
    const PRESET: crate::config::Preset = crate::config::Preset::Seed002;
    type Output = StudyResult;

    fn run(ctx: &mut Lab<'_>) -> anyhow::Result<StudyResult> {
        super::study::run_in_lab(ctx, study, ratios)
    }

    fn markdown(out: &StudyResult, png: bool, s: &mut String) {
        let _ = png;
        markdown(out, s)
    }

    fn charts(out: &StudyResult, dir: &std::path::Path, png: bool) -> anyhow::Result<()> {
        let _ = (out, dir, png);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_plan_follow_the_seed() {
        assert_eq!(display_name("octree:max_depth=8,balance=off"), "octree neighbour walk, unbalanced");
        assert_eq!(display_name("octree-descent:max_depth=11"), "octree top-down descent, balanced");
        let s = study(&BenchConfig::new(false));
        assert_eq!(s.plan[1].0, "dragon");
        assert!(s.plan[1].1.iter().any(|v| v.to_string() == "octree:max_depth=11,balance=off"));
        assert_eq!(s.plan[0].1.len(), 5);
    }
}
