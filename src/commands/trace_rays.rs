//! `dynray trace-rays`: the file-to-file batch query of `dynray_bench::trace_rays`
//! (docs/trace-rays.md), with its notes and warnings on stderr and its timing line last.

use crate::cli::TraceRaysArgs;
use anyhow::Result;
use dynray_bench::trace_rays::{self, Job, Notice, Query};

pub fn run(a: TraceRaysArgs) -> Result<()> {
    let query = if a.occluded { Query::Occluded } else { Query::Closest(a.fields) };
    let label = a.mesh.display().to_string();
    let pose = |scene: &mut dynray_scene::Scene| super::time::apply(scene, &label, &a.when);
    a.backend.check()?;
    let gpu = a.backend.gpu_options();
    let gpu_build = a.backend.gpu_build;
    let job = Job {
        mesh: &a.mesh,
        rays: &a.rays,
        output: &a.output,
        accel: &a.accel,
        query,
        pose: Some(&pose),
        gpu,
        gpu_build,
    };
    let summary = trace_rays::run(&job, &mut |notice| match notice {
        Notice::Note(m) => eprintln!("dynray: note: {m}"),
        Notice::Warning(w) => eprintln!("dynray: warning: {w}"),
    })?;
    eprintln!("{summary}");
    Ok(())
}
