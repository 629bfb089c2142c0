//! Physically based descriptions of how a surface scatters light, for the path tracer:
//! Mitsuba 3's `diffuse`, `conductor`, `roughconductor` and `dielectric` BSDFs with their
//! parameters, and whether `twosided` wraps them.
//!
//! A [`crate::Material`] carries one in [`crate::Material::bsdf`] when its file describes
//! the surface physically (Mitsuba XML); without one the path tracer derives a BSDF from
//! the scene language's Phong coefficients (docs/rendering.md, "Path tracer"). The
//! Whitted integrator reads the Phong coefficients only; loaders that set a BSDF also
//! fill those with an approximation so that Whitted renders such scenes sensibly.

use crate::Color;

/// A BSDF and its sidedness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bsdf {
    /// The scattering model.
    pub kind: BsdfKind,
    /// Mitsuba's reflecting BSDFs are one-sided: a surface seen from the side its normal
    /// points away from is black. `twosided` makes both sides reflect alike. Dielectrics
    /// always have two sides (inside and outside) and ignore this.
    pub two_sided: bool,
}

/// The scattering models.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BsdfKind {
    /// Lambertian reflection, `f = reflectance / π` (Mitsuba `diffuse`).
    Diffuse {
        /// Albedo, linear RGB in `[0, 1]`.
        reflectance: Color,
    },
    /// A metal: Fresnel reflection of a complex index of refraction, a perfect mirror
    /// (Mitsuba `conductor`) or a microfacet surface (`roughconductor`).
    Conductor {
        /// Real part of the index of refraction relative to the outside medium, per channel.
        eta: Color,
        /// Imaginary part (absorption coefficient), per channel.
        k: Color,
        /// Factor on the reflected light (Mitsuba `specular_reflectance`), 1 for physical
        /// metals.
        specular_reflectance: Color,
        /// `None` for a smooth conductor.
        roughness: Option<Roughness>,
    },
    /// A smooth interface between two dielectrics: Fresnel reflection and refraction
    /// (Mitsuba `dielectric`). The geometric normal points to the exterior.
    Dielectric {
        /// Index of refraction inside (where the normal points away from).
        int_ior: f32,
        /// Index of refraction outside.
        ext_ior: f32,
        /// Factor on reflected light.
        specular_reflectance: Color,
        /// Factor on transmitted light.
        specular_transmittance: Color,
    },
}

/// A microfacet distribution and its roughness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roughness {
    /// Which normal distribution function.
    pub distribution: Microfacet,
    /// Roughness along the surface's first tangent (Mitsuba `alpha_u`, or `alpha`).
    pub alpha_u: f32,
    /// Roughness along the second tangent (`alpha_v`, or `alpha`).
    pub alpha_v: f32,
}

/// Microfacet normal distributions (Walter et al. 2007).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Microfacet {
    /// Beckmann's distribution (Mitsuba's default for `roughconductor`).
    Beckmann,
    /// Trowbridge–Reitz, known as GGX.
    Ggx,
}

impl Bsdf {
    /// A one-sided Lambertian BSDF.
    pub fn diffuse(reflectance: Color) -> Self {
        Self { kind: BsdfKind::Diffuse { reflectance }, two_sided: false }
    }
}
