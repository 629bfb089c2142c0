//! `--preset seed000`: seed 000's experiment. The BIH with MaxPrims 1, 5, 10, 20, 30,
//! with and without its "shrink" step, against the kd-tree with the standard stack
//! traversal and with Ropes++: build, traversal and time to image per model (the layout of
//! its Table 1), and memory per structure (its memory chart, on the dragon).
//!
//! The seed's models (Hornbug, Alien, Dino, deformed by point-based animation) are not
//! available; the bunny and the dragon at two resolutions stand in, and the seed's own
//! memory figures were on the dragon. "Shrink on" is `BihParams::seed_000` (the seed's
//! build: shrink factor 1.3, no empty-space cuts); "shrink off" is
//! `BihParams::wachter_keller` (the node box only ever halves).

use super::experiment::{Experiment, Lab};
use super::study::{self, param, ratio, Metric, Study};
use crate::config::BenchConfig;
use crate::format::{bytes, num, thousands};
use crate::line_chart::{LineChart, Panel, Series};
use crate::presets::study::{Ratio, StudyResult};
use crate::rays::RayKind;
use crate::results::{SceneResult, StructureResult};
use std::fmt::Write;

/// The seed's MaxPrims values.
pub const MAX_PRIMS: [u32; 5] = [1, 5, 10, 20, 30];
const KD: &str = "kdtree";
const ROPES: &str = "kdtree-ropes";

/// The experiment: every scene gets the ten BIH variants and both kd-trees.
pub fn study(config: &BenchConfig) -> Study {
    let mut list = String::new();
    for shrink in ["seed_000", "wachter_keller"] {
        for m in MAX_PRIMS {
            let _ = write!(list, "bih:preset={shrink},max_prims={m},");
        }
    }
    list.push_str("kdtree,kdtree-ropes");
    let v = study::variants("seed000", &list);
    let own = ["bunny", "dragon-res2", "dragon"].iter().map(|s| (s.to_string(), v.clone())).collect();
    Study {
        preset: "seed000",
        plan: study::plan_or_given(config, own, &["dragon-res4"]),
        rays: vec![RayKind::Primary, RayKind::Shadow],
        size: (640, 480),
        time_to_image: true,
    }
}

/// `BIH MaxPrims = 5, shrink` / `kd-tree Ropes++`: the seed's names for our labels.
pub fn display_name(label: &str) -> String {
    match label {
        KD => "kd-tree Standard".into(),
        ROPES => "kd-tree Ropes++".into(),
        _ => match (param(label, "max_prims"), param(label, "preset")) {
            (Some(m), Some("seed_000")) => format!("BIH MaxPrims = {m}, shrink"),
            (Some(m), Some("wachter_keller")) => format!("BIH MaxPrims = {m}, no shrink"),
            _ => label.to_string(),
        },
    }
}

/// Every BIH variant against Ropes++ (build, primary trace, time to image, memory) and
/// against the standard kd-tree (memory), and shrink against no shrink at equal MaxPrims.
pub fn ratios(r: &StudyResult) -> Vec<Ratio> {
    let mut out = Vec::new();
    for sc in &r.scenes {
        for s in sc.structures.iter().filter(|s| s.accel.starts_with("bih")) {
            for m in [Metric::Build, Metric::Trace(RayKind::Primary), Metric::TimeToImage, Metric::Memory] {
                out.extend(ratio(sc, m, ROPES, &s.accel));
            }
            out.extend(ratio(sc, Metric::Memory, KD, &s.accel));
            if param(&s.accel, "preset") == Some("seed_000") {
                let off = s.accel.replace("seed_000", "wachter_keller");
                for m in [Metric::Build, Metric::Trace(RayKind::Primary), Metric::TimeToImage] {
                    out.extend(ratio(sc, m, &off, &s.accel));
                }
            }
        }
    }
    out
}

/// The preset's section of report.md.
pub fn markdown(r: &StudyResult, png: bool, s: &mut String) {
    let _ = writeln!(
        s,
        "## seed000: BIH against kd-trees (seed 000, Table 1 and memory chart)\n\n\
         {}×{} primary + shadow rays; time to image = build + Whitted render at that size. \
         Medians of {} runs. Ratios are `kd-tree Ropes++ / BIH`: above 1 the BIH wins.\n",
        r.width, r.height, r.repeat
    );
    let ext = if png { "png" } else { "svg" };
    let _ = writeln!(s, "![leaf-size sweep](seed000-sweep.{ext})\n\n![memory](seed000-memory.{ext})\n");
    for sc in &r.scenes {
        let _ = writeln!(s, "### {} — {} triangles\n", sc.name, thousands(sc.triangles as u64));
        let _ = writeln!(
            s,
            "| structure | build ms | primary ms | shadow ms | time to image ms | fps | memory | \
             build ×  | trace × | time to image × |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|"
        );
        for st in &sc.structures {
            let m = |k: Metric| k.of(st).map(num).unwrap_or_else(|| "—".into());
            let x = |k: Metric| {
                ratio(sc, k, ROPES, &st.accel).map(|q| format!("{:.2}", q.speedup)).unwrap_or_else(|| "—".into())
            };
            let fps = st.time_to_image_ms.map(|t| num(1000.0 / t)).unwrap_or_else(|| "—".into());
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {fps} | {} | {} | {} | {} |",
                display_name(&st.accel),
                m(Metric::Build),
                m(Metric::Trace(RayKind::Primary)),
                m(Metric::Trace(RayKind::Shadow)),
                m(Metric::TimeToImage),
                bytes(st.memory_bytes),
                x(Metric::Build),
                x(Metric::Trace(RayKind::Primary)),
                x(Metric::TimeToImage),
            );
        }
        let _ = writeln!(s);
    }
}

/// `(MaxPrims, value)` of the BIH variants of one shrink setting (`preset`) on a scene.
fn sweep(sc: &SceneResult, preset: &str, value: impl Fn(&StructureResult) -> Option<f64>) -> Vec<(f64, f64)> {
    sc.structures
        .iter()
        .filter(|s| param(&s.accel, "preset") == Some(preset))
        .filter_map(|s| Some((param(&s.accel, "max_prims")?.parse().ok()?, value(s)?)))
        .collect()
}

/// A horizontal line across the sweep at `label`'s value.
fn level(sc: &SceneResult, label: &str, value: impl Fn(&StructureResult) -> Option<f64>) -> Vec<(f64, f64)> {
    let v = sc.structures.iter().find(|s| s.accel == label).and_then(value);
    let (lo, hi) = (MAX_PRIMS[0] as f64, MAX_PRIMS[MAX_PRIMS.len() - 1] as f64);
    v.map(|v| vec![(lo, v), (hi, v)]).unwrap_or_default()
}

fn series(name: &str, points: Vec<(f64, f64)>, reference: bool) -> Series {
    Series { name: name.to_string(), points, reference }
}

/// One panel per scene of the sweep, against MaxPrims.
fn chart(
    r: &StudyResult,
    caption: String,
    y_desc: &str,
    log_y: bool,
    series: impl Fn(&SceneResult) -> Vec<Series>,
) -> LineChart {
    let panels = r
        .scenes
        .iter()
        .map(|sc| Panel {
            title: format!("{} ({} triangles)", sc.name, thousands(sc.triangles as u64)),
            series: series(sc),
        })
        .collect();
    LineChart {
        caption,
        x_desc: "MaxPrims (triangles per leaf)".into(),
        y_desc: y_desc.into(),
        log2_x: false,
        log_y,
        y_from_zero: !log_y,
        panels,
    }
}

/// The leaf-size sweep: time to image and build against MaxPrims, one panel per scene,
/// the kd-trees' time to image as references.
pub fn sweep_chart(r: &StudyResult) -> LineChart {
    let tti = |s: &StructureResult| s.time_to_image_ms;
    let build = |s: &StructureResult| Some(s.build_ms);
    let caption = format!("seed000: BIH leaf-size sweep, {}x{} (lower is better)", r.width, r.height);
    chart(r, caption, "ms", true, |sc| {
        vec![
            series("BIH shrink: time to image", sweep(sc, "seed_000", tti), false),
            series("BIH no shrink: time to image", sweep(sc, "wachter_keller", tti), false),
            series("BIH shrink: build", sweep(sc, "seed_000", build), false),
            series("BIH no shrink: build", sweep(sc, "wachter_keller", build), false),
            series("kd-tree Ropes++: time to image", level(sc, ROPES, tti), true),
            series("kd-tree Standard: time to image", level(sc, KD, tti), true),
        ]
    })
}

/// Memory against MaxPrims, one panel per scene, the kd-trees as references.
pub fn memory_chart(r: &StudyResult) -> LineChart {
    let mib = |s: &StructureResult| Some(s.memory_bytes as f64 / (1024.0 * 1024.0));
    let caption = "seed000: memory of the BIH by MaxPrims against the kd-trees".to_string();
    chart(r, caption, "MiB", false, |sc| {
        vec![
            series("BIH shrink", sweep(sc, "seed_000", mib), false),
            series("BIH no shrink", sweep(sc, "wachter_keller", mib), false),
            series("kd-tree Ropes++", level(sc, ROPES, mib), true),
            series("kd-tree Standard", level(sc, KD, mib), true),
        ]
    })
}

/// `--preset seed000`: the study, its ratios, its section and charts.
pub struct Seed000;

impl Experiment for Seed000 {
    const PRESET: crate::config::Preset = crate::config::Preset::Seed000;
    type Output = StudyResult;

    fn run(ctx: &mut Lab<'_>) -> anyhow::Result<StudyResult> {
        super::study::run_in_lab(ctx, study, ratios)
    }

    fn markdown(out: &StudyResult, png: bool, s: &mut String) {
        markdown(out, png, s)
    }

    fn charts(out: &StudyResult, dir: &std::path::Path, png: bool) -> anyhow::Result<()> {
        crate::charts::save(&sweep_chart(out), dir, "seed000-sweep", png)?;
        crate::charts::save(&memory_chart(out), dir, "seed000-memory", png)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_read_as_the_seed_names_them() {
        assert_eq!(display_name("bih:preset=seed_000,max_prims=5"), "BIH MaxPrims = 5, shrink");
        assert_eq!(display_name("bih:preset=wachter_keller,max_prims=30"), "BIH MaxPrims = 30, no shrink");
        assert_eq!(display_name("kdtree-ropes"), "kd-tree Ropes++");
        assert_eq!(display_name("grid"), "grid");
    }

    #[test]
    fn the_plan_has_ten_bih_variants_and_both_kd_trees_per_scene() {
        let s = study(&BenchConfig::new(false));
        assert_eq!(s.plan.len(), 3);
        for (_, v) in &s.plan {
            assert_eq!(v.len(), 12);
            assert_eq!(v.iter().filter(|a| a.to_string().starts_with("bih")).count(), 10);
        }
        assert_eq!(study(&BenchConfig::new(true)).plan.len(), 1);
    }
}
