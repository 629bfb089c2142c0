//! `dynray animate`: the frames of an animated scene to numbered PNGs through the
//! engine's animate job, with a progress bar (docs/animate.md).

use crate::cli::AnimateArgs;
use anyhow::Result;
use dynray_engine::{AnimateEvent, AnimateJob};
use indicatif::{ProgressBar, ProgressStyle};

pub fn run(a: AnimateArgs) -> Result<()> {
    let job = AnimateJob {
        out: a.out,
        frames: a.frames,
        clip: a.clip,
        fps: a.fps,
        accel: a.accel,
        update: a.update,
        scene_accel: a.scene_accel,
        width: a.width,
        height: a.height,
        spp: a.spp,
        integrator: a.integrator,
        seed: a.seed,
        shard: a.shard,
        resume: a.resume,
        checkpoint_every: a.checkpoint_every,
        await_checkpoints: a.await_checkpoints,
        export_meshes: a.export_meshes,
        flat_shading: a.flat_shading,
        backend: a.backend.choice(),
        gpu_strategy: a.gpu_strategy,
    };
    job.check()?;
    let loaded = super::load(Some(&a.scene))?;
    let label = loaded.label.clone();
    let bar = ProgressBar::hidden();
    bar.set_style(ProgressStyle::with_template("{bar:40} frame {pos}/{len} {elapsed} (eta {eta}) {msg}").unwrap());
    if a.merge {
        eprintln!("{}", job.merge(loaded)?);
        return Ok(());
    }
    let mut restored = false;
    let mut on_event = |event: AnimateEvent<'_>| match event {
        AnimateEvent::Resuming { done, of } => eprintln!("{label}: resuming: {done} of {of} frames already there"),
        AnimateEvent::Physics(what) => eprintln!("{label}: physics: {what}"),
        // The first restore says where the run starts; later ones (a checkpoint another
        // task wrote ahead of this one) would be a line a frame.
        AnimateEvent::FromCheckpoint { frame } => {
            if !restored {
                restored = true;
                bar.suspend(|| eprintln!("{label}: physics continues from the checkpoint of frame {frame}"));
            }
        }
        AnimateEvent::Simulated { took, .. } => {
            bar.set_message(format!("simulated {:.0} ms", took.as_secs_f64() * 1e3));
            bar.inc(1);
        }
        AnimateEvent::Started { count } => {
            bar.set_length(count as u64);
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
        AnimateEvent::Frame { update, to_image, .. } => {
            bar.set_message(format!("{update} {:.0} ms", to_image.as_secs_f64() * 1e3));
            bar.inc(1);
        }
    };
    let summary = if a.checkpoints_only { job.simulate(loaded, &mut on_event) } else { job.run(loaded, &mut on_event) };
    bar.finish_and_clear();
    eprintln!("{}", summary?);
    Ok(())
}
