//! The material of a body (the seed's "material": elasticity and density): Young's
//! modulus and Poisson's ratio as Lamé parameters, the volume stiffness, damping and the
//! plasticity constants, in SI units.

use dynray_scene::ElasticParams;

/// A body's material in the form the force computation uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Young's modulus `E`, Pa.
    pub young: f64,
    /// Poisson's ratio `ν`.
    pub poisson: f64,
    /// Lamé's first parameter `λ = E ν / ((1 + ν)(1 − 2ν))`, Pa.
    pub lambda: f64,
    /// Shear modulus `μ = E / (2 (1 + ν))`, Pa.
    pub mu: f64,
    /// Density `ρ`, kg/m³.
    pub density: f64,
    /// Volume-conservation stiffness `k_v`, Pa.
    pub volume: f64,
    /// Fraction of critical damping of a phyxel pair.
    pub damping: f64,
    /// Plastic yield `c_yield` (strain norm).
    pub plastic_yield: f64,
    /// Creep rate `c_creep`, 1/s.
    pub plastic_creep: f64,
    /// Largest plastic strain norm `c_max`.
    pub plastic_max: f64,
}

impl Material {
    /// From the scene's `elastic` block; `k_v` defaults to `E`.
    pub fn new(p: &ElasticParams) -> Self {
        let (e, nu) = (p.young as f64, p.poisson as f64);
        Self {
            young: e,
            poisson: nu,
            lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            mu: e / (2.0 * (1.0 + nu)),
            density: p.density as f64,
            volume: p.volume.map_or(e, f64::from),
            damping: p.damping as f64,
            plastic_yield: p.plastic_yield as f64,
            plastic_creep: p.plastic_creep as f64,
            plastic_max: p.plastic_max as f64,
        }
    }

    /// Whether strain can become plastic (a positive creep rate).
    pub fn is_plastic(&self) -> bool {
        self.plastic_creep > 0.0
    }

    /// Speed of pressure waves `√((λ + 2μ + k_v) / ρ)`, m/s: what bounds the time step.
    /// (For small strains the volume term adds `k_v` to `λ`, see [`Material::effective_young`].)
    pub fn wave_speed(&self) -> f64 {
        ((self.lambda + 2.0 * self.mu + self.volume) / self.density).sqrt()
    }

    /// Young's modulus the body shows under small uniaxial stress: the volume term's
    /// energy `½ k_v (det F − 1)²` is `½ k_v (tr ε)²` to first order, i.e. `λ + k_v` in
    /// place of `λ`, so `E' = μ (3λ' + 2μ) / (λ' + μ)`.
    pub fn effective_young(&self) -> f64 {
        let l = self.lambda + self.volume;
        self.mu * (3.0 * l + 2.0 * self.mu) / (l + self.mu)
    }
}
