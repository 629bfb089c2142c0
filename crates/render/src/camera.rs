//! Primary rays of the scene camera: perspective (vertical field of view) and parallel
//! (view height), through pixel centres, image y pointing down.

use crate::RayCone;
use dynray_geom::{Ray, Vec3};
use dynray_scene::{Camera, Clip, Projection};

/// A camera resolved for one image size: an orthonormal frame and the half extents of
/// the image window. Built once per frame, then asked for rays per pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraRays {
    origin: Vec3,
    forward: Vec3,
    /// Right vector scaled by the window's half width.
    right: Vec3,
    /// Up vector scaled by the window's half height.
    up: Vec3,
    parallel: bool,
    width: f32,
    height: f32,
    clip: Clip,
}

impl CameraRays {
    /// Resolves `camera` for a `width` × `height` image (aspect = width / height).
    ///
    /// Never produces NaN: a look-at point equal to the position looks down −z, an up
    /// vector parallel to the view direction is replaced by another axis, a field of view
    /// outside (0°, 180°) is clamped, a non-positive parallel height becomes 1, and a zero
    /// image dimension is treated as 1.
    pub fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let (w, h) = (width.max(1) as f32, height.max(1) as f32);
        let aspect = w / h;
        let origin = if camera.position.is_finite() { camera.position } else { Vec3::ZERO };
        let mut forward = (camera.look_at - origin).normalize_or_zero();
        if forward == Vec3::ZERO || !forward.is_finite() {
            forward = Vec3::NEG_Z;
        }
        let right = orthonormal_right(forward, camera.up);
        let up = right.cross(forward);
        let (half_h, parallel) = match camera.projection {
            Projection::Perspective { fov_y_deg } => {
                let fov = if fov_y_deg.is_finite() { fov_y_deg.clamp(1e-3, 179.0) } else { 60.0 };
                ((fov.to_radians() * 0.5).tan(), false)
            }
            Projection::Parallel { height } => {
                (if height.is_finite() && height > 0.0 { height * 0.5 } else { 1.0 }, true)
            }
        };
        // A clip that would leave nothing (or is not a number) clips nothing.
        let clip = camera.clip;
        let clip = if clip.near >= 0.0 && clip.far > clip.near { clip } else { Clip::NONE };
        Self { origin, forward, right: right * (half_h * aspect), up: up * half_h, parallel, width: w, height: h, clip }
    }

    /// The ray through continuous image position `(px, py)` (pixels, y down; the centre
    /// of pixel `(x, y)` is `(x + 0.5, y + 0.5)`). Perspective rays start at the eye,
    /// parallel rays on the plane through the eye; directions are unit length. The
    /// camera's [`Clip`] bounds the ray's interval: `[near, far] / cos θ` for a
    /// perspective ray at angle θ to the view axis (the planes are perpendicular to it),
    /// `[near, far]` for a parallel one; without clip planes it is `[0, ∞)`.
    pub fn ray_at(&self, px: f32, py: f32) -> Ray {
        let sx = 2.0 * px / self.width - 1.0;
        let sy = 1.0 - 2.0 * py / self.height;
        let offset = self.right * sx + self.up * sy;
        let ray = if self.parallel {
            Ray::new(self.origin + offset, self.forward)
        } else {
            Ray::new(self.origin, (self.forward + offset).normalize())
        };
        if self.clip == Clip::NONE {
            return ray;
        }
        let cos = if self.parallel { 1.0 } else { ray.dir.dot(self.forward) };
        Ray::with_interval(ray.origin, ray.dir, self.clip.near / cos, self.clip.far / cos)
    }

    /// The near and far planes camera rays are clipped to ([`Clip::NONE`] when none).
    pub fn clip(&self) -> Clip {
        self.clip
    }

    /// The ray through the centre of pixel `(x, y)`.
    pub fn primary(&self, x: u32, y: u32) -> Ray {
        self.ray_at(x as f32 + 0.5, y as f32 + 0.5)
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// The footprint of one pixel's camera ray ([`RayCone`]): a perspective camera's
    /// cone starts at a point and widens by a pixel's height at unit distance along the
    /// view axis (`2 tan(fov/2) / height`, the pixel spread angle of Akenine-Möller et
    /// al.); a parallel camera's keeps a pixel's height in world units. Pixels are
    /// square, so the width matches.
    pub fn pixel_cone(&self) -> RayCone {
        let pixel = 2.0 * self.up.length() / self.height;
        if self.parallel {
            RayCone { width: pixel, spread: 0.0 }
        } else {
            RayCone { width: 0.0, spread: pixel }
        }
    }

    /// The resolved vectors [`CameraRays::ray_at`] combines: what a port of it (the GPU
    /// backend's ray generation) needs to give the same rays.
    pub fn basis(&self) -> CameraBasis {
        CameraBasis {
            origin: self.origin,
            forward: self.forward,
            right: self.right,
            up: self.up,
            parallel: self.parallel,
            width: self.width,
            height: self.height,
        }
    }
}

/// A [`CameraRays`]' vectors: the ray through image position `(px, py)` has
/// `s = (2 px / width − 1, 1 − 2 py / height)`, `offset = right · s.x + up · s.y` and is
/// `(origin + offset, forward)` for a parallel camera, `(origin, normalize(forward +
/// offset))` for a perspective one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraBasis {
    /// Eye position.
    pub origin: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Right vector scaled by the window's half width.
    pub right: Vec3,
    /// Up vector scaled by the window's half height.
    pub up: Vec3,
    /// Parallel (true) or perspective projection.
    pub parallel: bool,
    /// Image width in pixels (at least 1).
    pub width: f32,
    /// Image height in pixels (at least 1).
    pub height: f32,
}

/// Unit right vector of a camera looking along unit `forward` with approximate `up`;
/// when `up` is zero, non-finite or (nearly) parallel to `forward`, the first of y, z, x
/// that is far from `forward` stands in for it.
fn orthonormal_right(forward: Vec3, up: Vec3) -> Vec3 {
    let r = forward.cross(up.normalize_or_zero());
    if r.is_finite() && r.length_squared() > 1e-8 {
        return r.normalize();
    }
    let alt = [Vec3::Y, Vec3::Z, Vec3::X].into_iter().find(|a| forward.dot(*a).abs() < 0.9).unwrap_or(Vec3::Y);
    forward.cross(alt).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(projection: Projection) -> Camera {
        Camera { position: Vec3::new(0.0, 0.0, 5.0), look_at: Vec3::ZERO, up: Vec3::Y, projection, clip: Clip::NONE }
    }

    #[test]
    fn clip_planes_bound_the_ray_interval_along_the_view_axis() {
        let clip = Clip { near: 2.0, far: 8.0 };
        let c = CameraRays::new(&Camera { clip, ..cam(Projection::Perspective { fov_y_deg: 90.0 }) }, 4, 4);
        // The centre ray runs along the axis: its interval is the planes' distances.
        let r = c.ray_at(2.0, 2.0);
        assert_eq!((r.tmin, r.tmax), (2.0, 8.0));
        // A corner ray reaches the planes later, at the same depth along the axis.
        let r = c.ray_at(0.0, 0.0);
        let depth = |t: f32| (r.dir * t).dot(c.forward());
        assert!((depth(r.tmin) - 2.0).abs() < 1e-5 && (depth(r.tmax) - 8.0).abs() < 1e-5, "{r:?}");
        assert!(r.tmin > 2.0);
        let p = CameraRays::new(&Camera { clip, ..cam(Projection::Parallel { height: 2.0 }) }, 4, 4).ray_at(0.0, 0.0);
        assert_eq!((p.tmin, p.tmax), (2.0, 8.0));
        // No clip, or one that would leave nothing: the whole ray.
        for clip in [Clip::NONE, Clip { near: 3.0, far: 1.0 }, Clip { near: f32::NAN, far: 1.0 }] {
            let r = CameraRays::new(&Camera { clip, ..cam(Projection::Perspective { fov_y_deg: 60.0 }) }, 4, 4)
                .ray_at(1.0, 3.0);
            assert_eq!((r.tmin, r.tmax), (0.0, f32::INFINITY));
        }
    }

    #[test]
    fn centre_ray_looks_at_target_and_y_points_down() {
        let c = CameraRays::new(&cam(Projection::Perspective { fov_y_deg: 90.0 }), 4, 2);
        let r = c.ray_at(2.0, 1.0);
        assert!((r.dir - Vec3::NEG_Z).length() < 1e-6);
        // Top edge of a 90° fov: 45° up; left edge: aspect 2 -> tan = 2.
        let top = c.ray_at(2.0, 0.0).dir;
        assert!((top - Vec3::new(0.0, 1.0, -1.0).normalize()).length() < 1e-6, "{top}");
        let left = c.ray_at(0.0, 1.0).dir;
        assert!((left - Vec3::new(-2.0, 0.0, -1.0).normalize()).length() < 1e-6, "{left}");
    }

    #[test]
    fn a_pixel_cone_is_one_pixel_wide_at_unit_distance() {
        // 90° over 100 pixels: the window is 2 units high at distance 1.
        let c = CameraRays::new(&cam(Projection::Perspective { fov_y_deg: 90.0 }), 200, 100).pixel_cone();
        assert_eq!(c.width, 0.0);
        assert!((c.spread - 0.02).abs() < 1e-7, "{c:?}");
        // Neighbouring pixel centres on the axis are that far apart at distance 1.
        let rays = CameraRays::new(&cam(Projection::Perspective { fov_y_deg: 90.0 }), 200, 100);
        let (a, b) = (rays.ray_at(100.0, 50.0).dir, rays.ray_at(100.0, 51.0).dir);
        assert!(((a / a.z - b / b.z).length() - c.spread).abs() < 1e-6);
        let p = CameraRays::new(&cam(Projection::Parallel { height: 4.0 }), 8, 8).pixel_cone();
        assert_eq!((p.width, p.spread), (0.5, 0.0));
    }

    #[test]
    fn parallel_rays_share_a_direction_and_span_the_height() {
        let c = CameraRays::new(&cam(Projection::Parallel { height: 4.0 }), 2, 2);
        let a = c.ray_at(1.0, 0.0);
        let b = c.ray_at(1.0, 2.0);
        assert_eq!(a.dir, b.dir);
        assert!((a.origin - Vec3::new(0.0, 2.0, 5.0)).length() < 1e-6, "{}", a.origin);
        assert!((b.origin - Vec3::new(0.0, -2.0, 5.0)).length() < 1e-6, "{}", b.origin);
    }

    #[test]
    fn degenerate_cameras_give_finite_rays() {
        let cases = [
            Camera { up: Vec3::Z, ..cam(Projection::Perspective { fov_y_deg: 45.0 }) },
            Camera { up: Vec3::ZERO, ..cam(Projection::Perspective { fov_y_deg: f32::NAN }) },
            Camera { look_at: Vec3::new(0.0, 0.0, 5.0), ..cam(Projection::Parallel { height: -1.0 }) },
            Camera { position: Vec3::splat(f32::NAN), ..cam(Projection::Perspective { fov_y_deg: 400.0 }) },
            Camera { up: Vec3::new(0.0, f32::INFINITY, 0.0), ..cam(Projection::Perspective { fov_y_deg: 0.0 }) },
        ];
        for (i, c) in cases.iter().enumerate() {
            let rays = CameraRays::new(c, 0, 3);
            for (x, y) in [(0, 0), (0, 2), (1, 1)] {
                let r = rays.primary(x, y);
                assert!(r.origin.is_finite() && r.dir.is_finite() && r.dir != Vec3::ZERO, "case {i}: {r:?}");
            }
        }
    }
}
