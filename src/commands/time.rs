//! Which instant of an animated scene a command looks at: `--clip` and `--fps` shape the
//! timeline, `--time` or `--frame` pick the instant (docs/animate.md, "Time").

use crate::cli::TimeArgs;
use anyhow::{bail, Result};
use dynray_scene::{Scene, Timeline};

/// Plays clip `clip` (by name) and sets the timeline's frame rate to `fps`, keeping the
/// duration it covers. Errors name the file (`label`).
pub fn shape_timeline(scene: &mut Scene, label: &str, clip: Option<&str>, fps: Option<f32>) -> Result<()> {
    if let Some(name) = clip {
        if let Err(e) = scene.select_clip(name) {
            bail!("{label}: {e}");
        }
    }
    if let Some(rate) = fps {
        if !(rate > 0.0 && rate.is_finite()) {
            bail!("--fps must be a positive number, got {rate}");
        }
        let t = scene.animation.timeline;
        let end = t.time_of(t.frames - 1);
        scene.animation.timeline = Timeline::covering(t.start, end, rate);
    }
    Ok(())
}

/// The time `when` asks for: `--time T`, the time of `--frame K` (which must be one of
/// the timeline's frames), or frame 0's.
pub fn chosen_time(scene: &Scene, label: &str, when: &TimeArgs) -> Result<f32> {
    let timeline = scene.animation.timeline;
    if let Some(t) = when.time {
        if !t.is_finite() {
            bail!("--time must be a finite number of seconds, got {t}");
        }
        return Ok(t);
    }
    let k = when.frame.unwrap_or(0);
    if k >= timeline.frames {
        bail!(
            "{label}: frame {k} is past the last frame, {} (the animation has {} frames)",
            timeline.frames - 1,
            timeline.frames
        );
    }
    Ok(timeline.time_of(k))
}

/// [`shape_timeline`] then [`chosen_time`], for `render` and `trace-rays`.
pub fn apply(scene: &mut Scene, label: &str, when: &TimeArgs) -> Result<f32> {
    shape_timeline(scene, label, when.clip.as_deref(), when.fps)?;
    chosen_time(scene, label, when)
}
