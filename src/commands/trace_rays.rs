//! `dynray trace-rays`: the file-to-file batch query of `dynray_bench::trace_rays`
//! (docs/trace-rays.md), with its notes and warnings on stderr and its timing line last.

use crate::cli::TraceRaysArgs;
use anyhow::Result;
use dynray_bench::trace_rays::{self, Job, Notice, Query};

pub fn run(a: TraceRaysArgs) -> Result<()> {
    let query = if a.occluded { Query::Occluded } else { Query::Closest(a.fields) };
    let job = Job { mesh: &a.mesh, rays: &a.rays, output: &a.output, accel: &a.accel, query };
    let summary = trace_rays::run(&job, &mut |notice| match notice {
        Notice::Note(m) => eprintln!("dynray: note: {m}"),
        Notice::Warning(w) => eprintln!("dynray: warning: {w}"),
    })?;
    eprintln!("{summary}");
    Ok(())
}
