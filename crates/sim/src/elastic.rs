//! Elastic forces from the strain energy (Müller et al. 2004, §4): with the MLS gradient
//! `∇u` of phyxel `i` and `F = I + ∇u`,
//!
//! - Green–Saint-Venant strain `ε = ½ (Fᵀ F − I) = ½ (∇u + ∇uᵀ + ∇uᵀ∇u)`, minus the
//!   plastic strain where there is one (`plastic.rs`);
//! - Hookean stress of an isotropic material `σ = λ tr(ε) I + 2μ ε`;
//! - strain energy `U_i = v_i ½ ε : σ` plus the volume term `v_i ½ k_v (det F − 1)²`,
//!   which penalises the volume changes the linear MLS gradient cannot see;
//! - forces `f_j = −∂U_i/∂u_j = −v_i (F σ + k_v (det F − 1) cof F) d_ij` on each neighbour
//!   and `f_i = −Σ_j f_j` on `i` itself (since `d_ii = −Σ_j d_ij`), so the internal forces
//!   of every phyxel sum to zero and momentum is conserved.
//!
//! The paper writes the strain without the ½ (and so its forces with a factor 2); the
//! standard ½ is used here, so that `young` is the Young's modulus the body shows
//! (tests/physics.rs checks a resting cube's compression against it).

use crate::material::Material;
use glam::{DMat3, DVec3};

/// What one phyxel contributes to the forces: the matrix `M_i` with `f_j = −M_i d_ij`,
/// and its strain energy.
#[derive(Clone, Copy, Debug)]
pub struct PhyxelStress {
    /// `M_i = v_i (F σ + k_v (det F − 1) cof F)`.
    pub m: DMat3,
    /// `U_i`, J.
    pub energy: f64,
    /// The total strain `ε` (before removing plastic strain), for plasticity.
    pub strain: DMat3,
}

/// `M_i`, `U_i` and `ε` of a phyxel of volume `vol` with gradient `grad` and plastic
/// strain `plastic`.
pub fn phyxel_stress(grad: DMat3, plastic: DMat3, vol: f64, mat: &Material) -> PhyxelStress {
    let f = DMat3::IDENTITY + grad;
    let strain = (f.transpose() * f - DMat3::IDENTITY) * 0.5;
    let e = strain - plastic;
    let tr = e.x_axis.x + e.y_axis.y + e.z_axis.z;
    let sigma = DMat3::from_diagonal(DVec3::splat(mat.lambda * tr)) + e * (2.0 * mat.mu);
    let det = f.determinant();
    let cof = DMat3::from_cols(f.y_axis.cross(f.z_axis), f.z_axis.cross(f.x_axis), f.x_axis.cross(f.y_axis));
    let m = (f * sigma + cof * (mat.volume * (det - 1.0))) * vol;
    let energy = vol * (0.5 * ddot(e, sigma) + 0.5 * mat.volume * (det - 1.0) * (det - 1.0));
    PhyxelStress { m, energy, strain }
}

/// `a : b = Σ a_kl b_kl`.
pub fn ddot(a: DMat3, b: DMat3) -> f64 {
    a.x_axis.dot(b.x_axis) + a.y_axis.dot(b.y_axis) + a.z_axis.dot(b.z_axis)
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_scene::ElasticParams;

    #[test]
    fn rotations_store_no_energy() {
        let mat = Material::new(&ElasticParams::default());
        let r = DMat3::from_rotation_y(0.7) * DMat3::from_rotation_x(-0.3);
        let s = phyxel_stress(r - DMat3::IDENTITY, DMat3::ZERO, 1e-3, &mat);
        assert!(s.energy.abs() < 1e-9 * mat.young * 1e-3, "energy {}", s.energy);
        assert!(s.m.abs_diff_eq(DMat3::ZERO, 1e-6 * mat.young), "{}", s.m);
    }

    #[test]
    fn forces_are_the_energy_gradient() {
        // M_i : δF = δU for a small δF (the derivation of f_j = −M_i d_ij).
        let mat = Material::new(&ElasticParams::default());
        let g = DMat3::from_cols_array(&[0.05, 0.02, -0.03, 0.01, -0.04, 0.02, 0.0, 0.03, 0.06]);
        let d = DMat3::from_cols_array(&[0.3, -0.1, 0.2, 0.5, 0.1, -0.4, 0.2, 0.3, 0.1]) * 1e-6;
        let s = phyxel_stress(g, DMat3::ZERO, 1.0, &mat);
        let up = phyxel_stress(g + d, DMat3::ZERO, 1.0, &mat).energy;
        let down = phyxel_stress(g - d, DMat3::ZERO, 1.0, &mat).energy;
        let want = (up - down) / 2.0;
        let got = ddot(s.m, d);
        assert!((got - want).abs() < 1e-6 * want.abs(), "{got} vs {want}");
    }
}
