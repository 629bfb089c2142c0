//! The shading frame (local coordinates with the shading normal as +z, where every BSDF
//! works) and the warps from uniform numbers to directions and points.

use dynray_geom::Vec3;
use std::f32::consts::{PI, TAU};

/// An orthonormal frame `(s, t, n)` around a unit normal `n`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Local {
    s: Vec3,
    t: Vec3,
    n: Vec3,
}

impl Local {
    /// The frame of unit `n` (Duff et al., "Building an Orthonormal Basis, Revisited",
    /// JCGT 2017: continuous except across `n.z = 0`'s sign, no division by zero).
    pub fn new(n: Vec3) -> Self {
        let sign = 1f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Self { s, t, n }
    }

    /// `v` in the frame's coordinates (`z` along the normal).
    pub fn to_local(self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local `v` back in world coordinates.
    pub fn to_world(self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

/// A point of the unit disk, uniform in area (Shirley and Chiu's concentric map).
pub(crate) fn square_to_disk(u: (f32, f32)) -> (f32, f32) {
    let (a, b) = (2.0 * u.0 - 1.0, 2.0 * u.1 - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let (r, phi) = if a.abs() > b.abs() { (a, (PI / 4.0) * (b / a)) } else { (b, PI / 2.0 - (PI / 4.0) * (a / b)) };
    (r * phi.cos(), r * phi.sin())
}

/// A cosine-distributed direction of the upper hemisphere (density `z / π`).
pub(crate) fn cosine_hemisphere(u: (f32, f32)) -> Vec3 {
    let (x, y) = square_to_disk(u);
    Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
}

/// A uniform direction of the unit sphere (density `1 / 4π`).
pub(crate) fn uniform_sphere(u: (f32, f32)) -> Vec3 {
    let z = 1.0 - 2.0 * u.0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u.1;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Barycentric `(b1, b2)` of a point uniform in area on a triangle.
pub(crate) fn uniform_triangle(u: (f32, f32)) -> (f32, f32) {
    let s = u.0.sqrt();
    (1.0 - s, u.1 * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal_and_round_trip() {
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize(), Vec3::new(-1e-7, 0.0, -1.0)] {
            let f = Local::new(n);
            assert!((f.s.dot(f.t)).abs() < 1e-6 && f.s.dot(n).abs() < 1e-6 && f.t.dot(n).abs() < 1e-6);
            assert!((f.s.cross(f.t) - n).length() < 1e-5, "right-handed for {n}");
            let v = Vec3::new(0.2, 0.7, -0.1);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-6);
            assert!((f.to_local(n) - Vec3::Z).length() < 1e-6);
        }
    }

    #[test]
    fn warps_stay_on_their_domains() {
        for i in 0..64 {
            let u = ((i % 8) as f32 / 8.0 + 0.01, (i / 8) as f32 / 8.0 + 0.02);
            let c = cosine_hemisphere(u);
            assert!((c.length() - 1.0).abs() < 1e-5 && c.z >= 0.0);
            assert!((uniform_sphere(u).length() - 1.0).abs() < 1e-5);
            let (b1, b2) = uniform_triangle(u);
            assert!(b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 + 1e-6);
        }
    }
}
