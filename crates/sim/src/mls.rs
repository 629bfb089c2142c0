//! Moving least squares over a phyxel's neighbours (Müller et al. 2004, §3.2): the
//! displacement gradient `∇u` at phyxel `i` is the best linear fit to its neighbours'
//! displacements, weighted by mass and kernel:
//!
//! `A = Σ_j m_j w_ij x_ij x_ijᵀ`,  `∇u_i = Σ_j (u_j − u_i) d_ijᵀ`,  `d_ij = A⁻¹ (m_j w_ij x_ij)`
//!
//! with `x_ij = x_j − x_i` in the rest state. The `d_ij` depend only on the rest state,
//! so they are computed once; `∇u` is then one sum per step. (`∇u` here has rows
//! `∂u_k/∂x`, so `F = I + ∇u` is the deformation gradient.)

use glam::{DMat3, DVec3};

/// Relative size of the ridge added to `A` before inverting it: it keeps a phyxel whose
/// neighbours are nearly coplanar (an edge of a thin body) from getting huge `d_ij`.
const RIDGE: f64 = 1e-6;

/// `A⁻¹` of phyxel `i` for neighbours `(x_ij, m_j w_ij)`; `None` when singular.
pub fn inverse_moments(neighbours: impl Iterator<Item = (DVec3, f64)>) -> Option<DMat3> {
    let mut a = DMat3::ZERO;
    for (x, mw) in neighbours {
        a += outer(x * mw, x);
    }
    let trace = a.x_axis.x + a.y_axis.y + a.z_axis.z;
    let a = a + DMat3::from_diagonal(DVec3::splat(RIDGE * trace / 3.0));
    let det = a.determinant();
    // Scale-free test: compare with the cube of the mean eigenvalue.
    (trace > 0.0 && det > 1e-4 * (trace / 3.0).powi(3)).then(|| a.inverse())
}

/// `a bᵀ`.
pub fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// `∇u_i = Σ_j (u_j − u_i) d_ijᵀ` for neighbour displacements `u_j` and weights `d_ij`.
pub fn gradient(u_i: DVec3, neighbours: impl Iterator<Item = (DVec3, DVec3)>) -> DMat3 {
    let mut g = DMat3::ZERO;
    for (u_j, d) in neighbours {
        g += outer(u_j - u_i, d);
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_fields_are_reproduced() {
        // Neighbours on a jittered shell; u = G x for a known G: the MLS gradient is G.
        let xs: Vec<DVec3> = (0..20)
            .map(|k| {
                let f = k as f64;
                DVec3::new((f * 1.3).sin(), (f * 2.1).cos(), (f * 0.7).sin() * 0.8) * 0.3
            })
            .collect();
        let g = DMat3::from_cols_array(&[0.1, -0.2, 0.05, 0.3, 0.0, 0.1, -0.1, 0.2, 0.4]);
        let mw: Vec<f64> = xs.iter().map(|x| 1.0 + x.length()).collect();
        let ainv = inverse_moments(xs.iter().zip(&mw).map(|(x, w)| (*x, *w))).unwrap();
        let d: Vec<DVec3> = xs.iter().zip(&mw).map(|(x, w)| ainv * (*x * *w)).collect();
        let u_i = DVec3::new(1.0, 2.0, 3.0);
        let got = gradient(u_i, xs.iter().zip(&d).map(|(x, d)| (u_i + g * *x, *d)));
        assert!((got - g).abs_diff_eq(DMat3::ZERO, 1e-5), "{got} vs {g}");
    }

    #[test]
    fn coplanar_neighbours_are_singular() {
        let xs = [DVec3::X, DVec3::Y, -DVec3::X, DVec3::new(0.5, 0.5, 0.0)];
        assert!(inverse_moments(xs.iter().map(|x| (*x, 1.0))).is_none());
    }
}
