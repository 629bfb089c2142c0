//! `dynray animate`: the frames of an animated scene to numbered PNGs through the
//! engine's animate job, with a progress bar (docs/animate.md).

use crate::cli::AnimateArgs;
use crate::progress::{duration, Progress};
use anyhow::Result;
use dynray_engine::{AnimateEvent, AnimateJob};
use std::time::{Duration, Instant};

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
    super::usage(job.check())?;
    let loaded = super::load(Some(&a.scene))?;
    let label = loaded.label.clone();
    if a.merge {
        eprintln!("{}", job.merge(loaded)?);
        return Ok(());
    }
    let progress = Progress::new(&label, "{bar:40} frame {pos}/{len} {elapsed} (eta {eta}) {msg}", Duration::ZERO);
    let verb = if a.checkpoints_only { "simulate" } else { "render" };
    let (mut total, mut done, mut started) = (0, 0, Instant::now());
    let mut restored = false;
    let mut on_event = |event: AnimateEvent<'_>| {
        let step = match event {
            AnimateEvent::Resuming { done, of } => {
                return progress.say(&format!("resuming: {done} of {of} frames already there"));
            }
            AnimateEvent::Physics(what) => return progress.say(&format!("physics: {what}")),
            // The first restore says where the run starts; later ones (a checkpoint
            // another task wrote ahead of this one) would be a line a frame.
            AnimateEvent::FromCheckpoint { frame } => {
                if !restored {
                    restored = true;
                    progress.say(&format!("physics continues from the checkpoint of frame {frame}"));
                }
                return;
            }
            AnimateEvent::Started { count } => {
                // Said up front: a BART scene without --frames is hundreds of frames.
                (total, started) = (count, Instant::now());
                progress.say(&format!("{count} frame{} to {verb}", if count == 1 { "" } else { "s" }));
                return progress.update(0, total, String::new);
            }
            AnimateEvent::Simulated { took, .. } => format!("simulated {}", duration(took)),
            AnimateEvent::Frame { update, to_image, .. } => format!("{update}, {}", duration(to_image)),
        };
        done += 1;
        if done == 1 && total > 1 {
            let first = started.elapsed();
            progress.say(&format!(
                "the first frame took {}: all {total} should take about {}",
                duration(first),
                duration(first.mul_f64(total as f64))
            ));
        }
        progress.set_message(step.clone());
        progress.update(done, total, || format!("frame {done}/{total} ({step})"));
    };
    let summary = if a.checkpoints_only { job.simulate(loaded, &mut on_event) } else { job.run(loaded, &mut on_event) };
    progress.finish();
    eprintln!("{}", summary?);
    Ok(())
}
