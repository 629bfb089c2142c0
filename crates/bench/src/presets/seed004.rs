//! `--preset seed004`: seed 004's experiment. The A-PIT (A-buffers on a cube around the
//! observer, each pixel's fragments in a pseudo-interval tree) against the plain A-buffer
//! (the same fragments in per-pixel lists) at several A-buffer resolutions, on coherent
//! rays from the observer and on rays that are not (shadow and diffuse bounces), at the
//! seed's 512×512: the layout of its Table 1 (average speed-up per scene and resolution).
//!
//! The seed's scenes (a 5k-triangle bunny, the Armadillo, the Happy Buddha) are stood in
//! for by the Cornell box (an enclosed scene), the duck (4k) and the bunny (69k, the
//! Armadillo's size). Both structures are centred on the camera, as in the seed.

use super::experiment::{Experiment, Lab};
use super::study::{self, ratio, Metric, Study};
use crate::config::BenchConfig;
use crate::format::{num, thousands};
use crate::line_chart::{LineChart, Panel, Series};
use crate::presets::study::{Ratio, StudyResult};
use crate::rays::RayKind;
use crate::results::{SceneResult, Work};
use std::fmt::Write;

/// A-buffer resolutions (pixels per cube-face side).
pub const RESOLUTIONS: [u32; 4] = [32, 64, 128, 256];
const KINDS: [RayKind; 3] = [RayKind::Primary, RayKind::Shadow, RayKind::Diffuse];

/// The experiment.
pub fn study(config: &BenchConfig) -> Study {
    let mut list = String::new();
    for r in RESOLUTIONS {
        let _ = write!(list, "abuffer:resolution={r},apit:resolution={r},");
    }
    let v = study::variants("seed004", list.trim_end_matches(','));
    let own = ["cornell-box", "duck", "bunny"].iter().map(|s| (s.to_string(), v.clone())).collect();
    Study {
        preset: "seed004",
        plan: study::plan_or_given(config, own, &["cornell-box", "dragon-res4"]),
        rays: KINDS.to_vec(),
        size: (512, 512),
        time_to_image: false,
    }
}

fn labels(res: u32) -> (String, String) {
    (format!("abuffer:resolution={res}"), format!("apit:resolution={res}"))
}

/// Per scene, resolution and ray kind: A-buffer trace time / A-PIT trace time; and the
/// build-time ratio.
pub fn ratios(r: &StudyResult) -> Vec<Ratio> {
    let mut out = Vec::new();
    for sc in &r.scenes {
        for res in RESOLUTIONS {
            let (plain, tree) = labels(res);
            for k in KINDS {
                out.extend(ratio(sc, Metric::Trace(k), &plain, &tree));
            }
            out.extend(ratio(sc, Metric::Build, &plain, &tree));
        }
    }
    out
}

/// Speed-ups of one scene at one resolution per ray kind, and their geometric mean (the
/// "average speed gain": a ratio's average is geometric, so 2× and 0.5× average to 1×).
fn speedups(sc: &SceneResult, res: u32) -> (Vec<Option<f64>>, Option<f64>) {
    let (plain, tree) = labels(res);
    let per: Vec<Option<f64>> =
        KINDS.iter().map(|k| ratio(sc, Metric::Trace(*k), &plain, &tree).map(|q| q.speedup)).collect();
    let got: Vec<f64> = per.iter().flatten().copied().collect();
    let mean = (!got.is_empty()).then(|| (got.iter().map(|x| x.ln()).sum::<f64>() / got.len() as f64).exp());
    (per, mean)
}

/// The preset's section of report.md.
pub fn markdown(r: &StudyResult, png: bool, s: &mut String) {
    let _ = writeln!(
        s,
        "## seed004: A-PIT against the plain A-buffer (seed 004, Table 1 layout)\n\n\
         {}×{} rays, cube centred on the camera; speed-up = A-buffer trace time / A-PIT trace time \
         (above 1 the A-PIT is faster), averaged geometrically over primary, shadow and diffuse rays.\n",
        r.width, r.height
    );
    let ext = if png { "png" } else { "svg" };
    let _ = writeln!(s, "![A-PIT speed-up by resolution](seed004-speedup.{ext})\n");
    let mut head = "| scene |".to_string();
    let mut rule = "|---|".to_string();
    for res in RESOLUTIONS {
        let _ = write!(head, " {res}² |");
        rule.push_str("--:|");
    }
    let _ = writeln!(s, "{head}\n{rule}");
    for sc in &r.scenes {
        let _ = write!(s, "| {} ({} tris) |", sc.name, thousands(sc.triangles as u64));
        for res in RESOLUTIONS {
            let (_, mean) = speedups(sc, res);
            let _ = write!(s, " {} |", mean.map(|m| format!("{m:.2}×")).unwrap_or_else(|| "—".into()));
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s, "\nPer ray kind (A-buffer Mrays/s → A-PIT Mrays/s, speed-up) and build times:\n");
    let _ = writeln!(
        s,
        "| scene | resolution | primary | shadow | diffuse | build ms (A-buffer / A-PIT) | memory |\n|---|--:|---|---|---|---|---|"
    );
    for sc in &r.scenes {
        for res in RESOLUTIONS {
            let (plain, tree) = labels(res);
            let (Some(p), Some(t)) =
                (sc.structures.iter().find(|s| s.accel == plain), sc.structures.iter().find(|s| s.accel == tree))
            else {
                continue;
            };
            let (per, _) = speedups(sc, res);
            let _ = write!(s, "| {} | {res}² |", sc.name);
            for (k, x) in KINDS.iter().zip(&per) {
                let m = |st: &crate::results::StructureResult| {
                    st.kinds.iter().find(|r| r.kind == k.name()).map(|r| num(r.mrays_per_s)).unwrap_or_default()
                };
                let x = x.map(|x| format!("{x:.2}×")).unwrap_or_else(|| "—".into());
                let _ = write!(s, " {} → {} ({x}) |", m(p), m(t));
            }
            let _ = writeln!(
                s,
                " {} / {} | {} / {} |",
                num(p.build_ms),
                num(t.build_ms),
                crate::format::bytes(p.memory_bytes),
                crate::format::bytes(t.memory_bytes)
            );
        }
    }
    let _ = writeln!(s);
    work_split(r, s);
}

/// Resolution of the hit/escape work table: the structures' `fast` preset, in the middle
/// of the sweep.
const SPLIT_RESOLUTION: u32 = 64;

/// Seed 004's worst case, measured: the work of the rays that hit beside that of the rays
/// that escape the scene (which walk frustum after frustum with nothing to stop them).
fn work_split(r: &StudyResult, s: &mut String) {
    let (plain, tree) = labels(SPLIT_RESOLUTION);
    let _ = writeln!(
        s,
        "Work per ray at {SPLIT_RESOLUTION}², rays that hit against rays that escape, hitting nothing \
         (shadow rays: that reach the light); nodes or fragments visited + triangles tested, counted \
         pass. Both structures clip rays to the mesh's box, the concrete form of the seed's \
         \"far enough\" cut-off, so an escaping ray walks the frustums inside the box:\n\n\
         | scene | rays | hit / escaped | A-PIT hit | A-PIT escaped | A-buffer hit | A-buffer escaped |\n\
         |---|---|--:|--:|--:|--:|--:|"
    );
    let work = |w: Option<Work>| w.map(|w| num(w.nodes + w.triangles)).unwrap_or_else(|| "—".into());
    for sc in &r.scenes {
        let find = |label: &str| sc.structures.iter().find(|x| x.accel == label);
        let (Some(p), Some(t)) = (find(&plain), find(&tree)) else {
            continue;
        };
        for k in KINDS {
            let of = |st: &crate::results::StructureResult| st.kinds.iter().find(|x| x.kind == k.name()).cloned();
            let (Some(pk), Some(tk)) = (of(p), of(t)) else {
                continue;
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} / {} | {} | {} | {} | {} |",
                sc.name,
                k.name(),
                thousands(tk.hits as u64),
                thousands((tk.rays - tk.hits) as u64),
                work(tk.hit_work),
                work(tk.escaped_work),
                work(pk.hit_work),
                work(pk.escaped_work)
            );
        }
    }
    let _ = writeln!(s);
}

/// Speed-up against resolution, one panel per scene, one line per ray kind plus the mean.
pub fn chart(r: &StudyResult) -> LineChart {
    let panels = r
        .scenes
        .iter()
        .map(|sc| {
            let rows: Vec<(u32, Vec<Option<f64>>, Option<f64>)> = RESOLUTIONS
                .iter()
                .map(|&res| {
                    let (per, mean) = speedups(sc, res);
                    (res, per, mean)
                })
                .collect();
            let mut series: Vec<Series> = KINDS
                .iter()
                .enumerate()
                .map(|(i, k)| Series {
                    name: format!("{} rays", k.name()),
                    points: rows.iter().filter_map(|(res, per, _)| Some((*res as f64, per[i]?))).collect(),
                    reference: false,
                })
                .collect();
            series.push(Series {
                name: "geometric mean".into(),
                points: rows.iter().filter_map(|(res, _, m)| Some((*res as f64, (*m)?))).collect(),
                reference: false,
            });
            series.push(Series {
                name: "no gain (1×)".into(),
                points: vec![(RESOLUTIONS[0] as f64, 1.0), (RESOLUTIONS[RESOLUTIONS.len() - 1] as f64, 1.0)],
                reference: true,
            });
            Panel { title: format!("{} ({} triangles)", sc.name, thousands(sc.triangles as u64)), series }
        })
        .collect();
    LineChart {
        caption: format!(
            "seed004: A-PIT speed-up over the plain A-buffer, {}x{} (higher is better)",
            r.width, r.height
        ),
        x_desc: "A-buffer resolution (pixels per cube-face side)".into(),
        y_desc: "speed-up (A-buffer time / A-PIT time)".into(),
        log2_x: true,
        log_y: false,
        y_from_zero: true,
        panels,
    }
}

/// `--preset seed004`: the study, its ratios, its section and charts.
pub struct Seed004;

impl Experiment for Seed004 {
    const PRESET: crate::config::Preset = crate::config::Preset::Seed004;
    type Output = StudyResult;

    fn run(ctx: &mut Lab<'_>) -> anyhow::Result<StudyResult> {
        super::study::run_in_lab(ctx, study, ratios)
    }

    fn markdown(out: &StudyResult, png: bool, s: &mut String) {
        markdown(out, png, s)
    }

    fn charts(out: &StudyResult, dir: &std::path::Path, png: bool) -> anyhow::Result<()> {
        crate::charts::save(&chart(out), dir, "seed004-speedup", png).map(drop)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::presets::study::param;

    #[test]
    fn every_resolution_pairs_the_two_structures() {
        let s = study(&BenchConfig::new(false));
        let labels: Vec<String> = s.plan[0].1.iter().map(|v| v.to_string()).collect();
        for res in RESOLUTIONS {
            let (p, t) = super::labels(res);
            assert!(labels.contains(&p) && labels.contains(&t), "{res}: {labels:?}");
        }
        assert_eq!(labels.len(), 2 * RESOLUTIONS.len());
        assert_eq!(param(&labels[1], "resolution"), Some("32"));
    }
}
