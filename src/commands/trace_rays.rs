//! `dynray trace-rays`: the engine's trace job from files (docs/trace-rays.md), with its
//! notes and warnings on stderr and its timing line last.

use crate::cli::TraceRaysArgs;
use anyhow::Result;
use dynray_engine::jobs::trace::Notice;
use dynray_engine::{Query, TraceJob};

pub fn run(a: TraceRaysArgs) -> Result<()> {
    let job = TraceJob {
        query: if a.occluded { Query::Occluded } else { Query::Closest(a.fields.clone()) },
        when: a.when.choice(),
        backend: a.backend.choice(),
        mesh: a.mesh,
        rays: a.rays,
        rows: a.rows,
        output: a.output,
        accel: a.accel,
    };
    let summary = job.run(&mut |notice| match notice {
        Notice::Note(m) => eprintln!("dynray: note: {m}"),
        Notice::Warning(w) => eprintln!("dynray: warning: {w}"),
    })?;
    eprintln!("{summary}");
    Ok(())
}
