//! Point-based physics in the commands' frame path (docs/physics.md): the scene's
//! simulated bodies are built once, then each frame, after `Scene::frame_into(t)`, the
//! world steps to `t` and writes its deformed vertices into the frame. Time runs in
//! fixed steps from 0, so any frame (a shard's, a resumed run's, `render --frame K`)
//! is re-simulated from time 0 to exactly the state a full run shows.

use anyhow::{Context, Result};
use dynray_scene::{Frame, Scene};
use dynray_sim::World;

/// The scene's simulation, `None` when no actor has an `elastic` block. Build it after
/// the timeline is shaped (`--fps` sets the step) and the shading applied.
pub fn world(scene: &Scene, label: &str) -> Result<Option<World>> {
    World::from_scene(scene).with_context(|| format!("{label}: physics"))
}

/// Steps `world` (if any) to time `t` and writes the bodies into `frame`.
pub fn simulate(world: Option<&mut World>, t: f32, frame: &mut Frame, label: &str) -> Result<()> {
    let Some(w) = world else { return Ok(()) };
    w.advance_to(t as f64).with_context(|| format!("{label}: physics at t = {t} s"))?;
    w.write_into(frame).with_context(|| format!("{label}: physics at t = {t} s"))
}
