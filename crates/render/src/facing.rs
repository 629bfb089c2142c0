//! The normals of a hit as seen from the side a ray arrives on, with the shading normal
//! adapted so that scattered rays leave on the correct side of the real surface.
//!
//! Interpolated vertex normals belong to a smooth surface that the triangles only
//! approximate. Near a silhouette the two disagree: a camera ray grazing a tessellated
//! sphere hits the front of a triangle (`ng · d < 0`) while the mirror direction about
//! the shading normal points *into* the triangle (`r · ng < 0`). Traced as it is, that
//! reflection starts inside the mesh, bounces between its inner faces and returns almost
//! black: the isolated dark pixels that used to sit on mirror outlines. Flipping the
//! shading normal by `ns · d` (what the Whitted tracer did) makes it worse, because at
//! such points it turns `ns` into the surface.
//!
//! The rule here (every integrator uses it):
//! 1. the geometric normal is turned towards the incoming ray: `ng · wo > 0` with
//!    `wo = -d`; that side decides entering or leaving a medium;
//! 2. the shading normal is turned into the same hemisphere as that geometric normal
//!    (never by its own sign against the ray, which is unreliable at silhouettes);
//! 3. when the mirror direction about it would not leave the geometric surface by at
//!    least [`MIN_EXIT_COS`], the shading normal is bent to the half vector between `wo`
//!    and the nearest direction that does — the shading-normal adaptation of the Iray
//!    renderer (Keller et al., "The Iray Light Transport Simulation and Rendering System",
//!    2017, §A.3). Away from silhouettes nothing changes, so smooth shading stays smooth.

use crate::SurfaceHit;
use dynray_geom::Vec3;

/// Smallest cosine between a reflected direction and the facing geometric normal: the
/// reflection leaves the triangle's plane at least this steeply (≈ 0.06°).
pub const MIN_EXIT_COS: f32 = 1e-3;

/// A hit's normals oriented for the ray that arrived at it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Facing {
    /// Unit geometric normal on the side the ray came from.
    pub ng: Vec3,
    /// Unit shading normal in `ng`'s hemisphere, adapted (module docs) so that
    /// `reflect(d, ns)` leaves the surface on `ng`'s side.
    pub ns: Vec3,
    /// True when the ray arrived on the side the geometry's normal points to (the
    /// outside of a closed mesh wound counter-clockwise): it enters the material.
    pub entering: bool,
}

impl Facing {
    /// Orients `hit`'s normals for a ray of direction `d` (any length) that arrived at it.
    pub fn new(hit: &SurfaceHit<'_>, d: Vec3) -> Self {
        let d = d.normalize_or_zero();
        let entering = hit.ng.dot(d) < 0.0;
        let ng = if entering { hit.ng } else { -hit.ng };
        let ns = if hit.ns.dot(ng) < 0.0 { -hit.ns } else { hit.ns };
        Self { ng, ns: adapt(-d, ng, ns), entering }
    }

    /// Mirror direction of `d` (unit) about the shading normal: always on `ng`'s side.
    pub fn reflect(&self, d: Vec3) -> Vec3 {
        reflect(d, self.ns)
    }
}

/// Bends unit `ns` (in `ng`'s hemisphere) towards the half vector of `wo` and the
/// reflection kept just above the surface, when the plain reflection would go below it.
fn adapt(wo: Vec3, ng: Vec3, ns: Vec3) -> Vec3 {
    if wo == Vec3::ZERO {
        return ns;
    }
    let r = reflect(-wo, ns);
    let up = r.dot(ng);
    if up >= MIN_EXIT_COS {
        return ns;
    }
    // The nearest direction to r that leaves at MIN_EXIT_COS: its tangential part, scaled
    // to keep unit length, plus that much of ng.
    let tangent = (r - ng * up).normalize_or_zero();
    if tangent == Vec3::ZERO {
        return ng;
    }
    let kept = tangent * (1.0 - MIN_EXIT_COS * MIN_EXIT_COS).sqrt() + ng * MIN_EXIT_COS;
    let half = (wo + kept).normalize_or_zero();
    if half == Vec3::ZERO || !half.is_finite() {
        ng
    } else {
        half
    }
}

/// Mirror direction of unit `d` about unit `n`.
pub(crate) fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - n * (2.0 * d.dot(n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::GeometryRef;
    use dynray_geom::Vec2;
    use dynray_scene::Material;

    fn hit(ng: Vec3, ns: Vec3, m: &Material) -> SurfaceHit<'_> {
        SurfaceHit {
            t: 1.0,
            p: Vec3::ZERO,
            ng,
            ns,
            uv: Vec2::ZERO,
            texel: dynray_scene::Color::ONE,
            material: m,
            at: GeometryRef { geometry: 0, instance: 0, prim: 0 },
        }
    }

    #[test]
    fn agreeing_normals_are_left_alone() {
        let m = Material::default();
        let ns = Vec3::new(0.1, 1.0, 0.0).normalize();
        let d = Vec3::new(0.3, -1.0, 0.2).normalize();
        let f = Facing::new(&hit(Vec3::Y, ns, &m), d);
        assert!(f.entering);
        assert_eq!((f.ng, f.ns), (Vec3::Y, ns));
    }

    #[test]
    fn from_behind_both_normals_turn_and_the_ray_leaves() {
        let m = Material::default();
        let ns = Vec3::new(0.1, 1.0, 0.0).normalize();
        let f = Facing::new(&hit(Vec3::Y, ns, &m), Vec3::new(0.0, 1.0, 0.0));
        assert!(!f.entering);
        assert_eq!(f.ng, -Vec3::Y);
        assert_eq!(f.ns, -ns);
    }

    /// The silhouette case measured on the Whitted example's mirror sphere: the ray hits
    /// the front of the triangle (`ng · d = -0.068`), the interpolated normal faces the
    /// ray too (`ns · d = -0.031`), yet its mirror direction went into the triangle.
    #[test]
    fn grazing_reflection_is_kept_above_the_surface() {
        let m = Material::default();
        let ng = Vec3::Y;
        let d = Vec3::new(0.0, -0.0677, (1.0f32 - 0.0677 * 0.0677).sqrt());
        // A shading normal leaning away from the ray yet still facing it (ns · d < 0), so
        // that r · ng < 0.
        let ns = Vec3::new(0.0, 1.0, 0.04).normalize();
        assert!(ns.dot(d) < 0.0);
        assert!(reflect(d, ns).dot(ng) < 0.0, "the test must start from a bad reflection");
        let f = Facing::new(&hit(ng, ns, &m), d);
        let r = f.reflect(d);
        assert!(r.dot(ng) >= MIN_EXIT_COS * 0.999, "{}", r.dot(ng));
        assert!((r.length() - 1.0).abs() < 1e-5);
        assert!(f.ns.dot(ng) > 0.0 && f.ns.dot(-d) > 0.0);
    }

    /// A shading normal that faces away from the ray (`ns · d > 0`) while the ray hits the
    /// front: the old flip by `ns · d` turned it into the surface.
    #[test]
    fn shading_normal_facing_away_is_not_flipped_into_the_surface() {
        let m = Material::default();
        let d = Vec3::new(0.0, -0.02, 1.0).normalize();
        let ns = Vec3::new(0.0, 1.0, 0.1).normalize();
        assert!(ns.dot(d) > 0.0);
        let f = Facing::new(&hit(Vec3::Y, ns, &m), d);
        assert!(f.ns.dot(Vec3::Y) > 0.0);
        assert!(f.reflect(d).dot(Vec3::Y) > 0.0);
    }
}
