//! Fresnel reflectance for unpolarised light: dielectric interfaces (with the refracted
//! cosine, as Mitsuba 3's `fresnel`) and conductors with a complex index of refraction.

use dynray_scene::Color;

/// Reflectance of a dielectric interface of relative index `eta` (inside over outside)
/// for a direction whose cosine to the normal is `cos_i` (negative: arriving from
/// inside). Returns `(R, cos_t, eta_it, eta_ti)`: reflectance, the cosine of the
/// refracted direction (opposite sign to `cos_i`; 0 under total internal reflection,
/// where `R = 1`), and the index ratios across the interface in the direction of travel
/// and back. Index-matched interfaces reflect nothing.
pub(crate) fn dielectric(cos_i: f32, eta: f32) -> (f32, f32, f32, f32) {
    let outside = cos_i >= 0.0;
    let (eta_it, eta_ti) = if outside { (eta, 1.0 / eta) } else { (1.0 / eta, eta) };
    let cos_t_sqr = 1.0 - eta_ti * eta_ti * (1.0 - cos_i * cos_i);
    let ci = cos_i.abs();
    let ct = cos_t_sqr.max(0.0).sqrt();
    let r = if eta == 1.0 {
        0.0
    } else if ci == 0.0 {
        1.0
    } else {
        let a_s = (eta_it * ct - ci) / (eta_it * ct + ci);
        let a_p = (eta_it * ci - ct) / (eta_it * ci + ct);
        0.5 * (a_s * a_s + a_p * a_p)
    };
    let cos_t = if outside { -ct } else { ct };
    (r.clamp(0.0, 1.0), cos_t, eta_it, eta_ti)
}

/// Reflectance of a conductor of complex index `eta + i k` (relative to the outside) at
/// incidence cosine `cos_i` (≥ 0), per channel: the exact unpolarised formula (as in
/// pbrt-v3's `FrConductor` and Mitsuba's `fresnel_conductor`). `eta = 0, k = 1` reflects
/// everything at every angle (Mitsuba's `material="none"`).
pub(crate) fn conductor(cos_i: f32, eta: Color, k: Color) -> Color {
    let c = cos_i.clamp(0.0, 1.0);
    let f = |eta: f32, k: f32| -> f32 {
        let cos2 = c * c;
        let sin2 = 1.0 - cos2;
        let (eta2, k2) = (eta * eta, k * k);
        let t0 = eta2 - k2 - sin2;
        let a2pb2 = (t0 * t0 + 4.0 * eta2 * k2).max(0.0).sqrt();
        let a = (0.5 * (a2pb2 + t0)).max(0.0).sqrt();
        let t1 = a2pb2 + cos2;
        let t2 = 2.0 * c * a;
        let rs = (t1 - t2) / (t1 + t2);
        let t3 = cos2 * a2pb2 + sin2 * sin2;
        let t4 = t2 * sin2;
        let rp = rs * (t3 - t4) / (t3 + t4);
        let r = 0.5 * (rp + rs);
        if r.is_finite() {
            r.clamp(0.0, 1.0)
        } else {
            1.0
        }
    };
    Color::new(f(eta.x, k.x), f(eta.y, k.y), f(eta.z, k.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_known_values() {
        // Normal incidence on glass: ((1.5 - 1) / (1.5 + 1))^2 = 0.04, from either side.
        let (r, ct, eit, eti) = dielectric(1.0, 1.5);
        assert!((r - 0.04).abs() < 1e-6 && (ct + 1.0).abs() < 1e-6 && eit == 1.5 && (eti - 1.0 / 1.5).abs() < 1e-7);
        assert!((dielectric(-1.0, 1.5).0 - 0.04).abs() < 1e-6);
        // Past the critical angle (41.8° inside glass) everything reflects.
        let c = (60f32).to_radians().cos();
        assert_eq!(dielectric(-c, 1.5).0, 1.0);
        assert_eq!(dielectric(-c, 1.5).1, 0.0);
        assert_eq!(dielectric(0.3, 1.0).0, 0.0);
        // Snell: sin_t = sin_i / eta.
        let ci = 0.6f32;
        let (_, ct, _, _) = dielectric(ci, 1.33);
        let (si, st) = ((1.0 - ci * ci).sqrt(), (1.0 - ct * ct).sqrt());
        assert!((si / st - 1.33).abs() < 1e-5);
    }

    #[test]
    fn conductor_limits() {
        assert_eq!(conductor(0.3, Color::ZERO, Color::ONE), Color::ONE);
        // A conductor without absorption is a dielectric.
        let r = conductor(1.0, Color::splat(1.5), Color::ZERO);
        assert!((r.x - 0.04).abs() < 1e-6, "{r}");
        let c = 0.4f32;
        assert!((conductor(c, Color::splat(1.5), Color::ZERO).x - dielectric(c, 1.5).0).abs() < 1e-5);
        // Gold at normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
        let (n, k) = (0.143f32, 3.983f32);
        let want = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
        assert!((conductor(1.0, Color::splat(n), Color::splat(k)).x - want).abs() < 1e-5);
        // Grazing light reflects fully.
        assert!(conductor(0.0, Color::splat(0.2), Color::splat(3.0)).x > 0.999);
    }
}
