//! The smoothing kernel of Müller et al. 2004 (their eq. 8, the "poly6" kernel of SPH):
//! `w(r, h) = 315 / (64 π h⁹) (h² − r²)³` for `r < h`, else 0. Smooth, compact, and cheap
//! (no square root: it takes `r²`).

/// `w(r, h)` from `r2 = r²`.
pub fn poly6(r2: f64, h: f64) -> f64 {
    let h2 = h * h;
    if r2 >= h2 {
        return 0.0;
    }
    let d = h2 - r2;
    315.0 / (64.0 * std::f64::consts::PI * h2.powi(4) * h) * d * d * d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_to_one() {
        // ∫ w dV over the ball of radius h is 1 (midpoint rule over shells).
        let h = 0.7;
        let n = 10_000;
        let dr = h / n as f64;
        let total: f64 = (0..n)
            .map(|k| {
                let r = (k as f64 + 0.5) * dr;
                4.0 * std::f64::consts::PI * r * r * poly6(r * r, h) * dr
            })
            .sum();
        assert!((total - 1.0).abs() < 1e-6, "∫w = {total}");
        assert_eq!(poly6(h * h, h), 0.0);
    }
}
