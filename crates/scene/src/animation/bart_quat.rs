//! Quaternion calculus as BART's reference code (`quat.c`) does it, for the rotation
//! spline of [`super::BartTrack`]: logarithm, exponential, slerp, squad, and the
//! angle–axis conversions its keys and results go through. All in `f64`, as there.
//!
//! Why not glam's operations: the reference's differ from the textbook ones in ways that
//! move poses, and BART's frames are defined by the reference.
//! - Its slerp does not take the shorter arc by itself: the spline puts neighbouring
//!   keys in one hemisphere (`kbsplrot.c`), and only those. Below a sine of 10⁻³ between
//!   its ends it returns the first one; its log and exp take their limits at the same
//!   cut-off.
//! - A key's quaternion is `cos(θ/2) + sin(θ/2)·axis` with the axis as written, not
//!   normalised (`FromAngleAxis`). BART's robots have axes up to 8 % off unit length.
//! - A result becomes a rotation through angle and axis (`ToAngleAxis`, then
//!   `FromAngleAxis` in `animation.c`): the angle `2·acos(w)` and the direction of the
//!   vector part, so an off-unit quaternion keeps its `w`.

use glam::{DQuat, DVec3};

/// Below this sine of an angle the reference's log, exp and slerp take their limits.
const SINE_CUTOFF: f64 = 1e-3;

/// `cos(θ/2) + sin(θ/2)·axis`, the axis used as given (`FromAngleAxis`).
pub(super) fn from_angle_axis(radians: f64, axis: DVec3) -> DQuat {
    let half = 0.5 * radians;
    let v = half.sin() * axis;
    DQuat::from_xyzw(v.x, v.y, v.z, half.cos())
}

/// Angle and unit axis of `q` (`ToAngleAxis`): `2·acos(w)` and the direction of the
/// vector part; a zero vector part is no rotation about x. `w` is clamped to [−1, 1]
/// (the reference would take the arc cosine of a rounding error beyond it: NaN).
pub(super) fn to_angle_axis(q: DQuat) -> (f64, DVec3) {
    let v = DVec3::new(q.x, q.y, q.z);
    let len2 = v.length_squared();
    if len2 > 0.0 {
        (2.0 * q.w.clamp(-1.0, 1.0).acos(), v / len2.sqrt())
    } else {
        (0.0, DVec3::X)
    }
}

/// `q` taken through angle and axis and back: the unit quaternion of the same angle
/// (its `w` kept) about the same axis. The reference does this to every interpolated
/// rotation, and to a key it negates (it stores keys as angle and axis).
pub(super) fn through_angle_axis(q: DQuat) -> DQuat {
    let (angle, axis) = to_angle_axis(q);
    from_angle_axis(angle, axis)
}

/// The Hamilton product `p·q` (`Mul`), for quaternions of any length (glam's product
/// may assert unit length).
pub(super) fn product(p: DQuat, q: DQuat) -> DQuat {
    DQuat::from_xyzw(
        p.w * q.x + p.x * q.w + p.y * q.z - p.z * q.y,
        p.w * q.y + p.y * q.w + p.z * q.x - p.x * q.z,
        p.w * q.z + p.z * q.w + p.x * q.y - p.y * q.x,
        p.w * q.w - p.x * q.x - p.y * q.y - p.z * q.z,
    )
}

/// `log q` (`Log`): `θ·axis` for `q = cos θ + sin θ·axis`, taking the vector part as it
/// is when `|w| ≥ 1` or `sin θ` is below the cut-off.
pub(super) fn log(q: DQuat) -> DQuat {
    let v = DVec3::new(q.x, q.y, q.z);
    let mut coeff = 1.0;
    if q.w.abs() < 1.0 {
        let angle = q.w.acos();
        let sin = angle.sin();
        if sin.abs() >= SINE_CUTOFF {
            coeff = angle / sin;
        }
    }
    let v = coeff * v;
    DQuat::from_xyzw(v.x, v.y, v.z, 0.0)
}

/// `exp q` of a pure quaternion (`Exp`; `w` is ignored): `cos |v| + sin |v|·v/|v|`, the
/// vector part kept as it is when `sin |v|` is below the cut-off.
pub(super) fn exp(q: DQuat) -> DQuat {
    let v = DVec3::new(q.x, q.y, q.z);
    let angle = v.length();
    let sin = angle.sin();
    let v = if sin.abs() >= SINE_CUTOFF { (sin / angle) * v } else { v };
    DQuat::from_xyzw(v.x, v.y, v.z, angle.cos())
}

/// Spherical interpolation from `p` (`t = 0`) to `q` (`Slerp`): along the arc between
/// them as given (no hemisphere flip), `p` itself when the sine of that arc is below the
/// cut-off.
pub(super) fn slerp(t: f64, p: DQuat, q: DQuat) -> DQuat {
    let cos = p.dot(q).clamp(-1.0, 1.0);
    let angle = cos.acos();
    let sin = angle.sin();
    if sin < SINE_CUTOFF {
        return p;
    }
    let c0 = ((1.0 - t) * angle).sin() / sin;
    let c1 = (t * angle).sin() / sin;
    p * c0 + q * c1
}

/// Shoemake's squad (`Squad`): `slerp(slerp(p, q, t), slerp(a, b, t), 2t(1 − t))`, the
/// segment from `p` to `q` with inner control quaternions `a` and `b`.
pub(super) fn squad(t: f64, p: DQuat, a: DQuat, b: DQuat, q: DQuat) -> DQuat {
    slerp(2.0 * t * (1.0 - t), slerp(t, p, q), slerp(t, a, b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn near(a: DQuat, b: DQuat) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn log_and_exp_invert_each_other() {
        let q = from_angle_axis(1.2, DVec3::new(0.0, 0.6, 0.8));
        let l = log(q);
        assert!((DVec3::new(l.x, l.y, l.z) - 0.6 * DVec3::new(0.0, 0.6, 0.8)).length() < 1e-12);
        assert!(near(exp(l), q));
        // Identity: the limits.
        assert!(near(log(DQuat::IDENTITY), DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0)));
        assert!(near(exp(DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0)), DQuat::IDENTITY));
    }

    #[test]
    fn slerp_follows_the_arc_as_given() {
        let p = DQuat::IDENTITY;
        let q = from_angle_axis(FRAC_PI_2, DVec3::Z);
        assert!(near(slerp(0.5, p, q), from_angle_axis(FRAC_PI_2 / 2.0, DVec3::Z)));
        // −q is the same rotation, but the reference does not flip it: the long way.
        let long = slerp(0.5, p, -q);
        assert!(near(long, from_angle_axis(-(2.0 * PI - FRAC_PI_2) / 2.0, DVec3::Z)), "{long}");
        // Ends closer than the cut-off: the first.
        let r = from_angle_axis(1e-4, DVec3::Z);
        assert_eq!(slerp(0.7, p, r), p);
    }

    #[test]
    fn angle_axis_round_trip_keeps_w_and_normalises() {
        // An axis 10 % long: w is kept, the vector part rescaled to make a unit quaternion.
        let q = from_angle_axis(1.0, DVec3::new(0.0, 1.1, 0.0));
        let r = through_angle_axis(q);
        assert!((r.w - q.w).abs() < 1e-15 && (r.length() - 1.0).abs() < 1e-15, "{r}");
        assert!(near(through_angle_axis(-q), -r));
        assert_eq!(through_angle_axis(DQuat::from_xyzw(0.0, 0.0, 0.0, -1.0)), DQuat::IDENTITY);
    }
}
