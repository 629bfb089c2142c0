//! The camera a file without one is seen through: [`Camera::default_view`].
//!
//! "The front" is `+z`, glTF's convention for the front of an asset and the side the
//! Stanford scans face. Two kinds of model want different views from there:
//! - an **enclosure** — a room, a Cornell box — is seen from its open side, head-on:
//!   from the front-right-above three-quarter view a box open towards `+z` shows the
//!   outside of its right wall. A model is taken as an enclosure open on a side when the
//!   straight line from outside that side to (just short of) the centre of its bounds
//!   crosses no triangle; sides are tried in the order `+z`, `−z`, `+x`, `−x`. A flat
//!   model lying through its centre (a quad facing `+z`) is seen head-on from `+z`;
//! - anything else (a solid like the bunny, whose centre is inside it) is seen from the
//!   front, a little from the right and above ([`Camera::framing`]), which shows its
//!   shape better than a head-on view.

use crate::{Camera, Projection, Scene};
use dynray_geom::{Aabb, PreparedRay, Ray, Triangle, Vec3};

/// Vertical field of view of the default cameras, degrees.
const FOV_Y_DEG: f32 = 45.0;

impl Camera {
    /// The default view of `scene` (module docs): head-on into an enclosure's open side,
    /// otherwise the front three-quarter view of [`Camera::framing`].
    pub fn default_view(scene: &Scene) -> Camera {
        let bounds = scene.bounds();
        if bounds.is_empty() {
            return Camera::framing(&bounds);
        }
        let c = bounds.center();
        let dist = framing_distance(&bounds);
        for side in [Vec3::Z, Vec3::NEG_Z, Vec3::X, Vec3::NEG_X] {
            let eye = c + side * dist;
            // Stops just short of the centre: a flat model through its centre (a quad, a
            // floor) is not in the way of its own front view.
            if !blocked(scene, &Ray::with_interval(eye, -side, 0.0, dist * (1.0 - 1e-3))) {
                return Camera {
                    position: c + side * head_on_distance(&bounds, side, scene.settings.width, scene.settings.height),
                    look_at: c,
                    up: Vec3::Y,
                    projection: Projection::Perspective { fov_y_deg: FOV_Y_DEG },
                    clip: crate::Clip::NONE,
                };
            }
        }
        Camera::framing(&bounds)
    }

    /// A perspective camera that frames `bounds` (seen from the front-right-above, y up)
    /// with a 45° vertical field of view.
    pub fn framing(bounds: &Aabb) -> Self {
        let c = bounds.center();
        let dir = Vec3::new(0.35, 0.3, 1.0).normalize();
        let dist = framing_distance(bounds);
        Self {
            position: c + dir * dist,
            look_at: c,
            up: Vec3::Y,
            projection: Projection::Perspective { fov_y_deg: FOV_Y_DEG },
            clip: crate::Clip::NONE,
        }
    }
}

/// Distance from the centre at which the bounding sphere of `bounds` fits the vertical
/// field of view, with 5 % margin.
fn framing_distance(bounds: &Aabb) -> f32 {
    let radius = if bounds.is_empty() { 1.0 } else { (bounds.extent().length() * 0.5).max(1e-3) };
    radius / (FOV_Y_DEG.to_radians() * 0.5).sin() * 1.05
}

/// Distance from the centre at which the face of `bounds` seen head-on along `-side`
/// fills the image (10 % margin): the camera sits in front of that face by what the
/// field of view needs for the face's half height, or half width over the aspect ratio.
fn head_on_distance(bounds: &Aabb, side: Vec3, width: u32, height: u32) -> f32 {
    let half = bounds.extent() * 0.5;
    let aspect = width.max(1) as f32 / height.max(1) as f32;
    let (half_w, half_depth) = if side.z != 0.0 { (half.x, half.z) } else { (half.z, half.x) };
    let fit = half.y.max(half_w / aspect).max(1e-3);
    half_depth + fit * 1.1 / (FOV_Y_DEG.to_radians() * 0.5).tan()
}

/// Whether any triangle of the scene (in world space) lies on `ray`: a brute-force
/// any-hit, run a few times per load.
fn blocked(scene: &Scene, ray: &Ray) -> bool {
    let prepared = PreparedRay::new(ray);
    scene.actors.iter().any(|a| {
        let world = |i: u32| {
            let p = a.mesh.positions[i as usize];
            Vec3::from_array(if a.transform.is_identity() { p } else { a.transform.point(p) })
        };
        a.mesh.indices.iter().any(|&[i0, i1, i2]| {
            Triangle::new(world(i0), world(i1), world(i2))
                .intersect(&prepared, ray.tmax)
                .is_some_and(|(t, _, _)| t >= ray.tmin)
        })
    })
}
