//! Moving the camera by hand: orbit about the point looked at, pan, zoom (dolly) and fly,
//! each a pure function from a camera to the next, so scripts and the mouse move it the
//! same way.

use dynray_geom::Vec3;
use dynray_scene::{Camera, Projection};

/// Radians of orbit per window pixel dragged.
const ORBIT_PER_PIXEL: f32 = 0.008;
/// Distance factor per wheel notch towards the scene.
const ZOOM_PER_NOTCH: f32 = 0.85;
/// Closest the view direction comes to the up vector when orbiting (radians), so the
/// camera never flips over the pole.
const POLE_MARGIN: f32 = 0.02;

/// The camera's unit frame: view direction, right, up (right-handed, up ⟂ view).
fn frame(camera: &Camera) -> (Vec3, Vec3, Vec3) {
    let forward = (camera.look_at - camera.position).normalize_or(Vec3::NEG_Z);
    let mut right = forward.cross(camera.up).normalize_or_zero();
    if right == Vec3::ZERO {
        right = forward.any_orthonormal_vector();
    }
    (forward, right, right.cross(forward))
}

/// Orbits the eye about the point looked at: dragging right turns the scene right about
/// the camera's up vector, dragging down tilts the view from above.
pub fn orbit(camera: &Camera, dx: f32, dy: f32) -> Camera {
    let up = camera.up.normalize_or(Vec3::Y);
    let offset = camera.position - camera.look_at;
    let yaw = glam::Quat::from_axis_angle(up, -dx * ORBIT_PER_PIXEL);
    let offset = yaw * offset;
    let (_, right, _) = frame(&Camera { position: camera.look_at + offset, ..*camera });
    // Pitch, kept off the poles.
    let angle_to_up = offset.normalize_or(Vec3::Z).dot(up).clamp(-1.0, 1.0).acos();
    let pitch =
        (dy * ORBIT_PER_PIXEL).clamp(-(std::f32::consts::PI - POLE_MARGIN - angle_to_up), angle_to_up - POLE_MARGIN);
    let offset = glam::Quat::from_axis_angle(right, -pitch) * offset;
    Camera { position: camera.look_at + offset, ..*camera }
}

/// Moves eye and target together in the image plane so the scene follows the pointer:
/// `(dx, dy)` window pixels of a window `height` pixels high.
pub fn pan(camera: &Camera, dx: f32, dy: f32, height: f32) -> Camera {
    let (_, right, up) = frame(camera);
    let distance = (camera.look_at - camera.position).length();
    let view_height = match camera.projection {
        Projection::Perspective { fov_y_deg } => 2.0 * distance * (fov_y_deg.to_radians() * 0.5).tan(),
        Projection::Parallel { height } => height,
    };
    let per_pixel = view_height / height.max(1.0);
    let shift = (-dx * right + dy * up) * per_pixel;
    Camera { position: camera.position + shift, look_at: camera.look_at + shift, ..*camera }
}

/// Dollies towards (positive notches) or away from the point looked at; a parallel
/// camera narrows or widens its view instead.
pub fn zoom(camera: &Camera, notches: f32) -> Camera {
    let factor = ZOOM_PER_NOTCH.powf(notches);
    match camera.projection {
        Projection::Parallel { height } => {
            Camera { projection: Projection::Parallel { height: (height * factor).max(1e-6) }, ..*camera }
        }
        Projection::Perspective { .. } => {
            let offset = camera.position - camera.look_at;
            let scaled = offset * factor;
            // Never onto the target itself.
            let offset = if scaled.length() > 1e-6 { scaled } else { offset };
            Camera { position: camera.look_at + offset, ..*camera }
        }
    }
}

/// Flies eye and target `step` world units along the view (`forward`), right and up.
pub fn fly(camera: &Camera, (forward, right, up): (i8, i8, i8), step: f32) -> Camera {
    let (f, r, u) = frame(camera);
    let shift = (f * forward as f32 + r * right as f32 + u * up as f32) * step;
    Camera { position: camera.position + shift, look_at: camera.look_at + shift, ..*camera }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_scene::Clip;

    fn cam() -> Camera {
        Camera {
            position: Vec3::new(0.0, 1.0, 5.0),
            look_at: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            projection: Projection::Perspective { fov_y_deg: 45.0 },
            clip: Clip::NONE,
        }
    }

    #[test]
    fn orbit_keeps_the_distance_and_the_target() {
        let c = orbit(&cam(), 120.0, -40.0);
        assert_eq!(c.look_at, cam().look_at);
        assert!(((c.position - c.look_at).length() - 5.0).abs() < 1e-4);
        assert!(c.position.x < 0.0, "dragging right swings the eye to the left of the scene");
        assert!(c.position.y < 1.0, "dragging up looks from below");
        // A huge drag stops short of the pole.
        let top = orbit(&cam(), 0.0, 1e6);
        let d = (top.position - top.look_at).normalize();
        assert!(d.dot(Vec3::Y) < 1.0 - 1e-4 && d.y > 0.99);
    }

    #[test]
    fn pan_moves_eye_and_target_together() {
        let c = pan(&cam(), 100.0, 0.0, 400.0);
        assert_eq!(c.position - cam().position, c.look_at - cam().look_at);
        assert!(c.position.x < 0.0, "the scene follows the pointer to the right");
    }

    #[test]
    fn zoom_dollies_and_fly_translates() {
        let c = zoom(&cam(), 2.0);
        assert!(((c.position - c.look_at).length() - 5.0 * 0.85 * 0.85).abs() < 1e-4);
        assert!((zoom(&zoom(&cam(), 3.0), -3.0).position.z - 5.0).abs() < 1e-5);
        let f = fly(&cam(), (1, 0, 1), 0.5);
        assert_eq!(f.position, Vec3::new(0.0, 1.5, 4.5));
        assert_eq!(f.look_at, Vec3::new(0.0, 1.5, -0.5));
    }
}
