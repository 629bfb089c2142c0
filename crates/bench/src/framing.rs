//! How the standard run's camera frames a model (`--framing`): the scene's own camera, or,
//! for a file without one (a bare mesh), the default view moved so that the model fills
//! the image. A scene's own camera (the kitchen seen from inside) is always kept.
//!
//! The default view of a mesh file frames its bounding sphere from afar, so most primary
//! rays of a slim model miss (85 % on the bunny): they time the root box test, not the
//! tree. `tight` keeps the view direction, up vector and field of view, aims at the
//! middle of the model's silhouette and moves the eye along the view axis until the
//! outermost vertex touches the image edge (with a 2 % margin).

use anyhow::{bail, Result};
use dynray_geom::Vec3;
use dynray_render::CameraRays;
use dynray_scene::{Frame, Projection};

/// Where the standard run's camera comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Framing {
    /// The scene's camera (or, for a bare mesh, the default view framing its bounds).
    #[default]
    Scene,
    /// For a file without a camera, the default view's direction, moved so that the model
    /// fills the image ([`frame_tightly`]); a scene's own camera is kept.
    Tight,
}

impl Framing {
    /// Every framing, as `--framing` lists them.
    pub const ALL: [Framing; 2] = [Framing::Scene, Framing::Tight];

    /// The `--framing` spelling, also the report's.
    pub fn name(self) -> &'static str {
        match self {
            Framing::Scene => "scene",
            Framing::Tight => "tight",
        }
    }
}

impl std::str::FromStr for Framing {
    type Err = anyhow::Error;

    fn from_str(s: &str) -> Result<Self> {
        match Framing::ALL.iter().find(|f| f.name() == s) {
            Some(f) => Ok(*f),
            None => bail!("--framing: unknown framing `{s}` (expected scene or tight)"),
        }
    }
}

/// Room left between the model and the image edge, as a fraction of the eye distance.
const MARGIN: f32 = 0.02;

/// Moves `frame`'s perspective camera so that its mesh fills a `width` × `height` image:
/// same view direction and up vector, the eye on the view axis through the middle of the
/// model's extent across the view, as close as keeps every vertex inside the window.
/// A parallel camera, or an empty mesh, is left as it is.
pub fn frame_tightly(frame: &mut Frame, width: u32, height: u32) {
    if matches!(frame.camera.projection, Projection::Parallel { .. }) || frame.mesh.positions.is_empty() {
        return;
    }
    let basis = CameraRays::new(&frame.camera, width, height).basis();
    let (f, r, u) = (basis.forward, basis.right, basis.up);
    // `right` and `up` are scaled by the window's half extent at unit distance.
    let (tan_x, tan_y) = (r.length(), u.length());
    let (rn, un) = (r / tan_x, u / tan_y);
    let points = || frame.mesh.positions.iter().map(|p| Vec3::from_array(*p));
    // The middle of the model across the view, and its depth midpoint along it.
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in points() {
        let q = Vec3::new(p.dot(rn), p.dot(un), p.dot(f));
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let mid = (lo + hi) * 0.5;
    let centre = rn * mid.x + un * mid.y + f * mid.z;
    // Each vertex q (relative to the centre) is inside the window from an eye at distance
    // D behind it when |q·right| ≤ tan_x (q·f + D) and |q·up| ≤ tan_y (q·f + D).
    let mut distance = 0.0f32;
    for p in points() {
        let q = p - centre;
        let depth = q.dot(f);
        distance = distance.max(q.dot(rn).abs() / tan_x - depth).max(q.dot(un).abs() / tan_y - depth);
    }
    let distance = distance * (1.0 + MARGIN);
    if !(distance.is_finite() && distance > 0.0) {
        return;
    }
    frame.camera.position = centre - f * distance;
    frame.camera.look_at = centre;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hits(frame: &Frame, w: u32, h: u32) -> f64 {
        let accel = dynray_accel::AccelKind::Bvh.build(&frame.mesh).unwrap();
        let rays = crate::rays::primary(frame, w, h);
        rays.iter().filter(|r| accel.intersect(r).is_hit()).count() as f64 / rays.len() as f64
    }

    #[test]
    fn tight_framing_fills_the_image_and_keeps_every_vertex_inside() {
        let mut frame = crate::scenes::demo().frame;
        // A flat 8 × 3 box seen from afar: the default view leaves most pixels empty.
        frame.mesh = dynray_scene::shapes::cuboid(Vec3::ZERO, Vec3::new(8.0, 3.0, 0.5), Vec3::ZERO);
        frame.camera.position = Vec3::new(0.0, 0.0, 30.0);
        frame.camera.look_at = Vec3::new(1.0, 0.0, 0.0);
        let (w, h) = (64, 48);
        let before = hits(&frame, w, h);
        frame_tightly(&mut frame, w, h);
        let after = hits(&frame, w, h);
        assert!(after > 0.3 && after > 4.0 * before, "hit fraction {before} -> {after}");
        // Every vertex projects inside the window.
        let b = CameraRays::new(&frame.camera, w, h).basis();
        for p in &frame.mesh.positions {
            let q = Vec3::from_array(*p) - b.origin;
            let z = q.dot(b.forward);
            assert!(z > 0.0);
            assert!(q.dot(b.right).abs() <= z * b.right.length_squared() * 1.0001, "{p:?}");
            assert!(q.dot(b.up).abs() <= z * b.up.length_squared() * 1.0001, "{p:?}");
        }
        // Same view direction.
        let f = (frame.camera.look_at - frame.camera.position).normalize();
        assert!(f.dot((Vec3::new(1.0, 0.0, 0.0) - Vec3::new(0.0, 0.0, 30.0)).normalize()) > 0.9999);
    }

    #[test]
    fn framings_round_trip() {
        for f in Framing::ALL {
            assert_eq!(f.name().parse::<Framing>().unwrap(), f);
        }
        assert!("loose".parse::<Framing>().is_err());
    }
}
