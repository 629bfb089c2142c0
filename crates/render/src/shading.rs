//! Whitted's shading at one hit, without the recursion: the local term (ambient plus
//! every light's Lambert/Phong through its shadow ray) and the scattered children
//! (mirror reflection, Snell refraction, their Fresnel-split coefficients and the
//! weight rule that decides whether they are traced). The recursive integrator
//! (`whitted.rs`) and the cumulative one (`cumulative/`) both shade through here, so
//! they agree on every hit by construction.
//!
//! Decisions the seed leaves open, and what this file does:
//! - Shadow rays let light through transparent surfaces, dimmed and tinted by each one
//!   they cross (`shadow.rs`); opaque surfaces block. (The seed casts one `occluded` ray
//!   per light, which made glass cast a black shadow; a frame without transparent
//!   materials still does exactly that.)
//! - Normals are oriented by `facing.rs`: the geometric normal towards the ray, the
//!   shading normal into its hemisphere and bent where its mirror direction would enter
//!   the surface (silhouettes). Refraction about the shading normal falls back to the
//!   geometric normal where it would not cross the triangle's plane.
//! - Entering or leaving a transparent object is decided by the geometric normal as wound
//!   (`(p1-p0)×(p2-p0)` points outwards) against the ray direction. There is no stack of
//!   nested media: entering goes from the environment's ior to the material's, leaving
//!   goes back to the environment's.
//! - A transparent surface splits its transparency coefficient between refraction and
//!   reflection by the Fresnel equations for unpolarised light (the seed gives constant
//!   coefficients and no rule): `transparency × (1 − F)` refracts and `transparency × F` is
//!   added to the mirror coefficient. Total internal reflection is `F = 1`, so that energy
//!   is reflected instead of lost. Without this split, rays entering a tessellated glass
//!   sphere at its rim refract at the critical angle, are reflected totally at the far
//!   side by a fraction of a degree of tessellation error, and stay trapped until the
//!   recursion limit: dark dots on the outline. With it, the rim mostly reflects, as glass
//!   does.
//! - The child ray's weight is the parent's weight times the largest component of its
//!   coefficient (seed 003's GPU rule); it is traced only when the parent's level is below
//!   `max_recursion_level` and that weight exceeds `min_weight`.

// `!(x > y)` is deliberate throughout: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::{CameraRays, Facing, RayCone, RayCounts, Sampler, SceneIntersector, Shadows, SurfaceHit};
use dynray_geom::{Ray, Vec3};
use dynray_scene::{Color, Frame, LightKind};

/// Hard cap on the recursion level, whatever the settings say: each level is one stack
/// frame of [`crate::Whitted::trace`] (and one bounce pass of the cumulative
/// integrator), and a scene file asking for a million levels between two mirrors must
/// not overflow the thread's stack. The seed's experiments go to 10.
pub const MAX_LEVEL_CAP: u32 = 64;

/// Whitted's shading over one frame's lights, settings and environment, tracing its
/// shadow rays through the frame's scene intersector.
pub(crate) struct WhittedShading<'a> {
    frame: &'a Frame,
    scene: &'a SceneIntersector<'a>,
    /// Offset scale from the scene size, added to the per-point part in [`Self::eps`].
    eps_base: f32,
    env_ior: f32,
    /// `max_recursion_level`, capped at [`MAX_LEVEL_CAP`].
    pub max_level: u32,
    min_weight: f32,
    shadows: Shadows,
    /// The footprint of a camera ray of one sample per pixel ([`CameraRays::pixel_cone`]).
    pixel_cone: RayCone,
}

/// What shading needs about a hit: the surface and its normals as the incoming ray sees
/// them (Whitted shades the side it sees).
pub(crate) struct Surface<'m> {
    pub hit: SurfaceHit<'m>,
    pub facing: Facing,
}

/// One ray a hit scatters: its direction and the coefficient its radiance is multiplied by.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Child {
    pub dir: Vec3,
    pub coef: Color,
}

/// The children of one hit, in the order Whitted adds them: reflection, then refraction.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Scatter {
    pub reflect: Option<Child>,
    pub refract: Option<Child>,
}

impl<'a> WhittedShading<'a> {
    /// Shading for `frame` whose rays go through `scene`.
    pub fn new(frame: &'a Frame, scene: &'a SceneIntersector<'a>) -> Self {
        let diag = scene.bounds().extent().length();
        let diag = if diag.is_finite() && diag > 0.0 { diag } else { 1.0 };
        Self {
            frame,
            scene,
            eps_base: diag * 1e-5,
            env_ior: sane_ior(frame.environment.ior),
            max_level: frame.settings.max_recursion_level.min(MAX_LEVEL_CAP),
            min_weight: frame.settings.min_weight,
            shadows: Shadows::new(frame),
            pixel_cone: CameraRays::new(&frame.camera, frame.settings.width, frame.settings.height).pixel_cone(),
        }
    }

    /// The footprint of the camera ray of the pixel sample `sampler` draws for: the
    /// pixel's cone, shared among the samples of its pattern.
    pub fn camera_cone(&self, sampler: &Sampler) -> RayCone {
        self.pixel_cone.for_samples(sampler.pattern_count())
    }

    /// The closest hit of `ray` (whose footprint is `cone`: textures are filtered by
    /// it), oriented towards it; `None` on a miss.
    pub fn intersect(&self, ray: &Ray, cone: &RayCone) -> Option<Surface<'a>> {
        self.scene.intersect_cone(ray, cone).map(|hit| Surface { facing: Facing::new(&hit, ray.dir), hit })
    }

    /// [`Self::intersect`] of each of a batch of coherent rays (camera rays in pixel
    /// order, `cones[i]` the footprint of `rays[i]`), traced through the scene's coherent
    /// path: packets where the structure has them, the same answers.
    pub fn intersect_coherent(&self, rays: &[Ray], cones: &[RayCone]) -> Vec<Option<Surface<'a>>> {
        let hits = self.scene.intersect_coherent_cones(rays, cones);
        hits.into_iter()
            .zip(rays)
            .map(|(h, ray)| h.map(|hit| Surface { facing: Facing::new(&hit, ray.dir), hit }))
            .collect()
    }

    /// What a ray that hits nothing sees.
    pub fn background(&self) -> Color {
        self.frame.environment.background
    }

    /// Offset for rays leaving `p`: relative to the scene and to the magnitude of `p`,
    /// so it stays above the f32 rounding of the hit point at any scale.
    pub fn eps(&self, p: Vec3) -> f32 {
        let m = p.abs().max_element();
        self.eps_base + if m.is_finite() { m * 1e-5 } else { 0.0 }
    }

    /// The local term at `s` for a ray of unit direction `d` (zero for a degenerate
    /// one): ambient plus every light's diffuse and Phong highlight, each through its
    /// shadow ray (counted in `counts`). `eps` is [`Self::eps`] of the hit point.
    pub fn local(&self, d: Vec3, s: &Surface<'_>, eps: f32, counts: &mut RayCounts) -> Color {
        let (m, p) = (s.hit.material, s.hit.p);
        let Facing { ng, ns, .. } = s.facing;
        let view = -d;
        let (diffuse, ambient) = (s.hit.diffuse(), s.hit.ambient());
        let mut c = ambient * self.frame.environment.ambient;

        for light in &self.frame.lights {
            let (l, tmax, att) = match light.kind {
                LightKind::Point { position, falloff } | LightKind::Spot { position, falloff, .. } => {
                    let to = position - p;
                    let dist = to.length();
                    if !(dist > 0.0 && dist.is_finite()) {
                        continue;
                    }
                    let l = to / dist;
                    (l, dist - eps, attenuation(dist, falloff) * light.kind.cone_factor(-l))
                }
                LightKind::Directional { direction } => (-direction.normalize_or_zero(), f32::INFINITY, 1.0),
            };
            if att == 0.0 {
                continue;
            }
            let ndl = ns.dot(l);
            // Also rejects a zero or NaN light direction and an infinite attenuation.
            if !(ndl > 0.0) || !att.is_finite() {
                continue;
            }
            // Start on the light's side of the triangle's plane, so the shadow ray cannot
            // hit the triangle it leaves.
            let side = if ng.dot(l) >= 0.0 { ng } else { -ng };
            let shadow = Ray::with_interval(p + side * eps, l, 0.0, tmax);
            let through = self.shadows.light_through(self.scene, &shadow, counts);
            if through == Color::ZERO {
                continue;
            }
            let r = ns * (2.0 * ndl) - l;
            let highlight =
                if m.spot == Color::ZERO { Color::ZERO } else { m.spot * r.dot(view).max(0.0).powf(m.shine) };
            c += light.color * through * att * (diffuse * ndl + highlight);
        }
        c
    }

    /// The mirror and refracted children of a ray of unit direction `d` at `s`, before
    /// the weight rule ([`Self::child_weight`]); the caller checks the level limit.
    pub fn scatter(&self, d: Vec3, s: &Surface<'_>) -> Scatter {
        let m = s.hit.material;
        let Facing { ng, entering, .. } = s.facing;
        let mut mirror = m.specular;
        let mut transmitted = None;
        if m.transparency.max_element() > 0.0 {
            let ior = sane_ior(m.ior);
            let eta = if entering { self.env_ior / ior } else { ior / self.env_ior };
            // Refracted about the (unbent) shading normal, the ray must still cross the
            // triangle's plane; where it would not (silhouettes), the geometric normal
            // refracts.
            let smooth = if s.hit.ns.dot(ng) < 0.0 { -s.hit.ns } else { s.hit.ns };
            let crossing = |t: &Vec3| t.dot(ng) < 0.0;
            let refracted = [smooth, ng].into_iter().find_map(|n| refract(d, n, eta).filter(crossing).map(|t| (t, n)));
            match refracted {
                Some((t, n)) => {
                    let r = fresnel(-d.dot(n), eta);
                    mirror += m.transparency * r;
                    transmitted = Some(Child { dir: t, coef: m.transparency * (1.0 - r) });
                }
                None => mirror += m.transparency,
            }
        }
        Scatter {
            reflect: (mirror.max_element() > 0.0).then(|| Child { dir: s.facing.reflect(d), coef: mirror }),
            refract: transmitted,
        }
    }

    /// The weight of `child` of a ray of weight `weight`, when it is to be traced (it
    /// exceeds `min_weight`); `None` when the rule stops it.
    pub fn child_weight(&self, weight: f32, child: &Child) -> Option<f32> {
        let w = weight * child.coef.max_element();
        (w > self.min_weight).then_some(w)
    }

    /// The ray of a child leaving `s` along `dir`, offset by `eps` to the side of the
    /// triangle's plane it goes to.
    pub fn child_ray(&self, s: &Surface<'_>, dir: Vec3, eps: f32) -> Ray {
        let ng = s.facing.ng;
        let side = if ng.dot(dir) >= 0.0 { ng } else { -ng };
        Ray::new(s.hit.p + side * eps, dir)
    }
}

/// `c` with NaN components replaced by zero: a NaN from a hostile material (NaN shine,
/// inf × 0) must not spread into a pixel.
pub(crate) fn no_nan(c: Color) -> Color {
    Color::from_array(c.to_array().map(|x| if x.is_nan() { 0.0 } else { x }))
}

/// `1 / d^falloff`; falloff 0 is no attenuation, negative exponents grow with distance as
/// written.
fn attenuation(dist: f32, falloff: i32) -> f32 {
    if falloff == 0 {
        1.0
    } else {
        1.0 / dist.powi(falloff)
    }
}

/// A usable index of refraction: positive and finite, otherwise 1 (no bending).
fn sane_ior(ior: f32) -> f32 {
    if ior.is_finite() && ior > 0.0 {
        ior
    } else {
        1.0
    }
}

/// Fresnel reflectance of an unpolarised ray arriving at a dielectric interface with
/// `cos_i` between the ray and the normal on its side and `eta = n_from / n_to`: the
/// mean of the s and p reflectances; 1 beyond the critical angle, 0 when `eta` is 1.
pub(crate) fn fresnel(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin_t2 = eta * eta * (1.0 - cos_i * cos_i);
    if !(sin_t2 < 1.0) {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r = 0.5 * (rs * rs + rp * rp);
    if r.is_finite() {
        r.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// Snell refraction of unit `d` through a surface with unit normal `n` facing the
/// incoming ray (`d·n <= 0`), `eta = n_from / n_to`. `None` on total internal reflection.
pub(crate) fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if !(k >= 0.0) {
        return None;
    }
    Some((d * eta + n * (eta * cos_i - k.sqrt())).normalize_or_zero()).filter(|t| *t != Vec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::facing::reflect;

    #[test]
    fn reflect_mirrors_about_the_normal() {
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        let r = reflect(d, Vec3::Y);
        assert!((r - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn refract_obeys_snell() {
        let d = Vec3::new(40f32.to_radians().sin(), -40f32.to_radians().cos(), 0.0);
        let t = refract(d, Vec3::Y, 1.0 / 1.5).unwrap();
        let sin_t = t.x;
        assert!((sin_t - 40f32.to_radians().sin() / 1.5).abs() < 1e-6, "{sin_t}");
        assert!(t.y < 0.0 && (t.length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn refract_with_eta_one_goes_straight() {
        let d = Vec3::new(0.3, -0.8, 0.2).normalize();
        let t = refract(d, Vec3::Y, 1.0).unwrap();
        assert!((t - d).length() < 1e-6, "{t} {d}");
    }

    #[test]
    fn total_internal_reflection_beyond_the_critical_angle() {
        // Glass to air: critical angle asin(1/1.5) ≈ 41.8°.
        let at = |deg: f32| Vec3::new(deg.to_radians().sin(), -deg.to_radians().cos(), 0.0);
        assert!(refract(at(41.0), Vec3::Y, 1.5).is_some());
        assert!(refract(at(42.5), Vec3::Y, 1.5).is_none());
        assert!(refract(at(10.0), Vec3::Y, f32::NAN).is_none());
    }

    #[test]
    fn fresnel_matches_known_values() {
        // Normal incidence, air to glass: ((1 - 1.5) / (1 + 1.5))² = 0.04.
        assert!((fresnel(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        // Matched media reflect nothing; grazing incidence reflects everything.
        assert!(fresnel(0.3, 1.0) < 1e-12);
        assert!(fresnel(1e-4, 1.0 / 1.5) > 0.999);
        // Beyond the critical angle (glass to air, 41.8°): total.
        assert_eq!(fresnel(45f32.to_radians().cos(), 1.5), 1.0);
        // Reciprocity: the same pair of angles reflects the same from either side.
        let (ci, eta) = (30f32.to_radians().cos(), 1.0 / 1.5);
        let ct = (1.0 - eta * eta * (1.0 - ci * ci)).sqrt();
        assert!((fresnel(ci, eta) - fresnel(ct, 1.0 / eta)).abs() < 1e-6);
        assert_eq!(fresnel(f32::NAN, 1.5), 1.0);
    }

    #[test]
    fn attenuation_is_inverse_power() {
        assert_eq!(attenuation(3.0, 0), 1.0);
        assert_eq!(attenuation(2.0, 2), 0.25);
        assert_eq!(attenuation(2.0, 1), 0.5);
    }
}
