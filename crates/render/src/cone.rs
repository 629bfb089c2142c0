//! Ray cones (Akenine-Möller et al., "Texture Level of Detail Strategies for Real-Time
//! Ray Tracing", Ray Tracing Gems ch. 20, 2019): the footprint a ray stands for, so a
//! texture lookup can read the mip level that footprint covers instead of one texel of
//! the full image (docs/rendering.md, "Texture filtering").
//!
//! A camera ray's cone is one pixel wide: its width grows from `width` at the origin by
//! `spread` per unit of distance (a perspective camera's pixel angle; a parallel camera's
//! cone keeps the pixel's width). Carried along a path it keeps its spread and starts the
//! next segment with the width it reached at the hit ([`RayCone::advance`]), so a floor
//! seen in a flat mirror is filtered as if seen through it. Curvature is ignored (a curved
//! mirror widens the cone, which this leaves narrower: sharper, some aliasing, never
//! blur), and after a rough bounce the cone goes on with the camera's spread, as pbrt-v4
//! sizes a non-specular vertex's footprint from the camera's — narrower than the lobe,
//! so indirect lookups are never over-blurred.
//!
//! At a hit the width becomes a width in uv units through the triangle's uv-to-world
//! scale ([`uv_width`]): `√(uv area / world area)`, divided by `|cos θ|` between the ray
//! and the triangle's normal (the footprint stretched along the surface at grazing
//! angles; an isotropic lookup takes that longer axis, as GPUs' trilinear does).
//! [`dynray_scene::TextureRef::lod`] turns it into a mip level.

use dynray_geom::{Vec2, Vec3};

/// The footprint of a ray: `width` at its origin, growing by `spread` per unit of `t`
/// along a unit direction. [`RayCone::POINT`] (both zero) is a point lookup, the finest
/// mip level, which is what a ray without a cone gets.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RayCone {
    /// Width of the footprint at the ray's origin, in world units.
    pub width: f32,
    /// Growth of the width per unit distance along the ray (the spread angle's tangent).
    pub spread: f32,
}

/// Smallest `|cos θ|` a footprint is divided by: past it the footprint is already wider
/// than any texture's coarsest level (2^20 times the cone's width), and dividing by a
/// cosine of exactly zero would give infinity.
const MIN_COS: f32 = 1e-6;

impl RayCone {
    /// No footprint: lookups read the finest level, as before texture filtering.
    pub const POINT: RayCone = RayCone { width: 0.0, spread: 0.0 };

    /// The width at distance `dist` along the ray.
    pub fn width_at(&self, dist: f32) -> f32 {
        self.width + self.spread * dist
    }

    /// The cone of a ray leaving the hit at distance `dist` (a reflection, refraction or
    /// any bounce): the width reached there, the same spread.
    pub fn advance(&self, dist: f32) -> RayCone {
        RayCone { width: self.width_at(dist), spread: self.spread }
    }

    /// The cone scaled by `s` (both width and spread).
    pub fn scaled(&self, s: f32) -> RayCone {
        RayCone { width: self.width * s, spread: self.spread * s }
    }

    /// The cone of one of `spp` samples of a pixel whose cone is `self`: pbrt's
    /// `max(1/8, 1/√spp)`. The samples of a pixel are averaged, so each need only filter
    /// its share of the pixel (the film's box filter does the rest); the 1/8 floor keeps
    /// high sample counts from falling back to aliasing lookups.
    pub fn for_samples(&self, spp: u32) -> RayCone {
        self.scaled((1.0 / (spp.max(1) as f32).sqrt()).max(0.125))
    }
}

/// The width in uv units of a footprint `world_width` wide where a ray of direction
/// `dir` (any length) hits the triangle `p` with texture coordinates `uv`:
/// `world_width · √(uv area / world area) / |cos θ|`, `θ` between `dir` and the
/// triangle's normal. Infinite for a triangle of zero area (it reads the coarsest
/// level), NaN where the inputs are (which reads the finest).
pub fn uv_width(p: [Vec3; 3], uv: [Vec2; 3], dir: Vec3, world_width: f32) -> f32 {
    let n = (p[1] - p[0]).cross(p[2] - p[0]);
    let world_area2 = n.length();
    let uv_area2 = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]).abs();
    let cos = (n.dot(dir) / (world_area2 * dir.length())).abs().max(MIN_COS);
    world_width * (uv_area2 / world_area2).sqrt() / cos
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 × 2 world quad's lower triangle mapped onto the unit uv square.
    fn tri() -> ([Vec3; 3], [Vec2; 3]) {
        (
            [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)],
            [Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0)],
        )
    }

    #[test]
    fn cones_grow_with_distance_and_keep_growing_after_a_bounce() {
        let c = RayCone { width: 0.5, spread: 0.01 };
        assert_eq!(c.width_at(0.0), 0.5);
        assert_eq!(c.width_at(100.0), 1.5);
        let b = c.advance(100.0);
        assert_eq!((b.width, b.spread), (1.5, 0.01));
        assert_eq!(b.width_at(50.0), c.width_at(150.0), "a flat mirror continues the cone");
        assert_eq!(RayCone::POINT.advance(1e6), RayCone::POINT);
    }

    #[test]
    fn samples_share_the_pixel_footprint_down_to_an_eighth() {
        let c = RayCone { width: 1.0, spread: 0.004 };
        assert_eq!(c.for_samples(1), c);
        assert_eq!(c.for_samples(0), c);
        assert_eq!(c.for_samples(4), c.scaled(0.5));
        assert_eq!(c.for_samples(9).spread, 0.004 / 3.0);
        assert_eq!(c.for_samples(64), c.scaled(0.125));
        assert_eq!(c.for_samples(1024), c.scaled(0.125));
    }

    #[test]
    fn uv_width_scales_by_the_texture_density_and_the_incidence() {
        let (p, uv) = tri();
        // The quad is 2 world units per uv unit: half a uv unit per world unit.
        assert_eq!(uv_width(p, uv, Vec3::NEG_Z, 0.1), 0.05);
        // Seen at 60° from the normal the footprint on the surface doubles.
        let d = Vec3::new(0.0, 60f32.to_radians().sin(), -60f32.to_radians().cos());
        assert!((uv_width(p, uv, d * 3.0, 0.1) - 0.1).abs() < 1e-6, "{}", uv_width(p, uv, d, 0.1));
        // From behind, the same.
        assert_eq!(uv_width(p, uv, Vec3::Z, 0.1), 0.05);
        // Squeezing the uvs (a texture tiled 4 times each way) quadruples it.
        assert_eq!(uv_width(p, uv.map(|t| t * 4.0), Vec3::NEG_Z, 0.1), 0.2);
        // Grazing along the surface: huge but finite; a degenerate triangle: infinite.
        let w = uv_width(p, uv, Vec3::X, 0.1);
        assert!(w.is_finite() && w >= 0.05e6, "{w}");
        let flat = [p[0], p[1], p[1]];
        assert_eq!(uv_width(flat, uv, Vec3::NEG_Z, 0.1), f32::INFINITY);
        assert_eq!(uv_width(p, uv, Vec3::NEG_Z, 0.0), 0.0);
    }
}
