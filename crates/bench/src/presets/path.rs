//! `--preset path`: the physically based path tracer (`--integrator path`) measured on
//! Mitsuba 3's reference scenes (`shared/reference`: a diffuse sphere on a plane under a
//! point light, `max_depth` 2 and 8, 4096 spp, with Mitsuba's render time and noise).
//!
//! Per scene:
//! - per structure, one render at a fixed sample count: camera samples/s and Mrays/s (every
//!   ray the structure answers: camera, shadow and bounce rays), and the RMSE against the
//!   reference. Every structure returns bit-identical hits and the sampler depends only on
//!   the pixel and sample, so the images must be identical (a difference is a mismatch).
//! - convergence (first structure): renders at 1, 2, 4, … spp, each one's time and RMSE
//!   against the reference, beside the time Mitsuba needs for the same RMSE. Mitsuba's time is *estimated* from its reference's own figures
//!   ([`MitsubaFigures`]): its pixel noise at 4096 spp falling as 1/√spp, at its measured
//!   seconds per sample (same machine class, `scalar_rgb`, both cores). dynray's RMSE
//!   includes the reference's own noise, so the estimate adds it to Mitsuba's too.

use super::experiment::{Experiment, Lab};
use crate::config::BenchConfig;
use crate::line_chart::{LineChart, Panel, Series};
use crate::measure::ms;
use crate::progress::progress_bar;
use crate::results::Mismatch;
use crate::scenes::scenes_dir;
use anyhow::{bail, Context, Result};
use dynray_accel::{Accel, AccelSpec};
use dynray_render::{render, Film, IntegratorKind, RenderOptions};
use dynray_scene::{load_file, Color};
use serde::{Deserialize, Serialize};
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `--preset path`: the path tracer's speed per structure and its convergence towards
/// Mitsuba 3's references (`presets::path`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PathResult {
    /// One entry per reference scene.
    pub scenes: Vec<PathScene>,
}

/// The path tracer on one reference scene.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PathScene {
    /// Reference name (`sphere_d2`, ...).
    pub name: String,
    /// The Mitsuba XML rendered.
    pub xml: String,
    /// Its triangles (dynray tessellates Mitsuba's analytic sphere).
    pub triangles: usize,
    /// Image width (the reference's).
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Mitsuba's `max_depth` (path segments).
    pub max_depth: u32,
    /// Samples per pixel of the per-structure runs.
    pub spp: u32,
    /// One entry per structure.
    pub runs: Vec<PathRun>,
    /// RMSE against the reference after each sample per pixel (first structure's run).
    pub convergence: Vec<PathConvergencePoint>,
    /// Mitsuba's own figures for its reference, from `reference/stats.json`.
    pub mitsuba: MitsubaFigures,
}

/// The path tracer over one structure at a fixed sample count.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PathRun {
    /// `--accels` spelling.
    pub accel: String,
    /// Build, ms.
    pub build_ms: f64,
    /// Render, median, ms.
    pub render_ms: f64,
    /// Camera samples per second (pixels × spp / render time).
    pub samples_per_s: f64,
    /// Every ray sent to the structure (camera, shadow, bounce) per second, millions.
    pub mrays_per_s: f64,
    /// Rays of one render.
    pub rays: u64,
    /// RMSE of the image against the reference.
    pub rmse: f64,
    /// Whether the image equals the first structure's, bit for bit.
    pub image_identical: bool,
}

/// The error after some samples per pixel, and when it was reached.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct PathConvergencePoint {
    /// Samples per pixel accumulated.
    pub spp: u32,
    /// Render time until then, ms.
    pub ms: f64,
    /// RMSE over every channel against the reference.
    pub rmse: f64,
    /// Time Mitsuba 3 needs for the same RMSE, ms, estimated from its reference's time and
    /// noise (null where the RMSE is below what that estimate can reach).
    pub mitsuba_ms: Option<f64>,
}

/// What `reference/stats.json` says of Mitsuba's reference render.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct MitsubaFigures {
    /// Samples per pixel of the reference.
    pub spp: u32,
    /// Its render time, s (Mitsuba 3, `scalar_rgb`, same machine class).
    pub render_s: f64,
    /// Root-mean-square per-pixel standard deviation at that spp, over the channels.
    pub rms_pixel_std: f64,
}

impl MitsubaFigures {
    /// Mitsuba's expected RMSE after `spp` samples against an independent reference like
    /// its own: pixel noise falls as 1/√spp, and the reference adds its own.
    pub fn rmse_at(&self, spp: f64) -> f64 {
        let s2 = self.rms_pixel_std.powi(2);
        (s2 * self.spp as f64 / spp + s2).sqrt()
    }

    /// The time, ms, at which Mitsuba reaches `rmse` (inverse of [`Self::rmse_at`] at its
    /// measured seconds per sample); `None` at or below the reference's own noise.
    pub fn ms_for(&self, rmse: f64) -> Option<f64> {
        let s2 = self.rms_pixel_std.powi(2);
        let excess = rmse * rmse - s2;
        (excess > 0.0 && s2 > 0.0).then(|| self.render_s * 1e3 * (s2 / excess))
    }
}

/// The structures measured unless `--accels` names others.
pub const DEFAULT_STRUCTURES: [&str; 4] = ["bvh", "bvh2", "bih", "kdtree"];

/// The reference scenes (`reference/stats.json` keys; `reference/sphere/NAME.xml|exr`).
pub const SCENES: [&str; 2] = ["sphere_d2", "sphere_d8"];

/// Root-mean-square difference over every channel of every pixel (the reference's
/// channels in the same order).
fn rmse(a: &Film, reference: &[Color]) -> f64 {
    let pa = a.pixels();
    let sq: f64 = pa.iter().zip(reference).flat_map(|(x, y)| (*x - *y).to_array()).map(|d| (d as f64).powi(2)).sum();
    (sq / (3 * pa.len().max(1)) as f64).sqrt()
}

/// Where the references are: `reference/` beside the models' folder.
fn reference_dir(config: &BenchConfig) -> Result<PathBuf> {
    let scenes = scenes_dir(config.scenes_dir.as_deref())
        .context("--preset path: the models' folder (../shared/scenes) was not found; its reference/ sibling holds Mitsuba's images")?;
    let dir = scenes.parent().map(|p| p.join("reference")).unwrap_or_else(|| PathBuf::from("reference"));
    if !dir.join("stats.json").is_file() {
        bail!("--preset path: {} has no stats.json (Mitsuba 3's reference images)", dir.display());
    }
    Ok(dir)
}

/// A linear RGB EXR as row-major pixels (row 0 at the top, as the film).
fn read_exr(path: &Path) -> Result<(u32, u32, Vec<Color>)> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| (resolution.width(), vec![Color::ZERO; resolution.width() * resolution.height()]),
        |(w, px), pos, (r, g, b, _a): (f32, f32, f32, f32)| px[pos.y() * *w + pos.x()] = Color::new(r, g, b),
    )
    .with_context(|| format!("{}: cannot read the reference EXR", path.display()))?;
    let size = image.layer_data.size;
    let (_, pixels) = image.layer_data.channel_data.pixels;
    Ok((size.width() as u32, size.height() as u32, pixels))
}

/// Mitsuba's figures for `name` in stats.json.
fn mitsuba_figures(stats: &serde_json::Value, name: &str, file: &Path) -> Result<MitsubaFigures> {
    let s = &stats[name];
    let num = |k: &str| s[k].as_f64().with_context(|| format!("{}: `{name}.{k}` missing", file.display()));
    let std: Vec<f64> = s["rms_pixel_std_rgb"]
        .as_array()
        .with_context(|| format!("{}: `{name}.rms_pixel_std_rgb` missing", file.display()))?
        .iter()
        .filter_map(serde_json::Value::as_f64)
        .collect();
    if std.len() != 3 {
        bail!("{}: `{name}.rms_pixel_std_rgb` is not three numbers", file.display());
    }
    Ok(MitsubaFigures {
        spp: num("spp")? as u32,
        render_s: num("render_s")?,
        rms_pixel_std: (std.iter().map(|v| v * v).sum::<f64>() / 3.0).sqrt(),
    })
}

/// Runs the preset: 16 spp per structure and convergence up to 256 spp (`--quick`: 2
/// and 4, the first scene only, two structures); the references' own size (an image of
/// another size could not be compared with them), `--repeat` timed runs per structure.
pub fn run(config: &BenchConfig, mismatches: &mut Vec<Mismatch>) -> Result<PathResult> {
    let dir = reference_dir(config)?;
    let stats_path = dir.join("stats.json");
    let stats: serde_json::Value = serde_json::from_slice(
        &std::fs::read(&stats_path).with_context(|| format!("cannot read {}", stats_path.display()))?,
    )
    .with_context(|| format!("{}: not JSON", stats_path.display()))?;
    let labels: Vec<AccelSpec> = if !config.accels.is_empty() {
        config.accels.clone()
    } else {
        let n = if config.quick { 2 } else { DEFAULT_STRUCTURES.len() };
        DEFAULT_STRUCTURES[..n].iter().map(|s| s.parse().expect("the default structures parse")).collect()
    };
    let (spp, max_spp) = if config.quick { (2, 4) } else { (16, 256) };
    let names = if config.quick { &SCENES[..1] } else { &SCENES[..] };
    let repeat = config.repeat.max(1);
    let mut scenes = Vec::new();
    let bar = progress_bar(config.progress, (names.len() * (labels.len() + 1)) as u64);
    for &name in names {
        let xml = dir.join("sphere").join(format!("{name}.xml"));
        let (w, h, reference) = read_exr(&dir.join("sphere").join(format!("{name}.exr")))?;
        let mitsuba = mitsuba_figures(&stats, name, &stats_path)?;
        let scene = load_file(&xml).with_context(|| format!("--preset path: {}", xml.display()))?;
        let frame = scene.frame(0.0);
        if (frame.settings.width, frame.settings.height) != (w, h) {
            bail!(
                "{}: {}×{} where its reference is {w}×{h}",
                xml.display(),
                frame.settings.width,
                frame.settings.height
            );
        }
        let max_depth = frame.settings.max_recursion_level + 1;
        let options =
            |spp, passes| RenderOptions { integrator: IntegratorKind::Path, spp, passes, ..Default::default() };
        let mut runs = Vec::new();
        let mut first: Option<Film> = None;
        let mut convergence = Vec::new();
        for spec in &labels {
            bar.set_message(format!("path: {name} over {spec}"));
            let t = Instant::now();
            let accel =
                spec.build(&frame.mesh, Some(frame.camera.position)).with_context(|| format!("path: {spec}"))?;
            let build_ms = ms(t);
            let accel: &dyn Accel = accel.as_ref();
            let mut times = Vec::new();
            let (mut film, mut stats) = render(&frame, accel, &options(spp, 1));
            for _ in 0..repeat {
                let t = Instant::now();
                (film, stats) = render(&frame, accel, &options(spp, 1));
                times.push(ms(t));
            }
            times.sort_by(f64::total_cmp);
            let render_ms = times[times.len() / 2];
            let identical = first.as_ref().is_none_or(|f| *f == film);
            if !identical {
                mismatches.push(Mismatch {
                    scene: format!("path ({name})"),
                    accel: spec.to_string(),
                    kind: "render".into(),
                    ray_index: 0,
                    ray: [0.0; 8],
                    expected: format!("the image over {}", labels[0]),
                    got: "a different image".into(),
                });
            }
            let secs = render_ms / 1e3;
            runs.push(PathRun {
                accel: spec.to_string(),
                build_ms,
                render_ms,
                samples_per_s: (w as u64 * h as u64 * spp as u64) as f64 / secs,
                mrays_per_s: stats.total_rays() as f64 / secs / 1e6,
                rays: stats.total_rays(),
                rmse: rmse(&film, &reference),
                image_identical: identical,
            });
            if first.is_none() {
                first = Some(film);
                // Convergence over the first structure: one render per power of two of
                // spp (the sampler stratifies a pixel's samples by their count, so the
                // passes of one progressive render would not be stratified as a whole).
                bar.set_message(format!("path: {name} convergence over {spec}, up to {max_spp} spp"));
                convergence = std::iter::successors(Some(1u32), |n| Some(n * 2))
                    .take_while(|n| *n <= max_spp)
                    .map(|n| {
                        let t = Instant::now();
                        let (film, _) = render(&frame, accel, &options(n, 1));
                        let ms = ms(t);
                        let rmse = rmse(&film, &reference);
                        PathConvergencePoint { spp: n, ms, rmse, mitsuba_ms: mitsuba.ms_for(rmse) }
                    })
                    .collect();
                bar.inc(1);
            }
            bar.inc(1);
        }
        scenes.push(PathScene {
            name: name.to_string(),
            xml: xml.display().to_string(),
            triangles: frame.mesh.triangle_count(),
            width: w,
            height: h,
            max_depth,
            spp,
            runs,
            convergence,
            mitsuba,
        });
    }
    bar.finish_and_clear();
    Ok(PathResult { scenes })
}

/// The section of report.md.
pub fn markdown(r: &PathResult, png: bool, s: &mut String) {
    let _ = writeln!(
        s,
        "## Preset path — the path tracer against Mitsuba 3's references\n\n\
         `--integrator path` on the scenes of `shared/reference` at their own size. Per structure: one \
         render at the spp shown (median), camera samples/s, Mrays/s over every ray the structure \
         answered (camera, shadow, bounce), RMSE against Mitsuba's 4096-spp image. Convergence: renders at \
         1, 2, 4, … spp over the first structure; Mitsuba's time for the same RMSE is \
         estimated from its reference's render time and pixel noise (`reference/stats.json`).\n"
    );
    for sc in &r.scenes {
        let _ = writeln!(
            s,
            "### {} ({} triangles, {}×{}, max_depth {}, {} spp)\n\n\
             | structure | build ms | render ms | samples/s | Mrays/s | rays | RMSE | image identical |\n\
             |---|--:|--:|--:|--:|--:|--:|---|",
            sc.name, sc.triangles, sc.width, sc.height, sc.max_depth, sc.spp
        );
        for x in &sc.runs {
            let _ = writeln!(
                s,
                "| {} | {:.1} | {:.1} | {:.0} | {:.2} | {} | {:.5} | {} |",
                x.accel,
                x.build_ms,
                x.render_ms,
                x.samples_per_s,
                x.mrays_per_s,
                crate::format::thousands(x.rays),
                x.rmse,
                if x.image_identical { "yes" } else { "**no**" }
            );
        }
        let _ = writeln!(
            s,
            "\n| spp | dynray ms | RMSE | Mitsuba ms for that RMSE (estimated) | Mitsuba / dynray |\n|--:|--:|--:|--:|--:|"
        );
        for p in sc.convergence.iter().filter(|p| p.spp.is_power_of_two()) {
            let (mi, ratio) = match p.mitsuba_ms {
                Some(m) => (format!("{m:.0}"), format!("{:.2}", m / p.ms)),
                None => ("—".into(), "—".into()),
            };
            let _ = writeln!(s, "| {} | {:.0} | {:.5} | {mi} | {ratio} |", p.spp, p.ms, p.rmse);
        }
        let m = &sc.mitsuba;
        let _ = writeln!(
            s,
            "\nMitsuba's reference: {} spp in {:.1} s, RMS pixel noise {:.2e} at that spp.\n",
            m.spp, m.render_s, m.rms_pixel_std
        );
    }
    let ext = if png { "png" } else { "svg" };
    let _ = writeln!(s, "![path tracer convergence](path-convergence.{ext})\n");
}

/// Per scene, RMSE (×1000) against time (ms, log₂ axis): dynray measured at powers of two
/// of spp, Mitsuba's estimate over the same RMSE range, and the 1/√N line from dynray's
/// first point (plus the reference's own noise, the floor both approach).
pub fn chart(r: &PathResult) -> LineChart {
    let panels = r
        .scenes
        .iter()
        .map(|sc| {
            let pts: Vec<&PathConvergencePoint> = sc.convergence.iter().filter(|p| p.spp.is_power_of_two()).collect();
            let measured = pts.iter().map(|p| (p.ms.max(1e-3), p.rmse * 1e3)).collect();
            let m = sc.mitsuba;
            let mitsuba = pts.iter().filter_map(|p| p.mitsuba_ms.map(|t| (t, p.rmse * 1e3))).collect();
            let floor = m.rmse_at(f64::INFINITY);
            let ideal = pts
                .first()
                .map(|p0| {
                    let e1 = (p0.rmse.powi(2) - floor * floor).max(0.0);
                    pts.iter().map(|p| (p.ms.max(1e-3), (e1 / p.spp as f64 + floor * floor).sqrt() * 1e3)).collect()
                })
                .unwrap_or_default();
            Panel {
                title: format!("{} ({} triangles, max_depth {})", sc.name, sc.triangles, sc.max_depth),
                series: vec![
                    Series { name: "dynray (measured)".into(), points: measured, reference: false },
                    Series {
                        name: "Mitsuba 3 (from its reference's time and noise)".into(),
                        points: mitsuba,
                        reference: false,
                    },
                    Series { name: "1/√spp from dynray's 1-spp point".into(), points: ideal, reference: true },
                ],
            }
        })
        .collect();
    LineChart {
        caption: "path: RMSE against Mitsuba 3's 4096-spp reference by render time".into(),
        x_desc: "render time (ms)".into(),
        y_desc: "RMSE (×10⁻³)".into(),
        log2_x: true,
        log_y: true,
        y_from_zero: false,
        panels,
    }
}

/// `--preset path`: the path tracer against Mitsuba 3's references.
pub struct PathTracer;

impl Experiment for PathTracer {
    const PRESET: crate::config::Preset = crate::config::Preset::Path;
    type Output = PathResult;

    fn run(ctx: &mut Lab<'_>) -> anyhow::Result<PathResult> {
        run(ctx.config, ctx.mismatches)
    }

    fn markdown(out: &PathResult, png: bool, s: &mut String) {
        markdown(out, png, s)
    }

    fn charts(out: &PathResult, dir: &std::path::Path, png: bool) -> anyhow::Result<()> {
        crate::charts::save(&chart(out), dir, "path-convergence", png).map(drop)
    }
}
