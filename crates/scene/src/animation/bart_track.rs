//! A BART (AFF) keyframe track, evaluated as BART's reference C code evaluates it.
//!
//! BART's frames are defined by its distribution's code — `parse.c` (reading keys),
//! `kbsplpos.c` (positions and scales), `kbsplrot.c` (rotations), `quat.c` (quaternion
//! calculus, here [`super::bart_quat`]) and `animation.c` (the `T·R·S` matrix) — and its
//! rules differ from those of dynray's own keyframes ([`super::Track`], which serve glTF
//! and the scene language with their documented semantics). So BART tracks are a kind of
//! their own ([`super::ChannelTrack::Bart`]); nothing else evaluates by these rules.
//!
//! 1. **End keys give tangents only.** A track has at least 4 keys (`parse.c` refuses
//!    fewer). Its curve runs from key 1 to key n−2 in n−3 segments, each between keys
//!    `i+1` and `i+2` with keys `i` and `i+3` as outer neighbours. Before key 1 the value
//!    is key 1's, after key n−2 key n−2's (`kbsplpos.c`, `ComputeIAndU`). Inside, a time
//!    is evaluated on the first segment that ends after it.
//! 2. **Keys are kept as written.** A segment between two keys at one time is never
//!    evaluated inside (an earlier segment ends after any time that reaches it), but both
//!    keys are neighbours of the segments beside it. Keys whose time goes back (one robot
//!    track runs 42…48 twice) are kept too: the segment search above then moves to the
//!    second run once time passes the first run's end.
//! 3. **Positions and scales** (`kbsplpos.c`): per segment from `P1` to `P2` (neighbours
//!    `P0`, `P3`, times `t0…t3`, tension `T`, continuity `C`, bias `B` per key) the cubic
//!    `P(u) = P1 + u·Tout + u²·(3ΔP − 2Tout − Tin) + u³·(−2ΔP + Tout + Tin)`, `ΔP = P2 − P1`,
//!    `u = (t − t1)/(t2 − t1)`, with
//!    `Tout = ½·a0·(1−T1)·[(1+C1)(1+B1)·(P1 − P0) + (1−C1)(1−B1)·ΔP]`,
//!    `a0 = 2(t2 − t1)/(t2 − t0)`, and
//!    `Tin = ½·a1·(1−T2)·[(1−C2)(1+B2)·ΔP + (1+C2)(1−B2)·(P3 − P2)]`,
//!    `a1 = 2(t2 − t1)/(t3 − t1)`.
//! 4. **Rotations** (`kbsplrot.c`): keys are quaternions `cos(θ/2) + sin(θ/2)·axis`
//!    (axis as written). Walking the segments in order, the segment's end key `q2` is
//!    negated when `q1·q2 < 0` (and the key stored so for the next segments); the outer
//!    keys are used as they are. The same tangents are taken on quaternion logarithms —
//!    `Tout = out0·log(q0⁻¹q1) + out1·log(q1⁻¹q2)`, `Tin = in0·log(q1⁻¹q2) + in1·log(q2⁻¹q3)`
//!    with the weights of rule 3 — and give the inner controls
//!    `a = q1·exp(½(Tout − log(q1⁻¹q2)))`, `b = q2·exp(½(log(q1⁻¹q2) − Tin))`. The value is
//!    `squad(u) = slerp(slerp(q1, q2, u), slerp(a, b, u), 2u(1 − u))`, made a rotation
//!    through angle and axis.
//!
//! Everything is computed in `f64` from the file's `f32` numbers, as the reference does.
//! Where the reference divides by zero in `a0` or `a1` (three keys at one time, or times
//! going back onto an earlier one) its tangent is NaN or infinite; here it is zero, which
//! changes only values the reference would make NaN.

use super::bart_quat::{exp, from_angle_axis, log, product, squad, through_angle_axis};
use super::track::TrackError;
use glam::{DQuat, DVec3};

/// The fewest keys a BART track has (`parse.c`): the first and last only give tangents.
pub const BART_MIN_KEYS: usize = 4;

/// One key of a BART track as the file gives it: a time, a value, and the
/// Kochanek–Bartels parameters shaping the curve at it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BartKey<V> {
    /// Time, on the scene's axis.
    pub time: f32,
    /// `x y z` of a translation or scale, or a rotation ([`AxisAngle`]).
    pub value: V,
    /// Tension (1: tight, −1: slack).
    pub tension: f32,
    /// Continuity (0: smooth; otherwise a corner).
    pub continuity: f32,
    /// Bias (positive: the tangent follows the chord into the key more; negative: the
    /// chord out of it).
    pub bias: f32,
}

/// A rotation key's value: `degrees` about `axis` (as written; not normalised, as in BART).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisAngle {
    /// The axis.
    pub axis: [f32; 3],
    /// The angle, in degrees; whole turns count (720° is two).
    pub degrees: f32,
}

/// A BART track of translations or scales (3 numbers) or rotations (4: a unit quaternion
/// `x y z w`), evaluated by the reference's rules (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct BartTrack {
    /// Per segment, its start and end time (keys `i+1` and `i+2`).
    spans: Vec<Span>,
    curve: Curve,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Span {
    start: f64,
    end: f64,
}

#[derive(Clone, Debug, PartialEq)]
enum Curve {
    /// Per segment the cubic's coefficients `C0…C3` in `u`.
    Vector(Vec<[DVec3; 4]>),
    /// Per segment squad's `p, a, b, q`.
    Rotation(Vec<[DQuat; 4]>),
}

impl BartTrack {
    /// A translation or scale track.
    pub fn vector(keys: &[BartKey<[f32; 3]>]) -> Result<Self, TrackError> {
        check(keys, |v| v.iter().all(|x| x.is_finite()))?;
        let point = |k: usize| DVec3::from_array(keys[k].value.map(f64::from));
        let curve = (0..keys.len() - 3)
            .map(|i| {
                let w = Weights::of(&keys[i..i + 4]);
                let (p0, p1, p2, p3) = (point(i), point(i + 1), point(i + 2), point(i + 3));
                let dp = p2 - p1;
                let t_out = w.out_next * dp + w.out_prev * (p1 - p0);
                let t_in = w.in_next * (p3 - p2) + w.in_prev * dp;
                [p1, t_out, 3.0 * dp - 2.0 * t_out - t_in, -2.0 * dp + t_out + t_in]
            })
            .collect();
        Ok(BartTrack { spans: spans(keys), curve: Curve::Vector(curve) })
    }

    /// A rotation track. A key turning by a non-zero angle about a zero axis is an error
    /// (the reference would silently make it no rotation).
    pub fn rotation(keys: &[BartKey<AxisAngle>]) -> Result<Self, TrackError> {
        check(keys, |r| r.axis.iter().all(|x| x.is_finite()) && r.degrees.is_finite())?;
        if let Some(key) = keys.iter().position(|k| k.value.axis == [0.0; 3] && k.value.degrees != 0.0) {
            return Err(TrackError::ZeroAxis { key });
        }
        let mut q: Vec<DQuat> = keys
            .iter()
            .map(|k| {
                let radians = f64::from(k.value.degrees) * std::f64::consts::PI / 180.0;
                from_angle_axis(radians, DVec3::from_array(k.value.axis.map(f64::from)))
            })
            .collect();
        let mut curve = Vec::with_capacity(keys.len() - 3);
        for i in 0..keys.len() - 3 {
            let (q0, q1, mut q2, q3) = (q[i], q[i + 1], q[i + 2], q[i + 3]);
            // The short way from q1 to q2; the reference stores the key negated (as angle
            // and axis), so later segments see it so.
            if q1.dot(q2) < 0.0 {
                q2 = -q2;
                q[i + 2] = through_angle_axis(q2);
            }
            let w = Weights::of(&keys[i..i + 4]);
            let log_dq = log(product(q1.conjugate(), q2));
            let t_out = log_dq * w.out_next + log(product(q0.conjugate(), q1)) * w.out_prev;
            let t_in = log_dq * w.in_prev + log(product(q2.conjugate(), q3)) * w.in_next;
            let a = product(q1, exp((t_out - log_dq) * 0.5));
            let b = product(q2, exp((log_dq - t_in) * 0.5));
            curve.push([q1, a, b, q2]);
        }
        Ok(BartTrack { spans: spans(keys), curve: Curve::Rotation(curve) })
    }

    /// Numbers a value has: 3, or 4 for rotations.
    pub fn width(&self) -> usize {
        match self.curve {
            Curve::Vector(_) => 3,
            Curve::Rotation(_) => 4,
        }
    }

    /// The times between which the value changes: key 1's and key n−2's.
    pub fn range(&self) -> (f32, f32) {
        let (first, last) = (self.spans[0], self.spans[self.spans.len() - 1]);
        (first.start as f32, last.end as f32)
    }

    /// Writes the value at `t` into `out` ([`BartTrack::width`] numbers; a rotation as a
    /// unit quaternion `x y z w`).
    pub fn sample_into(&self, t: f32, out: &mut [f32]) {
        let (i, u) = self.locate(f64::from(t));
        match &self.curve {
            Curve::Vector(c) => {
                let [c0, c1, c2, c3] = c[i];
                let p = c0 + u * (c1 + u * (c2 + u * c3));
                out[..3].copy_from_slice(&p.as_vec3().to_array());
            }
            Curve::Rotation(s) => {
                let [p, a, b, q] = s[i];
                let r = through_angle_axis(squad(u, p, a, b, q));
                out[..4].copy_from_slice(&r.as_quat().to_array());
            }
        }
    }

    /// The segment and the parameter `u` in it at `t` (`ComputeIAndU`): `u = 0` on the
    /// first segment up to its start, `u = 1` on the last from its end, else the first
    /// segment that ends after `t` (module docs, rules 1 and 2).
    fn locate(&self, t: f64) -> (usize, f64) {
        let last = self.spans.len() - 1;
        // A NaN time lands on key 1, as in the reference (its `tmin < t` is false).
        if t.is_nan() || t <= self.spans[0].start {
            return (0, 0.0);
        }
        if t >= self.spans[last].end {
            return (last, 1.0);
        }
        let i = self.spans.iter().position(|s| t < s.end).unwrap_or(last);
        let s = self.spans[i];
        (i, (t - s.start) / (s.end - s.start))
    }
}

/// Checks the key count and that times and values are finite.
fn check<V: Copy>(keys: &[BartKey<V>], finite: impl Fn(&V) -> bool) -> Result<(), TrackError> {
    if keys.len() < BART_MIN_KEYS {
        return Err(TrackError::TooFewBartKeys { keys: keys.len() });
    }
    for (key, k) in keys.iter().enumerate() {
        if !k.time.is_finite() {
            return Err(TrackError::NonFiniteTime { key });
        }
        if !finite(&k.value) || ![k.tension, k.continuity, k.bias].iter().all(|x| x.is_finite()) {
            return Err(TrackError::NonFiniteValue { key });
        }
    }
    Ok(())
}

fn spans<V>(keys: &[BartKey<V>]) -> Vec<Span> {
    keys[1..keys.len() - 1]
        .windows(2)
        .map(|w| Span { start: f64::from(w[0].time), end: f64::from(w[1].time) })
        .collect()
}

/// The weights of the chords in the tangents of one segment (module docs, rule 3): the
/// outgoing tangent at key 1 weighs the chord into it (`out_prev`) and out of it
/// (`out_next`), the incoming tangent at key 2 the chord into it (`in_prev`) and out of
/// it (`in_next`).
struct Weights {
    out_prev: f64,
    out_next: f64,
    in_prev: f64,
    in_next: f64,
}

impl Weights {
    /// For the segment from `k[1]` to `k[2]`, neighbours `k[0]` and `k[3]`.
    fn of<V>(k: &[BartKey<V>]) -> Weights {
        let t = |i: usize| f64::from(k[i].time);
        let [(t1, c1, b1), (t2, c2, b2)] =
            [1, 2].map(|i| (f64::from(k[i].tension), f64::from(k[i].continuity), f64::from(k[i].bias)));
        let a0 = spacing(t(2) - t(1), t(2) - t(0));
        let a1 = spacing(t(2) - t(1), t(3) - t(1));
        Weights {
            out_prev: 0.5 * a0 * (1.0 - t1) * (1.0 + c1) * (1.0 + b1),
            out_next: 0.5 * a0 * (1.0 - t1) * (1.0 - c1) * (1.0 - b1),
            in_prev: 0.5 * a1 * (1.0 - t2) * (1.0 - c2) * (1.0 + b2),
            in_next: 0.5 * a1 * (1.0 - t2) * (1.0 + c2) * (1.0 - b2),
        }
    }
}

/// Kochanek–Bartels' adjustment for uneven key spacing, `2·span / (span over both
/// neighbouring segments)`; zero where the reference divides by zero (module docs).
fn spacing(span: f64, both: f64) -> f64 {
    let a = 2.0 * span / both;
    if a.is_finite() {
        a
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys(times: &[f32], xs: &[f32]) -> Vec<BartKey<[f32; 3]>> {
        let key = |(&time, &x)| BartKey { time, value: [x, 0.0, 0.0], tension: 0.0, continuity: 0.0, bias: 0.0 };
        times.iter().zip(xs).map(key).collect()
    }

    fn x(track: &BartTrack, t: f32) -> f32 {
        let mut v = [0.0; 3];
        track.sample_into(t, &mut v);
        v[0]
    }

    #[test]
    fn fewer_than_four_keys_are_refused() {
        let e = BartTrack::vector(&keys(&[0.0, 1.0, 2.0], &[0.0; 3])).unwrap_err();
        assert_eq!(e, TrackError::TooFewBartKeys { keys: 3 });
    }

    #[test]
    fn segments_are_found_as_the_reference_finds_them() {
        // Keys 1 and 2 at one time: that segment is never evaluated inside; at t = 1 the
        // value is the second key's (the first segment ending after 1 starts there).
        let t = BartTrack::vector(&keys(&[0.0, 0.0, 1.0, 1.0, 2.0, 3.0], &[9.0, 0.0, 1.0, 2.0, 3.0, 9.0])).unwrap();
        assert_eq!(t.range(), (0.0, 2.0));
        assert_eq!(x(&t, 1.0), 2.0);
        assert_eq!(x(&t, f32::NAN), 0.0);
        assert_eq!(x(&t, -1.0), 0.0);
        assert!((x(&t, 5.0) - 3.0).abs() < 1e-6);
        // Times going back: 0 → 2 (x 0 → 2), then 1 → 3 (x 10 → 30). Before 2 the first
        // run; from 2 on, the first segment ending after t is the second run's, halfway
        // at t = 2.
        let back =
            BartTrack::vector(&keys(&[-1.0, 0.0, 2.0, 1.0, 3.0, 4.0], &[0.0, 0.0, 2.0, 10.0, 30.0, 40.0])).unwrap();
        assert!(x(&back, 1.5) < 3.0, "{}", x(&back, 1.5));
        assert!((10.0..30.0).contains(&x(&back, 2.0)), "{}", x(&back, 2.0));
        assert!(x(&back, 2.5) > x(&back, 2.0), "{}", x(&back, 2.5));
    }

    #[test]
    fn three_keys_at_one_time_give_finite_values() {
        let t = BartTrack::vector(&keys(&[0.0, 1.0, 1.0, 1.0, 2.0, 3.0], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0])).unwrap();
        for time in [0.0, 0.5, 1.0, 1.5, 2.0, 9.0] {
            assert!(x(&t, time).is_finite(), "t = {time}");
        }
    }
}
