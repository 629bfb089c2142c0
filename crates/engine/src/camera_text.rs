//! A camera as text, both ways: the body of the scene language's `camera { … }`
//! statement (docs/scene-language.md §7), which is also what `--camera` takes, so a view
//! found in the viewer can be pasted into a command line or a `.scn` file.
//!
//! Numbers print in Rust's shortest round-trip form, so text → camera → text and
//! camera → text → camera give back the same bits.

use anyhow::{bail, Result};
use dynray_scene::{Camera, Clip, Projection};
use std::path::Path;

/// The body of a `camera { … }` statement for `camera`:
/// `perspective position <0, 2, 7> to <0, 0.7, 0> up <0, 1, 0> angle 40`.
/// Clip planes have no scene-language form and are not written.
pub fn camera_text(camera: &Camera) -> String {
    let v = |p: dynray_geom::Vec3| format!("<{}, {}, {}>", p.x, p.y, p.z);
    let (kind, angle) = match camera.projection {
        Projection::Perspective { fov_y_deg } => ("perspective", fov_y_deg),
        Projection::Parallel { height } => ("parallel", height),
    };
    format!("{kind} position {} to {} up {} angle {angle}", v(camera.position), v(camera.look_at), v(camera.up))
}

/// Parses `--camera TEXT` (the body of a `camera { … }` statement). Errors quote the
/// scene language's message.
pub fn parse_camera(text: &str) -> Result<Camera> {
    if text.contains(['{', '}']) {
        bail!("--camera takes the inside of a `camera {{ … }}` statement, without braces: `{text}`");
    }
    let scene = dynray_scene::scn::parse_scn_str("--camera", &format!("camera {{ {text} }}"), Path::new("."))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    if scene.animation.camera_node.is_some() {
        bail!("--camera: an animated camera has no single view; give a still one");
    }
    match scene.camera {
        Some(c) => Ok(Camera { clip: Clip::NONE, ..c }),
        None => bail!("--camera: `{text}` is not a camera"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_geom::Vec3;

    #[test]
    fn text_and_camera_round_trip_to_the_bit() {
        let cams = [
            Camera {
                position: Vec3::new(0.1, -2.000_000_2, 7.0),
                look_at: Vec3::new(1e-7, 0.7, -3.25),
                up: Vec3::Y,
                projection: Projection::Perspective { fov_y_deg: 39.999_996 },
                clip: Clip::NONE,
            },
            Camera {
                position: Vec3::new(0.0, 0.0, 10.0),
                look_at: Vec3::ZERO,
                up: Vec3::new(0.0, 1.0, 0.2),
                projection: Projection::Parallel { height: 4.5 },
                clip: Clip::NONE,
            },
        ];
        for c in cams {
            let text = camera_text(&c);
            assert_eq!(parse_camera(&text).unwrap(), c, "{text}");
        }
        let text = "perspective position <0, 2, 7> to <0, 0.7, 0> up <0, 1, 0> angle 40";
        assert_eq!(camera_text(&parse_camera(text).unwrap()), text);
    }

    #[test]
    fn bad_text_is_an_error_with_the_languages_words() {
        for bad in ["perspective position <0, 2> to <0, 0, 0> up <0, 1, 0>", "{ perspective }", ""] {
            assert!(parse_camera(bad).is_err(), "{bad}");
        }
    }
}
