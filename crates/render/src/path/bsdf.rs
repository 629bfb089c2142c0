//! The path tracer's BSDFs at a hit, in the local shading frame (`z` = the shading
//! normal as the geometry orients it, never flipped towards the ray): evaluation, density
//! and importance sampling.
//!
//! Conventions (Mitsuba 3's): `wo` points to where the light goes (the viewer), `wi` is
//! the sampled or light direction; [`Bsdf::eval`] returns `f(wo, wi) · |cos θi|`, and a
//! sample's `weight` is that divided by its pdf. Reflecting BSDFs are one-sided unless
//! two-sided: seen from below (`wo.z ≤ 0`) they are black, as Mitsuba's are.
//!
//! From a [`Material`]: its physical [`dynray_scene::Bsdf`] when it has one (Mitsuba
//! scenes); otherwise the Phong mapping of the scene language's coefficients, a
//! two-sided mixture of lobes with the material's own weights (docs/rendering.md, "Path
//! tracer"):
//!
//! | coefficient | lobe |
//! |---|---|
//! | `diffuse` (× texture) | Lambertian, `ρ / π` |
//! | `spot`, `shine` | normalised modified Phong (Lafortune & Willems 1994): `ks (n + 2) / 2π · cos^n α` about the mirror direction |
//! | `specular` | perfect mirror |
//! | `transparency`, `ior` | smooth dielectric (Fresnel reflection and refraction) |
//!
//! scaled down together where their sum exceeds 1 in a channel, so no surface creates
//! energy; `ambient` has no physical meaning and is not used.

use super::fresnel;
use super::local::cosine_hemisphere;
use super::microfacet::Microfacet;
use crate::SurfaceHit;
use dynray_geom::Vec3;
use dynray_scene::{BsdfKind, Color, Material};
use std::f32::consts::{FRAC_1_PI, TAU};

/// A sampled direction.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BsdfSample {
    /// Local direction.
    pub wi: Vec3,
    /// `f · |cos θi| / pdf`.
    pub weight: Color,
    /// Density per solid angle (the discrete probability for a delta lobe).
    pub pdf: f32,
    /// From a delta (mirror or refraction) lobe: no light sample can reach it.
    pub delta: bool,
    /// Index ratio crossed (`eta_it` on refraction, 1 otherwise), for Russian roulette.
    pub eta: f32,
}

/// One scattering lobe.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Lobe {
    Diffuse(Color),
    /// Normalised modified Phong about the mirror direction: colour, exponent.
    Phong(Color, f32),
    /// Perfect mirror of constant reflectance.
    Mirror(Color),
    Conductor {
        eta: Color,
        k: Color,
        scale: Color,
        rough: Option<Microfacet>,
    },
    Dielectric {
        /// Inside over outside.
        eta: f32,
        r: Color,
        t: Color,
    },
}

impl Lobe {
    fn is_delta(&self) -> bool {
        match self {
            Lobe::Diffuse(_) | Lobe::Phong(..) => false,
            Lobe::Conductor { rough, .. } => rough.is_none(),
            Lobe::Mirror(_) | Lobe::Dielectric { .. } => true,
        }
    }

    /// Whether the lobe works on both sides (only dielectrics do by nature).
    fn is_two_sided_by_nature(&self) -> bool {
        matches!(self, Lobe::Dielectric { .. })
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Color {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Color::ZERO;
        }
        match *self {
            Lobe::Diffuse(rho) => rho * (FRAC_1_PI * wi.z),
            Lobe::Phong(ks, n) => {
                let c = mirror(wo).dot(wi);
                if c <= 0.0 {
                    return Color::ZERO;
                }
                ks * ((n + 2.0) / TAU * c.powf(n) * wi.z)
            }
            Lobe::Conductor { eta, k, scale, rough: Some(mf) } => {
                let h = (wo + wi).normalize_or_zero();
                if h.z <= 0.0 {
                    return Color::ZERO;
                }
                let f = fresnel::conductor(wi.dot(h), eta, k);
                scale * f * (mf.d(h) * mf.g(wo, wi, h) / (4.0 * wo.z))
            }
            _ => Color::ZERO,
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        match *self {
            Lobe::Diffuse(_) => FRAC_1_PI * wi.z,
            Lobe::Phong(_, n) => {
                let c = mirror(wo).dot(wi);
                if c <= 0.0 {
                    0.0
                } else {
                    (n + 1.0) / TAU * c.powf(n)
                }
            }
            Lobe::Conductor { rough: Some(mf), .. } => {
                let h = (wo + wi).normalize_or_zero();
                let dot = wo.dot(h);
                if h.z <= 0.0 || dot <= 0.0 {
                    return 0.0;
                }
                mf.pdf(wo, h) / (4.0 * dot)
            }
            _ => 0.0,
        }
    }

    /// A direction from this lobe alone; `weight` is this lobe's `f cos / pdf`.
    fn sample(&self, wo: Vec3, u1: f32, u2: (f32, f32)) -> Option<BsdfSample> {
        if let Lobe::Dielectric { eta, r, t } = *self {
            return sample_dielectric(wo, eta, r, t, u1);
        }
        if wo.z <= 0.0 {
            return None;
        }
        let smooth = |wi: Vec3| -> Option<BsdfSample> {
            let pdf = self.pdf(wo, wi);
            (pdf > 0.0).then(|| BsdfSample { wi, weight: self.eval(wo, wi) / pdf, pdf, delta: false, eta: 1.0 })
        };
        match *self {
            Lobe::Diffuse(rho) => {
                let wi = cosine_hemisphere(u2);
                (wi.z > 0.0).then_some(BsdfSample { wi, weight: rho, pdf: FRAC_1_PI * wi.z, delta: false, eta: 1.0 })
            }
            Lobe::Phong(_, n) => {
                // cos^n about the mirror direction, then discard what falls below.
                let cos = u2.0.powf(1.0 / (n + 1.0));
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let phi = TAU * u2.1;
                let r = mirror(wo);
                let frame = super::local::Local::new(r);
                let wi = frame.to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), cos));
                smooth(wi)
            }
            Lobe::Mirror(c) => Some(BsdfSample { wi: mirror(wo), weight: c, pdf: 1.0, delta: true, eta: 1.0 }),
            Lobe::Conductor { eta, k, scale, rough: None } => {
                let f = fresnel::conductor(wo.z, eta, k);
                Some(BsdfSample { wi: mirror(wo), weight: scale * f, pdf: 1.0, delta: true, eta: 1.0 })
            }
            Lobe::Conductor { eta, k, scale, rough: Some(mf) } => {
                let m = mf.sample(wo, u2);
                let dot = wo.dot(m);
                if dot <= 0.0 {
                    return None;
                }
                let wi = m * (2.0 * dot) - wo;
                if wi.z <= 0.0 {
                    return None;
                }
                let pdf = mf.pdf(wo, m) / (4.0 * dot);
                if !(pdf > 0.0) {
                    return None;
                }
                let f = fresnel::conductor(dot, eta, k);
                let weight = scale * f * (mf.d(m) * mf.g(wo, wi, m) / (4.0 * wo.z)) / pdf;
                Some(BsdfSample { wi, weight, pdf, delta: false, eta: 1.0 })
            }
            Lobe::Dielectric { .. } => None,
        }
    }
}

/// Mirror direction of `wo` about the local normal.
fn mirror(wo: Vec3) -> Vec3 {
    Vec3::new(-wo.x, -wo.y, wo.z)
}

/// Mitsuba's smooth dielectric: reflect with probability `R`, refract otherwise; the
/// refracted radiance is scaled by `eta_ti²` (radiance is compressed into the denser
/// medium's smaller solid angle).
fn sample_dielectric(wo: Vec3, eta: f32, r: Color, t: Color, u: f32) -> Option<BsdfSample> {
    if wo.z == 0.0 {
        return None;
    }
    let (fr, cos_t, eta_it, eta_ti) = fresnel::dielectric(wo.z, eta);
    if u < fr {
        Some(BsdfSample { wi: mirror(wo), weight: r, pdf: fr, delta: true, eta: 1.0 })
    } else {
        let wi = Vec3::new(-eta_ti * wo.x, -eta_ti * wo.y, cos_t);
        Some(BsdfSample { wi, weight: t * (eta_ti * eta_ti), pdf: 1.0 - fr, delta: true, eta: eta_it })
    }
}

/// Most lobes a mapped Phong material has.
const MAX_LOBES: usize = 4;

/// The BSDF at one hit: up to four weighted lobes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bsdf {
    lobes: [Option<(Lobe, f32)>; MAX_LOBES],
    two_sided: bool,
}

impl Bsdf {
    /// The BSDF of `hit`'s material; `env_ior` is the index of the medium outside
    /// transparent Phong materials.
    pub fn at(hit: &SurfaceHit<'_>, env_ior: f32) -> Self {
        Self::of(hit.material, hit.texel, env_ior)
    }

    /// The BSDF of `m` with its texture's colour `texel` (white when untextured).
    pub fn of(m: &Material, texel: Color, env_ior: f32) -> Self {
        let finite = |c: Color| Color::from_array(c.to_array().map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 }));
        if let Some(b) = &m.bsdf {
            let lobe = match b.kind {
                BsdfKind::Diffuse { reflectance } => Lobe::Diffuse(finite(reflectance * texel).min(Color::ONE)),
                BsdfKind::Conductor { eta, k, specular_reflectance, roughness } => Lobe::Conductor {
                    eta: finite(eta),
                    k: finite(k),
                    scale: finite(specular_reflectance),
                    rough: roughness.map(|r| Microfacet::new(r.distribution, r.alpha_u, r.alpha_v)),
                },
                BsdfKind::Dielectric { int_ior, ext_ior, specular_reflectance, specular_transmittance } => {
                    Lobe::Dielectric {
                        eta: sane_eta(int_ior / ext_ior),
                        r: finite(specular_reflectance),
                        t: finite(specular_transmittance),
                    }
                }
            };
            return Self { lobes: [Some((lobe, 1.0)), None, None, None], two_sided: b.two_sided };
        }
        // The Phong mapping (module docs).
        let kd = finite(m.diffuse * texel);
        let ks = finite(m.spot);
        let km = finite(m.specular);
        let kt = finite(m.transparency);
        let total = (kd + ks + km + kt).max_element();
        let norm = if total > 1.0 { 1.0 / total } else { 1.0 };
        let shine = if m.shine.is_finite() { m.shine.clamp(0.0, 1e4) } else { 1.0 };
        let eta = sane_eta(m.ior / if env_ior.is_finite() && env_ior > 0.0 { env_ior } else { 1.0 });
        let candidates = [
            (Lobe::Diffuse(kd * norm), kd),
            (Lobe::Phong(ks * norm, shine), ks),
            (Lobe::Mirror(km * norm), km),
            (Lobe::Dielectric { eta, r: kt * norm, t: kt * norm }, kt),
        ];
        let mut lobes = [None; MAX_LOBES];
        let weights: f32 = candidates.iter().map(|(_, c)| c.max_element()).sum();
        if weights > 0.0 {
            for (slot, (lobe, c)) in lobes.iter_mut().zip(candidates) {
                if c.max_element() > 0.0 {
                    *slot = Some((lobe, c.max_element() / weights));
                }
            }
        }
        Self { lobes, two_sided: true }
    }

    fn lobes(&self) -> impl Iterator<Item = (Lobe, f32)> + '_ {
        self.lobes.iter().flatten().copied()
    }

    /// The lobes with their choice probabilities (tables.rs exports them).
    pub(crate) fn lobe_list(&self) -> impl Iterator<Item = (Lobe, f32)> + '_ {
        self.lobes()
    }

    /// Whether reflecting lobes work from both sides.
    pub(crate) fn two_sided(&self) -> bool {
        self.two_sided
    }

    /// True when some lobe is not a delta: light sampling can reach it.
    pub fn has_smooth(&self) -> bool {
        self.lobes().any(|(l, _)| !l.is_delta())
    }

    /// `(wo, wi)` as a one-sided lobe sees them: mirrored to the upper side for a
    /// two-sided BSDF seen from below.
    fn side(&self, lobe: &Lobe, wo: Vec3, wi: Vec3) -> (Vec3, Vec3) {
        if self.two_sided && wo.z < 0.0 && !lobe.is_two_sided_by_nature() {
            (flip(wo), flip(wi))
        } else {
            (wo, wi)
        }
    }

    /// `f(wo, wi) · |cos θi|` of the smooth lobes (deltas evaluate to zero).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Color {
        self.lobes()
            .filter(|(l, _)| !l.is_delta())
            .map(|(l, _)| {
                let (o, i) = self.side(&l, wo, wi);
                l.eval(o, i)
            })
            .sum()
    }

    /// Density of [`Self::sample`] choosing `wi` through a smooth lobe.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.lobes()
            .filter(|(l, _)| !l.is_delta())
            .map(|(l, p)| {
                let (o, i) = self.side(&l, wo, wi);
                p * l.pdf(o, i)
            })
            .sum()
    }

    /// A direction for `wo`: a lobe chosen by its weight, then its sample. The weight
    /// of a smooth sample accounts for every smooth lobe (`eval / pdf` of the mixture).
    pub fn sample(&self, wo: Vec3, u1: f32, u2: (f32, f32)) -> Option<BsdfSample> {
        let mut u = u1;
        let (lobe, p) = {
            let mut chosen = None;
            let mut last = None;
            for (l, p) in self.lobes() {
                last = Some((l, p));
                if u < p {
                    chosen = Some((l, p));
                    break;
                }
                u -= p;
            }
            chosen.or(last)?
        };
        // Reuse the remainder of u1 (uniform on [0, 1) within the chosen lobe).
        let u = (u / p).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
        let flipped = self.two_sided && wo.z < 0.0 && !lobe.is_two_sided_by_nature();
        let o = if flipped { flip(wo) } else { wo };
        let mut s = lobe.sample(o, u, u2)?;
        if flipped {
            s.wi = flip(s.wi);
        }
        if s.delta {
            s.weight /= p;
            s.pdf *= p;
        } else {
            let pdf = self.pdf(wo, s.wi);
            if !(pdf > 0.0) {
                return None;
            }
            s.weight = self.eval(wo, s.wi) / pdf;
            s.pdf = pdf;
        }
        Some(s)
    }
}

fn flip(v: Vec3) -> Vec3 {
    Vec3::new(v.x, v.y, -v.z)
}

/// A usable relative index of refraction (1 for NaN, infinite or non-positive ones).
fn sane_eta(eta: f32) -> f32 {
    if eta.is_finite() && eta > 0.0 {
        eta
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::local::uniform_sphere;
    use dynray_scene::{Bsdf as Desc, Microfacet as Kind, Roughness};

    fn physical(kind: BsdfKind, two_sided: bool) -> Bsdf {
        let m = Material { bsdf: Some(Desc { kind, two_sided }), ..Material::default() };
        Bsdf::of(&m, Color::ONE, 1.0)
    }

    fn rough(kind: Kind, a: f32) -> BsdfKind {
        BsdfKind::Conductor {
            eta: Color::ZERO,
            k: Color::ONE,
            specular_reflectance: Color::ONE,
            roughness: Some(Roughness { distribution: kind, alpha_u: a, alpha_v: a }),
        }
    }

    fn phong(kd: f32, ks: f32, shine: f32, km: f32, kt: f32) -> Bsdf {
        let m = Material {
            diffuse: Color::splat(kd),
            spot: Color::splat(ks),
            shine,
            specular: Color::splat(km),
            transparency: Color::splat(kt),
            ior: 1.5,
            ..Material::default()
        };
        Bsdf::of(&m, Color::ONE, 1.0)
    }

    /// `n` pseudo-random 3D points from the renderer's own generator (fixed seed, so
    /// every estimate is deterministic).
    fn points(n: usize) -> impl Iterator<Item = (f32, (f32, f32))> {
        let mut r = crate::Sampler::new(42, 1, 0, 0, 0, 1);
        (0..n).map(move |_| (r.next_f32(), r.next_2d()))
    }

    /// The mean sample weight for `wo`: the directional albedo (energy reflected, and
    /// transmitted, for light arriving along `wo`); transmitted radiance weights are
    /// divided back by `eta_ti²`, which only rescales radiance, not energy.
    fn albedo(b: &Bsdf, wo: Vec3, n: usize) -> f64 {
        let mut sum = 0.0f64;
        for (u1, u2) in points(n) {
            if let Some(s) = b.sample(wo, u1, u2) {
                let energy = if s.eta != 1.0 { s.weight * s.eta * s.eta } else { s.weight };
                sum += energy.x as f64;
            }
        }
        sum / n as f64
    }

    fn dirs() -> [Vec3; 4] {
        [
            Vec3::Z,
            Vec3::new(0.3, 0.2, 0.9).normalize(),
            Vec3::new(-0.7, 0.1, 0.3).normalize(),
            Vec3::new(0.9, 0.0, 0.1).normalize(),
        ]
    }

    /// White furnace per BSDF: a white lossless BSDF reflects (or transmits) all the
    /// energy for every incident direction; microfacet models lose what single
    /// scattering misses (light the microfacets send below the horizon: GGX's long tail
    /// loses about 12 % at alpha 0.3, and 8 % at alpha 0.05 at 84° incidence, where
    /// masking dominates), and none creates energy.
    #[test]
    fn white_furnace_per_bsdf() {
        let diffuse = physical(BsdfKind::Diffuse { reflectance: Color::ONE }, false);
        let mirror = physical(
            BsdfKind::Conductor { eta: Color::ZERO, k: Color::ONE, specular_reflectance: Color::ONE, roughness: None },
            false,
        );
        let glass = physical(
            BsdfKind::Dielectric {
                int_ior: 1.5,
                ext_ior: 1.0,
                specular_reflectance: Color::ONE,
                specular_transmittance: Color::ONE,
            },
            false,
        );
        for wo in dirs() {
            assert!((albedo(&diffuse, wo, 20_000) - 1.0).abs() < 2e-3, "diffuse {wo}");
            assert!((albedo(&mirror, wo, 100) - 1.0).abs() < 1e-6, "mirror {wo}");
            for side in [wo, -wo] {
                assert!(
                    (albedo(&glass, side, 20_000) - 1.0).abs() < 1e-3,
                    "glass {side}: {}",
                    albedo(&glass, side, 20_000)
                );
            }
            for kind in [Kind::Beckmann, Kind::Ggx] {
                for a in [0.05, 0.3] {
                    let r = albedo(&physical(rough(kind, a), false), wo, 40_000);
                    let floor = if a > 0.1 || wo.z < 0.2 { 0.8 } else { 0.95 };
                    assert!(r <= 1.0 + 5e-3 && r > floor, "{kind:?} alpha {a} at {wo}: albedo {r}");
                }
            }
            // The Phong mapping: white in total, every lobe kind at once; the glossy lobe
            // loses what falls below the horizon, nothing gains.
            for b in [phong(0.3, 0.3, 30.0, 0.2, 0.2), phong(1.0, 0.0, 1.0, 0.0, 0.0), phong(0.9, 0.9, 5.0, 0.9, 0.0)] {
                let r = albedo(&b, wo, 40_000);
                assert!(r <= 1.0 + 5e-3 && r > 0.6, "phong mapping at {wo}: albedo {r}");
            }
        }
        // Phong mapping of a pure white diffuse surface is exactly Lambertian.
        assert!((albedo(&phong(1.0, 0.0, 1.0, 0.0, 0.0), Vec3::Z, 20_000) - 1.0).abs() < 2e-3);
    }

    /// One-sided BSDFs are black from behind; `twosided` and the Phong mapping are not.
    #[test]
    fn sidedness() {
        let back = Vec3::new(0.2, 0.1, -0.9).normalize();
        let inside = Vec3::new(-0.3, 0.0, -0.8).normalize();
        let one = physical(BsdfKind::Diffuse { reflectance: Color::splat(0.5) }, false);
        assert_eq!(albedo(&one, back, 1000), 0.0);
        assert_eq!(one.eval(back, inside), Color::ZERO);
        let two = physical(BsdfKind::Diffuse { reflectance: Color::splat(0.5) }, true);
        assert!((albedo(&two, back, 20_000) - 0.5).abs() < 2e-3);
        assert!(two.eval(back, inside).x > 0.0 && two.pdf(back, inside) > 0.0);
        assert_eq!(two.eval(back, -inside), Color::ZERO, "no transmission through a two-sided diffuse surface");
        assert!((albedo(&phong(0.5, 0.0, 1.0, 0.0, 0.0), back, 20_000) - 0.5).abs() < 2e-3);
    }

    /// `f(wo, wi) = f(wi, wo)` for the smooth lobes (eval returns `f · cos θi`).
    #[test]
    fn reciprocity() {
        let bsdfs = [
            physical(BsdfKind::Diffuse { reflectance: Color::splat(0.7) }, false),
            physical(rough(Kind::Beckmann, 0.2), false),
            physical(rough(Kind::Ggx, 0.4), false),
            physical(
                BsdfKind::Conductor {
                    eta: Color::new(0.14, 0.37, 1.44),
                    k: Color::new(3.98, 2.38, 1.60),
                    specular_reflectance: Color::ONE,
                    roughness: Some(Roughness { distribution: Kind::Ggx, alpha_u: 0.3, alpha_v: 0.1 }),
                },
                false,
            ),
            phong(0.4, 0.5, 12.0, 0.0, 0.0),
        ];
        for (i, b) in bsdfs.iter().enumerate() {
            for a in dirs() {
                for c in dirs() {
                    let c = Vec3::new(-c.x, c.y, c.z).normalize();
                    let f_ac = b.eval(a, c) / c.z;
                    let f_ca = b.eval(c, a) / a.z;
                    let tol = 1e-4 * f_ac.max_element().max(1.0);
                    assert!(
                        (f_ac - f_ca).abs().max_element() <= tol,
                        "bsdf {i}: f({a}, {c}) = {f_ac} but f({c}, {a}) = {f_ca}"
                    );
                }
            }
        }
    }

    /// The sample weights and `eval / pdf` agree, and the density integrates to at most
    /// one (directions below the horizon are discarded), checked against quadrature.
    #[test]
    fn sampling_agrees_with_eval_and_pdf() {
        let bsdfs = [
            physical(BsdfKind::Diffuse { reflectance: Color::splat(0.6) }, false),
            physical(rough(Kind::Beckmann, 0.3), false),
            physical(rough(Kind::Ggx, 0.3), false),
            phong(0.3, 0.6, 20.0, 0.0, 0.0),
        ];
        for (i, (b, wo)) in
            bsdfs.iter().flat_map(|b| [(b, Vec3::new(0.4, -0.2, 0.7).normalize()), (b, Vec3::Z)]).enumerate()
        {
            for (u1, u2) in points(500) {
                if let Some(s) = b.sample(wo, u1, u2) {
                    let want = b.eval(wo, s.wi) / b.pdf(wo, s.wi);
                    assert!((s.weight - want).abs().max_element() < 1e-4 * want.max_element().max(1.0), "bsdf {i}");
                    assert!((s.pdf - b.pdf(wo, s.wi)).abs() <= 1e-4 * s.pdf);
                }
            }
            let q = 500;
            let (mut int_pdf, mut int_f) = (0.0f64, 0.0f64);
            for x in 0..q {
                for y in 0..q {
                    let wi = uniform_sphere(((x as f32 + 0.5) / q as f32, (y as f32 + 0.5) / q as f32));
                    int_pdf += b.pdf(wo, wi) as f64;
                    int_f += b.eval(wo, wi).x as f64;
                }
            }
            let w = 4.0 * std::f64::consts::PI / (q * q) as f64;
            assert!(int_pdf * w <= 1.01 && int_pdf * w > 0.7, "bsdf {i}: ∫ pdf = {}", int_pdf * w);
            // The albedo by sampling equals the albedo by quadrature of eval.
            let sampled = albedo(b, wo, 40_000);
            assert!((sampled - int_f * w).abs() < 0.01, "bsdf {i}: sampled albedo {sampled} vs ∫ f cos {}", int_f * w);
        }
    }
}
