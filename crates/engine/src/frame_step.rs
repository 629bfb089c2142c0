//! The frame step every front end drives: pose the scene at `t`, advance its physics to
//! `t`, apply the job's frame settings, then bring the tracer's structure up to date
//! under the update policy.
//!
//! Physics runs in fixed steps from time 0 ([`dynray_sim::World::advance_to`]), so a frame
//! reached by any path — the next frame of a run, a shard's first, a resumed run's, a
//! seek backwards (which re-simulates from 0), a run continued from a checkpoint
//! ([`Stage::restore_physics`]) — has exactly the state a full run shows.

use crate::tracer::Tracer;
use anyhow::{Context, Result};
use dynray_accel::UpdateReport;
use dynray_scene::{Frame, Scene};
use dynray_sim::World;
use std::time::{Duration, Instant};

/// What a job changes in every frame's settings (`--width`, `--height`, `--max-depth`,
/// `--min-weight`); `None` keeps the scene's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameSettings {
    /// Image width in pixels.
    pub width: Option<u32>,
    /// Image height in pixels.
    pub height: Option<u32>,
    /// Deepest ray level, as the integrator counts it (already converted by the job).
    pub max_recursion_level: Option<u32>,
    /// Smallest path weight still traced.
    pub min_weight: Option<f32>,
}

impl FrameSettings {
    fn apply(&self, frame: &mut Frame) {
        let s = &mut frame.settings;
        s.width = self.width.unwrap_or(s.width);
        s.height = self.height.unwrap_or(s.height);
        s.max_recursion_level = self.max_recursion_level.unwrap_or(s.max_recursion_level);
        s.min_weight = self.min_weight.unwrap_or(s.min_weight);
    }
}

/// The time one [`Stage::pose`] took.
#[derive(Clone, Copy, Debug, Default)]
pub struct PoseTiming {
    /// Posing and simulating.
    pub total: Duration,
    /// The simulation's part (zero without physics).
    pub physics: Duration,
}

/// A scene in motion: the posed frame and the physics that deforms it.
pub struct Stage {
    scene: Scene,
    world: Option<World>,
    frame: Frame,
    settings: FrameSettings,
    label: String,
}

impl Stage {
    /// The stage of `scene` (shaded, its timeline shaped: `--fps` sets the physics
    /// step). Builds the simulation when an actor has an `elastic` block. Errors name the
    /// file (`label`).
    pub fn new(scene: Scene, label: &str, settings: FrameSettings) -> Result<Self> {
        let world = World::from_scene(&scene).with_context(|| format!("{label}: physics"))?;
        Ok(Stage { scene, world, frame: Frame::default(), settings, label: label.to_string() })
    }

    /// Poses the scene at `t` and advances its physics to `t`.
    pub fn pose(&mut self, t: f32) -> Result<PoseTiming> {
        let t0 = Instant::now();
        self.scene.frame_into(t, &mut self.frame);
        let t1 = Instant::now();
        if let Some(w) = self.world.as_mut() {
            let at = || format!("{}: physics at t = {t} s", self.label);
            w.advance_to(t as f64).with_context(at)?;
            w.write_into(&mut self.frame).with_context(at)?;
        }
        let physics = t1.elapsed();
        self.settings.apply(&mut self.frame);
        Ok(PoseTiming { total: t0.elapsed(), physics })
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The frame last posed.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The frame last posed, for a job that adjusts it (a camera framing fields).
    pub fn frame_mut(&mut self) -> &mut Frame {
        &mut self.frame
    }

    /// The simulation, where the scene has one.
    pub fn world(&self) -> Option<&World> {
        self.world.as_ref()
    }

    /// Continues the simulation from a checkpoint ([`World::checkpoint`]); an error
    /// (another scene's, damaged) changes nothing. A scene without physics has nothing
    /// to restore: its checkpoints are refused.
    pub fn restore_physics(&mut self, bytes: &[u8]) -> Result<()> {
        let w = self.world.as_mut().ok_or_else(|| anyhow::anyhow!("{}: the scene has no physics", self.label))?;
        Ok(w.restore(bytes)?)
    }

    /// The frame's settings every pose applies.
    pub fn settings_mut(&mut self) -> &mut FrameSettings {
        &mut self.settings
    }

    /// The scene's name in messages.
    pub fn label(&self) -> &str {
        &self.label
    }
}

/// The figures of one [`FrameStep::advance_to`].
#[derive(Clone, Copy, Debug)]
pub struct StepReport {
    /// Posing and simulating.
    pub pose: Duration,
    /// The structure's update.
    pub update: UpdateReport,
}

/// A stage and the tracer that follows it: what animate, the bench's frame loops and a
/// live viewer drive, one `advance_to` a frame.
pub struct FrameStep {
    /// The posed scene.
    pub stage: Stage,
    /// The structures over it.
    pub tracer: Tracer,
}

impl FrameStep {
    /// `stage` traced by `tracer` (nothing built until the first step).
    pub fn new(stage: Stage, tracer: Tracer) -> Self {
        FrameStep { stage, tracer }
    }

    /// Poses, simulates and updates the structure to time `t`.
    pub fn advance_to(&mut self, t: f32) -> Result<StepReport> {
        let pose = self.stage.pose(t)?.total;
        let update = self.tracer.update(&self.stage.scene, &self.stage.frame)?;
        Ok(StepReport { pose, update })
    }
}
