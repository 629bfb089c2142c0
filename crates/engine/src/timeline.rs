//! Which instant of an animated scene a front end looks at (docs/animate.md, "Time"):
//! the clip and frame rate shape the timeline, a time or a frame number picks the
//! instant. This is the one definition of frame `k`'s time and of "frame 0" (the
//! timeline's start, which is not 0 s wherever a file's animation starts elsewhere:
//! BART's museum starts at −1 s).

use anyhow::{bail, Result};
use dynray_scene::{Scene, Timeline};

/// The instant a job looks at, and how the timeline is shaped first. Plain options:
/// each front end fills it from its own arguments (`--time`, `--frame`, `--clip`,
/// `--fps`; Python's keywords).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TimeChoice {
    /// Seconds on the scene's own axis (exclusive with `frame`).
    pub time: Option<f32>,
    /// A frame number of the (shaped) timeline; neither given: frame 0.
    pub frame: Option<u32>,
    /// The animation clip to play, by name (files with several).
    pub clip: Option<String>,
    /// The timeline's frame rate, replacing the file's.
    pub fps: Option<f32>,
}

impl TimeChoice {
    /// The instant `t` seconds.
    pub fn at(t: f32) -> Self {
        TimeChoice { time: Some(t), ..Default::default() }
    }

    /// Checks what needs no scene: a finite time, a positive frame rate, not both a time
    /// and a frame.
    pub fn check(&self) -> Result<()> {
        if let Some(t) = self.time {
            if !t.is_finite() {
                bail!("--time must be a finite number of seconds, got {t}");
            }
            if self.frame.is_some() {
                bail!("--time and --frame both choose the instant: give one");
            }
        }
        if let Some(rate) = self.fps {
            if !(rate > 0.0 && rate.is_finite()) {
                bail!("--fps must be a positive number, got {rate}");
            }
        }
        Ok(())
    }

    /// Shapes `scene`'s timeline ([`shape_timeline`]) and returns the chosen time
    /// ([`chosen_time`]). Errors name the file (`label`).
    pub fn apply(&self, scene: &mut Scene, label: &str) -> Result<f32> {
        self.check()?;
        shape_timeline(scene, label, self.clip.as_deref(), self.fps)?;
        chosen_time(scene, label, self)
    }
}

/// Plays clip `clip` (by name) and sets the timeline's frame rate to `fps`, keeping the
/// duration it covers. Errors name the file (`label`).
pub fn shape_timeline(scene: &mut Scene, label: &str, clip: Option<&str>, fps: Option<f32>) -> Result<()> {
    if let Some(name) = clip {
        if let Err(e) = scene.select_clip(name) {
            bail!("{label}: {e}");
        }
    }
    if scene.animation.timeline.frames == 0 {
        bail!("{label}: the animation has no frames");
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

/// The time `when` asks for: its time, the time of its frame (which must be one of the
/// timeline's frames), or frame 0's ([`frame_zero`]).
pub fn chosen_time(scene: &Scene, label: &str, when: &TimeChoice) -> Result<f32> {
    let timeline = scene.animation.timeline;
    if let Some(t) = when.time {
        if !t.is_finite() {
            bail!("--time must be a finite number of seconds, got {t}");
        }
        return Ok(t);
    }
    let k = when.frame.unwrap_or(0);
    if timeline.frames == 0 {
        bail!("{label}: the animation has no frames");
    }
    if k >= timeline.frames {
        bail!(
            "{label}: frame {k} is past the last frame, {} (the animation has {} frames)",
            timeline.frames - 1,
            timeline.frames
        );
    }
    Ok(timeline.time_of(k))
}

/// The time of frame 0: the timeline's start. Every front end's "no time given" is this.
pub fn frame_zero(scene: &Scene) -> f32 {
    scene.animation.timeline.time_of(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene_starting_at(start: f32) -> Scene {
        let mut s = Scene::default();
        s.animation.timeline = Timeline::covering(start, start + 1.0, 10.0);
        s
    }

    #[test]
    fn frame_zero_is_the_timelines_start_not_time_zero() {
        let s = scene_starting_at(-1.0);
        assert_eq!(frame_zero(&s), -1.0);
        assert_eq!(chosen_time(&s, "x", &TimeChoice::default()).unwrap(), -1.0);
        assert_eq!(chosen_time(&s, "x", &TimeChoice { frame: Some(5), ..Default::default() }).unwrap(), -0.5);
    }

    #[test]
    fn a_timeline_without_frames_is_an_error_not_frame_4294967295() {
        let mut s = Scene::default();
        s.animation.timeline.frames = 0;
        let e = TimeChoice::default().apply(&mut s, "a.aff").unwrap_err().to_string();
        assert_eq!(e, "a.aff: the animation has no frames");
        let e = chosen_time(&s, "a.aff", &TimeChoice::default()).unwrap_err().to_string();
        assert_eq!(e, "a.aff: the animation has no frames");
    }

    #[test]
    fn bad_choices_are_refused_with_the_flag_named() {
        let e = TimeChoice::at(f32::NAN).check().unwrap_err().to_string();
        assert!(e.contains("--time"), "{e}");
        let e = TimeChoice { fps: Some(0.0), ..Default::default() }.check().unwrap_err().to_string();
        assert!(e.contains("--fps"), "{e}");
        let s = scene_starting_at(0.0);
        let e = chosen_time(&s, "a.scn", &TimeChoice { frame: Some(99), ..Default::default() }).unwrap_err();
        assert!(e.to_string().starts_with("a.scn: frame 99 is past the last frame, 10"), "{e}");
    }
}
