//! Plasticity as in Müller et al. 2004, §4.3 (after O'Brien et al. 2002): the elastic
//! strain is the total strain minus a stored plastic strain; where the elastic strain's
//! norm exceeds the yield, a part of it (the creep rate times the step) moves into the
//! plastic strain, whose norm is then capped. The body so keeps part of a deformation.

use crate::material::Material;
use glam::DMat3;

/// The plastic strain after one step of `dt` seconds, from the total strain `strain`.
pub fn update(plastic: DMat3, strain: DMat3, dt: f64, mat: &Material) -> DMat3 {
    if !mat.is_plastic() {
        return plastic;
    }
    let elastic = strain - plastic;
    let mut p = plastic;
    if norm(elastic) > mat.plastic_yield {
        p += elastic * (dt * mat.plastic_creep).min(1.0);
    }
    let n = norm(p);
    if n > mat.plastic_max {
        p *= mat.plastic_max / n;
    }
    p
}

/// Frobenius norm.
pub fn norm(m: DMat3) -> f64 {
    crate::elastic::ddot(m, m).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_scene::ElasticParams;

    #[test]
    fn yields_creeps_and_caps() {
        let p = ElasticParams { plastic_yield: 0.1, plastic_creep: 10.0, plastic_max: 0.2, ..Default::default() };
        let mat = Material::new(&p);
        let small = DMat3::from_diagonal(glam::DVec3::new(0.05, 0.0, 0.0));
        assert_eq!(update(DMat3::ZERO, small, 0.01, &mat), DMat3::ZERO, "below yield nothing flows");
        let big = DMat3::from_diagonal(glam::DVec3::new(0.5, 0.0, 0.0));
        let once = update(DMat3::ZERO, big, 0.01, &mat);
        assert!((once.x_axis.x - 0.05).abs() < 1e-7, "10 /s × 0.01 s of 0.5");
        let mut q = DMat3::ZERO;
        for _ in 0..1000 {
            q = update(q, big, 0.01, &mat);
        }
        assert!((norm(q) - mat.plastic_max).abs() < 1e-12, "capped at max_plastic");
        let elastic = Material::new(&ElasticParams::default());
        assert_eq!(update(DMat3::ZERO, big, 0.01, &elastic), DMat3::ZERO);
    }
}
