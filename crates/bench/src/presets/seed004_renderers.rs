//! `--preset seed004`, second part: the seed's renderer comparison. Its "accumulative"
//! tracer (`--integrator cumulative`) against the recursive Whitted tracer it unrolls,
//! each over the A-PIT, the plain A-buffer and the BVH: time per pass, the image error
//! against the recursive image, and how that error falls as passes accumulate.
//!
//! The scene is the built-in demo (a mirror sphere and a glass sphere over a
//! checkerboard: the seed's Fresnel and mirror materials; its model scenes carry no such
//! materials). Per structure: the recursive render; the cumulative one with every bounce
//! expanded (`K = max_recursion_level`, which must be Whitted's image to rounding); and
//! `K = 0` over `passes` passes, the seed's fully "chosen" form, timed per pass with its
//! RMSE after each. Every structure returns bit-identical hits, so the images of all
//! three are compared too and must be identical (a difference is a mismatch).

use super::experiment::{Experiment, Lab};
use crate::config::BenchConfig;
use crate::line_chart::{LineChart, Panel, Series};
use crate::measure::ms;
use crate::progress::progress_bar;
use crate::results::Mismatch;
use crate::scenes::{load_scenes, DEMO};
use anyhow::{Context, Result};
use dynray_accel::{Accel, AccelSpec};
use dynray_render::{render, Film, IntegratorKind, IntegratorParams, RenderOptions};
use serde::{Deserialize, Serialize};
use std::fmt::Write;
use std::sync::Mutex;
use std::time::Instant;

/// `--preset seed004`'s renderer comparison (`presets::seed004_renderers`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed004Renderers {
    /// Scene rendered.
    pub scene: String,
    /// Its triangles.
    pub triangles: usize,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The scene's `max_recursion_level` (the full branch depth used).
    pub max_recursion_level: u32,
    /// Passes of the `K = 0` renders (one sample per pixel each).
    pub passes: u32,
    /// One entry per structure.
    pub runs: Vec<RendererRun>,
    /// RMSE against Whitted's image after each pass of `K = 0` (the first structure's;
    /// every structure's images are identical).
    pub convergence: Vec<ConvergencePoint>,
}

/// Both renderers over one structure.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RendererRun {
    /// `--accels` spelling.
    pub accel: String,
    /// Build, ms (one build).
    pub build_ms: f64,
    /// Recursive Whitted render, median, ms.
    pub whitted_ms: f64,
    /// Rays of the Whitted render (primary + shadow + secondary).
    pub whitted_rays: u64,
    /// Cumulative render with every bounce expanded, median, ms.
    pub full_branch_ms: f64,
    /// Its largest per-channel relative difference to Whitted's image.
    pub full_branch_max_rel_diff: f64,
    /// Cumulative `K = 0`: median render time over the passes / passes, ms.
    pub pass_ms: f64,
    /// Rays per pass of that render.
    pub pass_rays: u64,
    /// Its RMSE against Whitted's image after the last pass.
    pub rmse: f64,
    /// Whether this structure's images equal the first structure's, bit for bit.
    pub images_identical: bool,
}

/// The error after some passes.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct ConvergencePoint {
    /// Passes accumulated.
    pub passes: u32,
    /// RMSE over every channel against Whitted's image.
    pub rmse: f64,
}

/// The structures compared, as `--accels` spells them (the study's middle resolution).
pub const STRUCTURES: [&str; 3] = ["apit:resolution=64", "abuffer:resolution=64", "bvh"];

/// Largest relative difference per channel allowed between the fully expanded
/// cumulative image and Whitted's: the two sum the same terms in another order (a few
/// f32 ulps per term, see `dynray_render::Cumulative`).
pub const FULL_BRANCH_TOLERANCE: f64 = 1e-5;

/// Root-mean-square difference over every channel of every pixel.
pub fn rmse(a: &Film, b: &Film) -> f64 {
    let (pa, pb) = (a.pixels(), b.pixels());
    let sq: f64 = pa.iter().zip(&pb).flat_map(|(x, y)| (*x - *y).to_array()).map(|d| (d as f64).powi(2)).sum();
    (sq / (3 * pa.len().max(1)) as f64).sqrt()
}

/// Largest per-channel difference relative to the larger magnitude (floored at 1e-3).
fn max_rel_diff(a: &Film, b: &Film) -> f64 {
    let (pa, pb) = (a.pixels(), b.pixels());
    pa.iter()
        .zip(&pb)
        .flat_map(|(x, y)| x.to_array().into_iter().zip(y.to_array()))
        .map(|(x, y)| ((x - y).abs() / x.abs().max(y.abs()).max(1e-3)) as f64)
        .fold(0.0, f64::max)
}

/// Runs the comparison: 512×512 and 16 passes (the seed's size), `--quick` 64×48 and 4
/// passes, `--width/--height` override the size.
pub fn run(config: &BenchConfig, mismatches: &mut Vec<Mismatch>) -> Result<Seed004Renderers> {
    let (width, height) = if config.size_given {
        (config.width, config.height)
    } else if config.quick {
        (64, 48)
    } else {
        (512, 512)
    };
    let passes: u32 = if config.quick { 4 } else { 16 };
    let scene = load_scenes(&[DEMO.to_string()], config.scenes_dir.as_deref())?.remove(0);
    let mut frame = scene.frame;
    frame.settings.width = width;
    frame.settings.height = height;
    let max_level = frame.settings.max_recursion_level;
    let repeat = config.repeat.max(1);
    let options = |integrator, k, passes| RenderOptions {
        integrator,
        params: IntegratorParams { branch_depth: k },
        passes,
        spp: 1,
        ..Default::default()
    };
    let mut runs = Vec::new();
    let mut convergence = Vec::new();
    let mut first: Option<(Film, Film)> = None;
    let bar = progress_bar(config.progress, STRUCTURES.len() as u64);
    for label in STRUCTURES {
        bar.set_message(format!("seed004 renderers: whitted and cumulative over {label}"));
        let spec: AccelSpec = label.parse().map_err(|e| anyhow::anyhow!("seed004: bad structure `{label}`: {e}"))?;
        let t = Instant::now();
        let accel =
            spec.build(&frame.mesh, Some(frame.camera.position)).with_context(|| format!("seed004: {label}"))?;
        let build_ms = ms(t);
        let accel: &dyn Accel = accel.as_ref();
        let timed = |o: &RenderOptions<'_>| {
            let mut times = Vec::new();
            let mut out = render(&frame, accel, o);
            for _ in 0..repeat {
                let t = Instant::now();
                out = render(&frame, accel, o);
                times.push(ms(t));
            }
            times.sort_by(f64::total_cmp);
            (out, times[times.len() / 2])
        };
        let ((whitted, ws), whitted_ms) = timed(&options(IntegratorKind::Whitted, 0, 1));
        let ((full, fs), full_branch_ms) = timed(&options(IntegratorKind::Cumulative, max_level, 1));
        let full_diff = max_rel_diff(&full, &whitted);
        if full_diff > FULL_BRANCH_TOLERANCE || fs.secondary_rays != ws.secondary_rays {
            mismatches.push(mismatch(label, format!("full-branch cumulative off Whitted by {full_diff:e} relative")));
        }
        // K = 0 over the passes, recording the error after each; the timed run is the
        // last repetition.
        let errors = Mutex::new(Vec::new());
        let record = |pass: u32, film: &Film| errors.lock().unwrap().push((pass, rmse(film, &whitted)));
        let mut o = options(IntegratorKind::Cumulative, 0, passes);
        o.pass_done = Some(&record);
        let ((chosen, cs), chosen_ms) = timed(&o);
        let errors = errors.into_inner().unwrap_or_default();
        let last: Vec<(u32, f64)> = errors[errors.len().saturating_sub(passes as usize)..].to_vec();
        let identical = match &first {
            None => {
                convergence = last.iter().map(|&(passes, rmse)| ConvergencePoint { passes, rmse }).collect();
                first = Some((whitted.clone(), chosen.clone()));
                true
            }
            Some((w0, c0)) => *w0 == whitted && *c0 == chosen,
        };
        if !identical {
            mismatches.push(mismatch(label, format!("images differ from {}'s", STRUCTURES[0])));
        }
        runs.push(RendererRun {
            accel: label.to_string(),
            build_ms,
            whitted_ms,
            whitted_rays: ws.total_rays(),
            full_branch_ms,
            full_branch_max_rel_diff: full_diff,
            pass_ms: chosen_ms / passes as f64,
            pass_rays: cs.total_rays() / passes as u64,
            rmse: last.last().map_or(f64::NAN, |p| p.1),
            images_identical: identical,
        });
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(Seed004Renderers {
        scene: scene.name,
        triangles: frame.mesh.triangle_count(),
        width,
        height,
        max_recursion_level: max_level,
        passes,
        runs,
        convergence,
    })
}

fn mismatch(accel: &str, what: String) -> Mismatch {
    Mismatch {
        scene: "seed004 renderers (demo)".into(),
        accel: accel.to_string(),
        kind: "render".into(),
        ray_index: 0,
        ray: [0.0; 8],
        expected: "cumulative image equal to (expected value of) Whitted's".into(),
        got: what,
    }
}

/// The section of report.md.
pub fn markdown(r: &Seed004Renderers, png: bool, s: &mut String) {
    let _ = writeln!(
        s,
        "### seed004: cumulative against recursive Whitted (seed 004 §2.7)\n\n\
         {} ({} triangles) at {}×{}, one ray per pixel, `max_recursion_level` {}. Whitted: the recursive \
         tracer. Full branch: `--integrator cumulative --branch-depth {}` (every bounce expanded; its \
         largest relative difference to Whitted's image beside it). K = 0: `--branch-depth 0`, one child \
         chosen by Fresnel at every hit, {} passes; time per pass and RMSE against Whitted's image after \
         the last pass.\n",
        r.scene, r.triangles, r.width, r.height, r.max_recursion_level, r.max_recursion_level, r.passes
    );
    let _ = writeln!(
        s,
        "| structure | build ms | Whitted ms | full branch ms (max rel. diff) | K = 0 ms per pass | rays per pass (Whitted) | RMSE after {} passes | images identical |\n|---|--:|--:|--:|--:|--:|--:|---|",
        r.passes
    );
    for x in &r.runs {
        let _ = writeln!(
            s,
            "| {} | {:.1} | {:.1} | {:.1} ({:.1e}) | {:.1} | {} ({}) | {:.4} | {} |",
            x.accel,
            x.build_ms,
            x.whitted_ms,
            x.full_branch_ms,
            x.full_branch_max_rel_diff,
            x.pass_ms,
            crate::format::thousands(x.pass_rays),
            crate::format::thousands(x.whitted_rays),
            x.rmse,
            if x.images_identical { "yes" } else { "**no**" }
        );
    }
    let ext = if png { "png" } else { "svg" };
    let _ = writeln!(s, "\n![cumulative convergence](seed004-convergence.{ext})\n");
    let pts: Vec<String> = r.convergence.iter().map(|p| format!("{}: {:.4}", p.passes, p.rmse)).collect();
    let _ = writeln!(s, "RMSE against Whitted by passes (K = 0): {}.\n", pts.join(", "));
}

/// RMSE (×1000, so that axis labels keep their digits) against passes at powers of two
/// (a readable log₂ axis; report.json has every pass), beside the 1/√N line an unbiased
/// estimator follows.
pub fn chart(r: &Seed004Renderers) -> LineChart {
    let measured: Vec<(f64, f64)> =
        r.convergence.iter().filter(|p| p.passes.is_power_of_two()).map(|p| (p.passes as f64, p.rmse * 1e3)).collect();
    let e1 = measured.first().map_or(0.0, |p| p.1);
    let ideal = measured.iter().map(|&(n, _)| (n, e1 / n.sqrt())).collect();
    LineChart {
        caption: format!(
            "seed004: cumulative tracer (K = 0) converging to Whitted's image, {} {}x{}",
            r.scene, r.width, r.height
        ),
        x_desc: "passes (1 sample per pixel each)".into(),
        y_desc: "RMSE against the recursive image (×10⁻³)".into(),
        log2_x: true,
        log_y: true,
        y_from_zero: false,
        panels: vec![Panel {
            title: format!("{} triangles, max recursion level {}", r.triangles, r.max_recursion_level),
            series: vec![
                Series { name: "measured RMSE".into(), points: measured, reference: false },
                Series { name: "1/√N from pass 1".into(), points: ideal, reference: true },
            ],
        }],
    }
}

/// `--preset seed004`'s renderer comparison.
pub struct Seed004RenderersRun;

impl Experiment for Seed004RenderersRun {
    const PRESET: crate::config::Preset = crate::config::Preset::Seed004;
    type Output = Seed004Renderers;

    fn run(ctx: &mut Lab<'_>) -> anyhow::Result<Seed004Renderers> {
        run(ctx.config, ctx.mismatches)
    }

    fn markdown(out: &Seed004Renderers, png: bool, s: &mut String) {
        markdown(out, png, s)
    }

    fn charts(out: &Seed004Renderers, dir: &std::path::Path, png: bool) -> anyhow::Result<()> {
        crate::charts::save(&chart(out), dir, "seed004-convergence", png).map(drop)
    }
}
