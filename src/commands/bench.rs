//! `dynray bench`: raw options -> a validated [`BenchConfig`] -> the bench library; exits
//! non-zero (after writing the report) when any structure disagrees with brute force.

use crate::cli::BenchArgs;
use anyhow::{bail, Result};
use dynray_bench::config::GpuBench;
use dynray_bench::{parse_accels, run::mismatch_summary, BenchConfig, Preset};

pub fn run(a: BenchArgs) -> Result<()> {
    if let Some(dir) = &a.replot {
        let report = dynray_bench::run::replot(dir, !a.no_png)?;
        eprintln!("dynray bench: charts and report.md of {} redrawn -> {}", report.started_utc, dir.display());
        return Ok(());
    }
    let config = config(a)?;
    let report = dynray_bench::run(&config)?;
    eprintln!(
        "dynray bench: preset {}, {} scene measurement(s) on {} threads, {} – {} -> {}",
        report.config.presets.join("+"),
        report.scene_runs(),
        report.threads,
        report.started_utc,
        report.finished_utc,
        config.out.join("report.md").display()
    );
    if let Some(m) = mismatch_summary(&report.mismatches) {
        bail!("{m} (report written to {})", config.out.display());
    }
    Ok(())
}

fn list(s: &str) -> Vec<String> {
    s.split(',').map(str::trim).filter(|x| !x.is_empty()).map(String::from).collect()
}

fn config(a: BenchArgs) -> Result<BenchConfig> {
    let mut c = BenchConfig::new(a.quick);
    if let Some(s) = &a.scenes {
        c.scenes = list(s);
        if c.scenes.is_empty() {
            bail!("--scenes: no scene named");
        }
    }
    if let Some(s) = &a.accels {
        c.accels = parse_accels(s)?;
    }
    if let Some(rays) = a.rays {
        c.rays = rays;
        // Each kind once, in the order first named.
        let mut seen = Vec::new();
        c.rays.retain(|k| {
            !seen.contains(k) && {
                seen.push(*k);
                true
            }
        });
    }
    if let Some(w) = a.width {
        c.width = w;
        c.size_given = true;
    }
    if let Some(h) = a.height {
        c.height = h;
        c.size_given = true;
    }
    if let Some(f) = a.framing {
        c.framing = f;
    }
    if let Some(r) = a.repeat {
        c.repeat = r; // at least 1: clap checks the range
    }
    if let Some(p) = &a.preset {
        c.presets = Preset::parse(p)?;
    }
    if let Some(f) = a.frames {
        if f == 0 {
            bail!("--frames must be at least 1");
        }
        c.frames = f;
    }
    if let Some(v) = &a.verify {
        c.verify_sample = match v.as_str() {
            "all" => None,
            n => match n.parse::<usize>() {
                Ok(n) if n > 0 => Some(n),
                _ => bail!("--verify must be a positive count or `all`, got `{v}`"),
            },
        };
    }
    super::usage(a.backend.choice().check())?;
    c.gpu = a.backend.gpu_options().map(|options| GpuBench { options, build: a.backend.gpu_build });
    c.out = a.out;
    c.scenes_dir = a.scenes_dir;
    c.png = !a.no_png;
    Ok(c)
}
