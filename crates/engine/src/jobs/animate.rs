//! The animate job: the frames of an animated scene to numbered PNGs through the frame
//! step ([`FrameStep`]: pose, physics, structure update) and the tracer, with per-frame
//! timings, a preview, shards for array jobs, resumption, physics checkpoints and the
//! merge of an array job's timings (docs/animate.md).

use super::animate_merge::frame_done;
use super::shard::Shard;
use super::{checkpoints, preview};
use crate::backend::BackendChoice;
use crate::fields::Fields;
use crate::format::thousands;
use crate::frame_step::{FrameSettings, FrameStep, Stage};
use crate::load::Loaded;
use crate::timeline::shape_timeline;
use crate::tracer::{GpuChoice, Tracer};
use anyhow::{bail, Context, Result};
use dynray_accel::{AccelSpec, SceneLayout, UpdatePolicy};
use dynray_gpu::GpuStrategy;
use dynray_render::{write_image, IntegratorKind, RenderOptions};
use dynray_scene::{Frame, Timeline};
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Columns of `timings.csv`, one row per rendered frame.
pub const TIMINGS_HEADER: &str = "frame,time_s,pose_ms,update,update_ms,sah_ratio,render_ms,time_to_image_ms,rays";

/// Most frames one run renders (a shard's, with `--shard`): a million PNGs is days of
/// rendering already, and the run keeps its list of frames in memory.
pub const MAX_FRAMES_PER_RUN: u64 = 1_000_000;

/// `DIR/frame_NNNN.png`.
pub fn frame_path(dir: &Path, k: u32) -> PathBuf {
    dir.join(format!("frame_{k:04}.png"))
}

/// Everything an animation run is asked.
#[derive(Clone, Debug)]
pub struct AnimateJob {
    /// The folder of frames, timings and preview.
    pub out: PathBuf,
    /// The frames `A..=B` to render; `None`: all.
    pub frames: Option<(u32, u32)>,
    /// The clip to play.
    pub clip: Option<String>,
    /// The timeline's frame rate, replacing the file's.
    pub fps: Option<f32>,
    /// The structure.
    pub accel: AccelSpec,
    /// How it follows the motion.
    pub update: UpdatePolicy,
    /// How actors are arranged into structures.
    pub scene_accel: SceneLayout,
    /// Image size; `None` keeps the scene's.
    pub width: Option<u32>,
    /// Image size; `None` keeps the scene's.
    pub height: Option<u32>,
    /// Samples per pixel.
    pub spp: u32,
    /// Whitted, cumulative or path.
    pub integrator: IntegratorKind,
    /// Sampler seed.
    pub seed: u64,
    /// One task's part of the frames (`--shard K/N[:blocks]`); `None`: all of them.
    pub shard: Option<Shard>,
    /// Skip frames whose PNG is there.
    pub resume: bool,
    /// With physics, write the simulation's state every this many frames (frames
    /// `k % every == 0`) to `OUT/checkpoints/`; 0: never. Runs continue from the latest
    /// checkpoint at or before each frame they render instead of from time 0.
    pub checkpoint_every: u32,
    /// With physics, wait up to this long for the checkpoint of each frame to appear
    /// (written by a `--checkpoints-only` job running alongside) before simulating to it;
    /// after one wait times out the run simulates on its own. `None`: never wait.
    pub await_checkpoints: Option<Duration>,
    /// Also write each frame's world-space triangles as OBJ.
    pub export_meshes: bool,
    /// Flat shading for every actor.
    pub flat_shading: bool,
    /// CPU or GPU.
    pub backend: BackendChoice,
    /// Seed 003's GPU strategy.
    pub gpu_strategy: GpuStrategy,
}

/// What a run tells its front end as it goes.
#[derive(Clone, Copy, Debug)]
pub enum AnimateEvent<'a> {
    /// Resuming: `done` of the shard's `of` frames are there already.
    Resuming {
        /// Frames found.
        done: usize,
        /// Frames of this shard.
        of: usize,
    },
    /// The scene has physics: its description.
    Physics(&'a str),
    /// The simulation continues from the checkpoint of this frame.
    FromCheckpoint {
        /// The checkpoint's frame.
        frame: u32,
    },
    /// `--checkpoints-only`: the simulation reached frame `k`.
    Simulated {
        /// Its number.
        k: u32,
        /// Time since the previous frame.
        took: Duration,
    },
    /// `count` frames are about to be rendered.
    Started {
        /// Frames to render.
        count: usize,
    },
    /// Frame `k` is written.
    Frame {
        /// Its number.
        k: u32,
        /// What the structure's update did (`kept`, `refit`, `rebuilt`, `moved`).
        update: &'static str,
        /// Pose to written image.
        to_image: Duration,
    },
}

impl AnimateJob {
    /// Checks what needs no scene: the shard, the frame range, the backend's flags and
    /// what the GPU can trace and integrate.
    pub fn check(&self) -> Result<()> {
        self.backend.check()?;
        if self.backend.is_gpu() {
            self.accel.binary_bvh()?;
            let probe = RenderOptions { integrator: self.integrator, ..Default::default() };
            crate::tracer::gpu_integrator(&probe, self.gpu_strategy)?;
        }
        if let Some(s) = self.shard {
            if s.count == 0 || s.index >= s.count {
                bail!("--shard {s}: K must be below N");
            }
        }
        if let Some((a, b)) = self.frames {
            if a > b {
                bail!("--frames {a}..{b}: the first frame is after the last");
            }
        }
        Ok(())
    }

    /// Renders the frames of `loaded`; `events` hears of the progress. Returns the
    /// summary line.
    pub fn run(&self, mut loaded: Loaded, events: &mut dyn FnMut(AnimateEvent<'_>)) -> Result<String> {
        let Plan { label, timeline, first, last, shard } = self.plan(&mut loaded)?;
        // Refused options and a missing GPU fail before anything is written.
        let options =
            RenderOptions { spp: self.spp, seed: self.seed, integrator: self.integrator, ..Default::default() };
        let fields = Fields::load(&loaded.scene.distance_fields, &label)?;
        let tracer = match &self.backend.gpu {
            None => Tracer::cpu(&self.accel, self.update, self.scene_accel, fields),
            Some(_) if !fields.is_empty() => {
                bail!("{label}: scenes with `adf` blocks render on the CPU only; drop --backend gpu")
            }
            Some(gpu) => {
                let choice = GpuChoice {
                    options: gpu,
                    build: self.backend.gpu_build,
                    strategy: self.gpu_strategy,
                    context: None,
                };
                Tracer::gpu(&self.accel, self.update, &options, choice).with_context(|| label.clone())?
            }
        };
        let out = &self.out;
        std::fs::create_dir_all(out).with_context(|| format!("{}: cannot create the output folder", out.display()))?;
        let mine = shard.frames(first, last);
        // A frame counts as done when its PNG is there and not empty (frames are renamed
        // into place whole, but a disk that filled up or a copy may leave 0 bytes).
        let todo: Vec<u32> = mine.iter().copied().filter(|&k| !(self.resume && frame_done(out, k))).collect();
        if todo.len() < mine.len() {
            events(AnimateEvent::Resuming { done: mine.len() - todo.len(), of: mine.len() });
        }
        let timings_name = shard.timings_name();
        let timings_path = out.join(&timings_name);
        let mut timings = open_timings(&timings_path, self.resume)?;

        // Built before the loop (sampling and neighbourhoods once); each frame steps it on.
        let settings = FrameSettings { width: self.width, height: self.height, ..Default::default() };
        let stage = Stage::new(loaded.scene, &label, settings)?;
        if let Some(w) = stage.world() {
            events(AnimateEvent::Physics(&w.describe()));
        }
        let physics = stage.world().is_some();
        let mut step = FrameStep::new(stage, tracer);
        events(AnimateEvent::Started { count: todo.len() });
        let started = Instant::now();
        let mut rays_total = 0u64;
        // The frame the simulation stands at (`None`: time 0).
        let mut at = None;
        let mut wait = self.await_checkpoints;
        for &k in &todo {
            let t = timeline.time_of(k);
            let t0 = Instant::now();
            if physics {
                catch_up(&mut step.stage, out, k, &mut at, &mut wait, events)?;
            }
            let at_frame = || format!("{label}: frame {k}");
            let report = step.advance_to(t).with_context(at_frame)?;
            at = Some(k);
            if physics && self.checkpoint_every > 0 && k.is_multiple_of(self.checkpoint_every) {
                checkpoints::save(&step.stage, out, k)?;
            }
            let t1 = Instant::now();
            let frame = step.stage.frame();
            let (film, stats) = step.tracer.render(frame, &options).with_context(at_frame)?;
            let render_time = t1.elapsed();
            let to_image = t0.elapsed();
            write_image(&film, &frame_path(out, k))?;
            if self.export_meshes {
                write_obj(frame, &out.join(format!("mesh_{k:04}.obj")))?;
            }
            let ms = |d: Duration| d.as_secs_f64() * 1e3;
            let update = report.update;
            let ratio = update.cost_ratio.map(|r| format!("{r:.4}")).unwrap_or_default();
            writeln!(
                timings,
                "{k},{t},{:.3},{},{:.3},{ratio},{:.3},{:.3},{}",
                ms(report.pose),
                update.action.name(),
                ms(update.time),
                ms(render_time),
                ms(to_image),
                stats.total_rays()
            )
            .and_then(|()| timings.flush())
            .with_context(|| format!("{}: cannot write", timings_path.display()))?;
            rays_total += stats.total_rays();
            events(AnimateEvent::Frame { k, update: update.action.name(), to_image });
        }
        let all: Vec<PathBuf> = (first..=last).map(|k| frame_path(out, k)).collect();
        let preview_note = if all.iter().all(|p| p.is_file()) {
            let path = out.join("preview.gif");
            preview::write_gif(&all, timeline.frame_rate, &path)?;
            format!(", preview {}", path.display())
        } else {
            String::new()
        };
        Ok(format!(
            "{label}: {} frames of {first}..={last} ({} triangles, {}), {} rays in {:.2} s -> {}/frame_NNNN.png, {timings_name}{preview_note}",
            todo.len(),
            thousands(step.stage.frame().mesh.triangle_count() as u64),
            step.tracer.describe(),
            thousands(rays_total),
            started.elapsed().as_secs_f64(),
            out.display()
        ))
    }
}

/// What every mode of the job settles first: the scene shaded and its timeline shaped,
/// the frame range, and this task's shard.
pub(super) struct Plan {
    pub(super) label: String,
    pub(super) timeline: Timeline,
    pub(super) first: u32,
    pub(super) last: u32,
    pub(super) shard: Shard,
}

impl AnimateJob {
    pub(super) fn plan(&self, loaded: &mut Loaded) -> Result<Plan> {
        self.check()?;
        let label = loaded.label.clone();
        loaded.shade(self.flat_shading)?;
        shape_timeline(&mut loaded.scene, &label, self.clip.as_deref(), self.fps)?;
        let timeline = loaded.scene.animation.timeline;
        let last_frame = timeline.frames - 1; // shape_timeline refuses a timeline without frames
        let (first, last) = self.frames.unwrap_or((0, last_frame));
        if last > last_frame {
            bail!(
                "{label}: --frames {first}..{last} goes past the last frame, {last_frame} ({} frames at {} fps)",
                timeline.frames,
                timeline.frame_rate
            );
        }
        let shard = self.shard.unwrap_or(Shard::WHOLE);
        // The frames of this shard, counted before anything lists them: a timeline of 2^32
        // frames (an AFF `a 0 1 4000000000`, `--fps 5e9`) must not become an 8 GiB list.
        let mine_count = shard.frame_count(first, last);
        if mine_count > MAX_FRAMES_PER_RUN {
            bail!(
                "{label}: {mine_count} frames in one run ({first}..={last}{}), more than {MAX_FRAMES_PER_RUN}: \
                 choose a range with --frames A..B or split the run with --shard K/N",
                if shard.count > 1 { format!(", shard {shard}") } else { String::new() }
            );
        }
        Ok(Plan { label, timeline, first, last, shard })
    }

    /// `--checkpoints-only`: simulates the physics of this task's frames without
    /// rendering, writing a checkpoint every `checkpoint_every` frames — the first job of
    /// a chain whose render tasks then start from the checkpoints (docs/animate.md,
    /// "Physics checkpoints"). Returns the summary line.
    pub fn simulate(&self, mut loaded: Loaded, events: &mut dyn FnMut(AnimateEvent<'_>)) -> Result<String> {
        let Plan { label, timeline, first, last, shard } = self.plan(&mut loaded)?;
        if self.checkpoint_every == 0 {
            bail!("--checkpoints-only with --checkpoint-every 0 would write nothing");
        }
        let settings = FrameSettings { width: self.width, height: self.height, ..Default::default() };
        let mut stage = Stage::new(loaded.scene, &label, settings)?;
        let Some(w) = stage.world() else {
            bail!("{label}: no actor has an `elastic` block, so there is no physics to checkpoint")
        };
        events(AnimateEvent::Physics(&w.describe()));
        let out = &self.out;
        std::fs::create_dir_all(out).with_context(|| format!("{}: cannot create the output folder", out.display()))?;
        // Through the last frame of this task's part (its block, or the whole range).
        let frames = shard.frames(first, last);
        let (Some(&from), Some(&to)) = (frames.first(), frames.last()) else {
            return Ok(format!("{label}: shard {shard} holds no frames of {first}..={last}"));
        };
        events(AnimateEvent::Started { count: (to - from + 1) as usize });
        let started = Instant::now();
        let mut at = None;
        let mut written = 0;
        for k in from..=to {
            let t0 = Instant::now();
            catch_up(&mut stage, out, k, &mut at, &mut None, events)?;
            stage.pose(timeline.time_of(k)).with_context(|| format!("{label}: frame {k}"))?;
            at = Some(k);
            if k.is_multiple_of(self.checkpoint_every) && !checkpoints::path(out, k).is_file() {
                checkpoints::save(&stage, out, k)?;
                written += 1;
            }
            events(AnimateEvent::Simulated { k, took: t0.elapsed() });
        }
        let steps = stage.world().map_or(0, |w| w.steps());
        Ok(format!(
            "{label}: simulated to frame {to} (step {steps}) in {:.2} s, {written} checkpoints written -> {}",
            started.elapsed().as_secs_f64(),
            checkpoints::dir(out).display()
        ))
    }
}

/// Before the simulation steps to frame `k`: restores the latest checkpoint at or before
/// `k` when it is ahead of where the simulation stands (`at`), so a resumed run, a block
/// of frames, or a shard behind another one does not step through what is saved.
///
/// With `wait`, first waits (polling) up to that long for frame `k`'s own checkpoint; a
/// wait that times out clears `wait`, so a simulation job that died costs one timeout.
fn catch_up(
    stage: &mut Stage,
    out: &Path,
    k: u32,
    at: &mut Option<u32>,
    wait: &mut Option<Duration>,
    events: &mut dyn FnMut(AnimateEvent<'_>),
) -> Result<()> {
    if let Some(limit) = *wait {
        if *at != Some(k) && !checkpoints::path(out, k).is_file() {
            let start = Instant::now();
            while !checkpoints::path(out, k).is_file() {
                if start.elapsed() >= limit {
                    *wait = None;
                    break;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
        }
    }
    if let Some(c) = checkpoints::nearest(out, k).filter(|&c| at.is_none_or(|a| c > a)) {
        checkpoints::restore(stage, out, c)?;
        *at = Some(c);
        events(AnimateEvent::FromCheckpoint { frame: c });
    }
    Ok(())
}

/// The timings file: new (with its header), or appended to when resuming one that has
/// rows already (rows are written only after their frame's PNG, so none is repeated).
fn open_timings(path: &Path, resume: bool) -> Result<BufWriter<File>> {
    let append = resume && path.is_file();
    let file = if append { OpenOptions::new().append(true).open(path) } else { File::create(path) }
        .with_context(|| format!("{}: cannot open", path.display()))?;
    let mut w = BufWriter::new(file);
    if !append {
        writeln!(w, "{TIMINGS_HEADER}").with_context(|| format!("{}: cannot write", path.display()))?;
    }
    Ok(w)
}

/// The frame's world-space triangles as OBJ, in the frame's stable order (vertex `i` of
/// the frame is OBJ vertex `i + 1`), written atomically ([`crate::output`]). Floats
/// are printed in Rust's shortest round-trip form, so reading them back gives the same
/// bits.
pub fn write_obj(frame: &Frame, path: &Path) -> Result<()> {
    crate::output::write_with(path, |file| {
        let mut w = BufWriter::new(file);
        writeln!(w, "# dynray animate: frame at t = {} s, {} triangles", frame.time, frame.mesh.triangle_count())?;
        for p in &frame.mesh.positions {
            writeln!(w, "v {} {} {}", p[0], p[1], p[2])?;
        }
        for t in &frame.mesh.indices {
            writeln!(w, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
        }
        w.flush()?;
        Ok(())
    })
}
