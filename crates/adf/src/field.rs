//! What a distance field samples: an exact distance function split into its unsigned
//! part and its sign, so the builder can skip most sign queries (see
//! `build.rs`, "sign propagation").

use dynray_geom::Vec3;

/// An exact distance function the builder samples (world space).
pub trait DistanceSource: Sync {
    /// Unsigned distance from `p` to the surface.
    fn unsigned_distance(&self, p: Vec3) -> f32;

    /// True when `p` is inside the solid (the signed distance is negative there).
    fn inside(&self, p: Vec3) -> bool;

    /// Signed distance: negative inside.
    fn signed_distance(&self, p: Vec3) -> f32 {
        let d = self.unsigned_distance(p);
        if self.inside(p) {
            -d
        } else {
            d
        }
    }
}

/// A sphere, exactly: the analytic source of the deep-level tests and a reference for
/// reconstruction error.
#[derive(Clone, Copy, Debug)]
pub struct SphereSource {
    /// Centre.
    pub centre: Vec3,
    /// Radius.
    pub radius: f32,
}

impl DistanceSource for SphereSource {
    fn unsigned_distance(&self, p: Vec3) -> f32 {
        ((p - self.centre).length() - self.radius).abs()
    }

    fn inside(&self, p: Vec3) -> bool {
        (p - self.centre).length() < self.radius
    }
}
