//! A keyframe track: one animated quantity (a translation, a rotation, a scale, morph
//! weights, a light's colour…) sampled at any time — the keyframes of glTF and of the
//! scene language. BART's (AFF) tracks follow other rules, those of BART's reference
//! code, and are a kind of their own ([`super::BartTrack`]).
//!
//! Values are stored flat, `width` floats per key, so one type carries every quantity
//! the loaders read. Outside its keys a track holds its first or last value (glTF's
//! rule). Interpolation is per track:
//! - [`Interpolation::Step`]: the value of the last key at or before `t`;
//! - [`Interpolation::Linear`]: componentwise lerp, or for rotations (unit quaternions,
//!   `x y z w`) a slerp along the shorter arc, as glTF asks;
//! - [`Interpolation::CubicSpline`]: glTF's cubic Hermite spline with explicit in/out
//!   tangents per key (scaled by the key interval, glTF spec appendix C);
//! - [`Interpolation::Tcb`]: a Kochanek–Bartels spline (SIGGRAPH 1984) with tension,
//!   continuity and bias per key; all zero is the Catmull–Rom spline. It runs through
//!   every key, the first and last included; end keys use zero-length outer chords (the
//!   curve's tangent there comes from its one neighbour). This is the scene language's
//!   `smooth` (docs/scene-language.md), not BART's rule.
//!
//! Cubic rotations are interpolated componentwise and then normalised (the glTF rule);
//! successive quaternion keys are first put in the same hemisphere so the curve takes
//! the short way round.

use glam::{Quat, Vec4};

/// How a [`Track`] goes from one key to the next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Hold each key until the next.
    Step,
    /// Straight lines (slerp for rotations).
    Linear,
    /// glTF `CUBICSPLINE`: Hermite with the file's tangents.
    CubicSpline,
    /// Kochanek–Bartels (tension, continuity, bias per key; zeros: Catmull–Rom).
    Tcb,
}

/// Why a track cannot be made: the loaders add the file and the place.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TrackError {
    /// No keys at all.
    #[error("an animation track needs at least one key")]
    Empty,
    /// A key time that is NaN or infinite.
    #[error("key {key} has a non-finite time")]
    NonFiniteTime {
        /// 0-based key.
        key: usize,
    },
    /// A key time not after the previous one.
    #[error("key {key} at time {time} is not after the previous key at {previous}")]
    NotIncreasing {
        /// 0-based key.
        key: usize,
        /// Its time.
        time: f32,
        /// The previous key's time.
        previous: f32,
    },
    /// A value that is NaN or infinite.
    #[error("key {key} has a non-finite value")]
    NonFiniteValue {
        /// 0-based key.
        key: usize,
    },
    /// Value (or tangent, or TCB) arrays whose length does not fit the key count.
    #[error("{what}: {got} numbers for {keys} keys of width {width} (expected {expected})")]
    Length {
        /// Which array.
        what: &'static str,
        /// Numbers given.
        got: usize,
        /// Numbers expected.
        expected: usize,
        /// Keys.
        keys: usize,
        /// Numbers per key.
        width: usize,
    },
    /// A rotation key that is not a usable quaternion (zero length).
    #[error("rotation key {key} is not a rotation (zero quaternion)")]
    ZeroRotation {
        /// 0-based key.
        key: usize,
    },
    /// A BART track with fewer than [`super::BART_MIN_KEYS`] keys.
    #[error(
        "{keys} keys: a BART track needs at least 4 (the first and the last only give the end tangents; \
         BART's parse.c refuses fewer)"
    )]
    TooFewBartKeys {
        /// Keys given.
        keys: usize,
    },
    /// A rotation key turning by a non-zero angle about a zero axis.
    #[error("rotation key {key} turns about a zero axis")]
    ZeroAxis {
        /// 0-based key.
        key: usize,
    },
}

/// One animated quantity: key times, `width` values per key, and how to interpolate.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    times: Vec<f32>,
    width: usize,
    values: Vec<f32>,
    interpolation: Interpolation,
    /// [`Interpolation::CubicSpline`] only: per key, the in-tangent then the out-tangent
    /// (`2 × width` numbers per key).
    tangents: Vec<f32>,
    /// [`Interpolation::Tcb`] only: per key tension, continuity, bias.
    tcb: Vec<[f32; 3]>,
    /// Values are unit quaternions `x y z w` (width 4).
    rotation: bool,
}

impl Track {
    /// A track of `width`-wide values (`values.len() == times.len() × width`) with
    /// `Step` or `Linear` interpolation, or `Tcb` with all-zero parameters
    /// (Catmull–Rom). Times must be finite and strictly increasing.
    pub fn new(
        times: Vec<f32>,
        width: usize,
        values: Vec<f32>,
        interpolation: Interpolation,
    ) -> Result<Self, TrackError> {
        let keys = times.len();
        let tcb = if interpolation == Interpolation::Tcb { vec![[0.0; 3]; keys] } else { Vec::new() };
        let track = Track { times, width, values, interpolation, tangents: Vec::new(), tcb, rotation: false };
        if interpolation == Interpolation::CubicSpline {
            // Tangents are required: `cubic_spline` is the constructor for it.
            return Err(TrackError::Length { what: "tangents", got: 0, expected: 2 * width * keys, keys, width });
        }
        track.check()?;
        Ok(track)
    }

    /// A glTF `CUBICSPLINE` track: `triples` holds, per key, in-tangent, value and
    /// out-tangent (`3 × width` numbers per key), the order of glTF's output accessor.
    pub fn cubic_spline(times: Vec<f32>, width: usize, triples: &[f32]) -> Result<Self, TrackError> {
        let keys = times.len();
        if triples.len() != 3 * width * keys {
            return Err(TrackError::Length {
                what: "cubic-spline values",
                got: triples.len(),
                expected: 3 * width * keys,
                keys,
                width,
            });
        }
        let mut values = Vec::with_capacity(width * keys);
        let mut tangents = Vec::with_capacity(2 * width * keys);
        for k in triples.chunks_exact(3 * width) {
            tangents.extend_from_slice(&k[..width]);
            values.extend_from_slice(&k[width..2 * width]);
            tangents.extend_from_slice(&k[2 * width..]);
        }
        let track = Track {
            times,
            width,
            values,
            interpolation: Interpolation::CubicSpline,
            tangents,
            tcb: Vec::new(),
            rotation: false,
        };
        track.check()?;
        Ok(track)
    }

    /// A Kochanek–Bartels track with `tcb[k] = [tension, continuity, bias]` for key `k`.
    pub fn tcb(times: Vec<f32>, width: usize, values: Vec<f32>, tcb: Vec<[f32; 3]>) -> Result<Self, TrackError> {
        let keys = times.len();
        if tcb.len() != keys {
            return Err(TrackError::Length {
                what: "tension/continuity/bias",
                got: 3 * tcb.len(),
                expected: 3 * keys,
                keys,
                width: 3,
            });
        }
        let track = Track {
            times,
            width,
            values,
            interpolation: Interpolation::Tcb,
            tangents: Vec::new(),
            tcb,
            rotation: false,
        };
        track.check()?;
        Ok(track)
    }

    /// The same track read as rotations (width 4, unit quaternions `x y z w`): keys are
    /// normalised, made hemisphere-consistent, and linear interpolation becomes slerp.
    pub fn into_rotation(mut self) -> Result<Self, TrackError> {
        if self.width != 4 {
            return Err(TrackError::Length {
                what: "rotation values",
                got: self.values.len(),
                expected: 4 * self.times.len(),
                keys: self.times.len(),
                width: 4,
            });
        }
        let mut previous: Option<Vec4> = None;
        for (key, q) in self.values.chunks_exact_mut(4).enumerate() {
            let mut v = Vec4::from_slice(q);
            if v.length_squared() == 0.0 {
                return Err(TrackError::ZeroRotation { key });
            }
            v = v.normalize();
            // Cubic and TCB curves run through the components: keep neighbours within
            // 90° in 4-D so the curve takes the short arc (slerp does this itself).
            if self.interpolation != Interpolation::Linear {
                if let Some(p) = previous {
                    if p.dot(v) < 0.0 {
                        v = -v;
                    }
                }
            }
            previous = Some(v);
            v.write_to_slice(q);
        }
        self.rotation = true;
        Ok(self)
    }

    fn check(&self) -> Result<(), TrackError> {
        let (keys, width) = (self.times.len(), self.width);
        if keys == 0 || width == 0 {
            return Err(TrackError::Empty);
        }
        if self.values.len() != keys * width {
            return Err(TrackError::Length {
                what: "values",
                got: self.values.len(),
                expected: keys * width,
                keys,
                width,
            });
        }
        for (key, &time) in self.times.iter().enumerate() {
            if !time.is_finite() {
                return Err(TrackError::NonFiniteTime { key });
            }
            if key > 0 && time <= self.times[key - 1] {
                return Err(TrackError::NotIncreasing { key, time, previous: self.times[key - 1] });
            }
        }
        let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
        if let Some(key) = self.values.chunks_exact(width).position(|v| !finite(v)) {
            return Err(TrackError::NonFiniteValue { key });
        }
        if let Some(key) = self.tangents.chunks_exact(2 * width).position(|v| !finite(v)) {
            return Err(TrackError::NonFiniteValue { key });
        }
        if let Some(key) = self.tcb.iter().position(|v| !finite(v)) {
            return Err(TrackError::NonFiniteValue { key });
        }
        Ok(())
    }

    /// Numbers per key.
    pub fn width(&self) -> usize {
        self.width
    }

    /// The key times.
    pub fn times(&self) -> &[f32] {
        &self.times
    }

    /// The interpolation.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// Time of the first and of the last key.
    pub fn range(&self) -> (f32, f32) {
        (self.times[0], *self.times.last().expect("tracks have keys"))
    }

    fn value(&self, k: usize) -> &[f32] {
        &self.values[k * self.width..(k + 1) * self.width]
    }

    /// Writes the value at time `t` into `out` (`width` numbers).
    pub fn sample_into(&self, t: f32, out: &mut [f32]) {
        let w = self.width;
        let out = &mut out[..w];
        let n = self.times.len();
        // Index of the first key after t; held values outside the keys.
        let next = self.times.partition_point(|&k| k <= t);
        if next == 0 || n == 1 {
            out.copy_from_slice(self.value(0));
            return;
        }
        if next == n {
            out.copy_from_slice(self.value(n - 1));
            return;
        }
        let (k0, k1) = (next - 1, next);
        let (t0, t1) = (self.times[k0], self.times[k1]);
        let dt = t1 - t0;
        let s = ((t - t0) / dt).clamp(0.0, 1.0);
        match self.interpolation {
            Interpolation::Step => out.copy_from_slice(self.value(k0)),
            Interpolation::Linear if self.rotation => {
                let q = quat(self.value(k0)).slerp(quat(self.value(k1)), s);
                out.copy_from_slice(&q.to_array());
            }
            Interpolation::Linear => {
                for ((o, a), b) in out.iter_mut().zip(self.value(k0)).zip(self.value(k1)) {
                    *o = a + (b - a) * s;
                }
            }
            Interpolation::CubicSpline => {
                let out_tangent = &self.tangents[(2 * k0 + 1) * w..(2 * k0 + 2) * w];
                let in_tangent = &self.tangents[2 * k1 * w..(2 * k1 + 1) * w];
                for i in 0..w {
                    let m0 = dt * out_tangent[i];
                    let m1 = dt * in_tangent[i];
                    out[i] = hermite(self.value(k0)[i], m0, self.value(k1)[i], m1, s);
                }
            }
            Interpolation::Tcb => {
                for (i, o) in out.iter_mut().enumerate() {
                    let (m0, m1) = self.tcb_tangents(k0, i);
                    *o = hermite(self.value(k0)[i], m0, self.value(k1)[i], m1, s);
                }
            }
        }
        if self.rotation && self.interpolation != Interpolation::Linear {
            let q = Vec4::from_slice(out).normalize_or_zero();
            q.write_to_slice(out);
        }
    }

    /// Kochanek–Bartels tangents of component `i` on the segment from key `k0` to
    /// `k0 + 1`: the outgoing tangent at `k0` and the incoming one at `k0 + 1`, each
    /// scaled for the uneven key spacing (Kochanek & Bartels §4).
    fn tcb_tangents(&self, k0: usize, i: usize) -> (f32, f32) {
        let n = self.times.len();
        let p = |k: usize| self.value(k)[i];
        let t = |k: usize| self.times[k];
        // Chords into and out of key k (zero past the ends).
        let chord_in = |k: usize| if k == 0 { 0.0 } else { p(k) - p(k - 1) };
        let chord_out = |k: usize| if k + 1 >= n { 0.0 } else { p(k + 1) - p(k) };
        let span_in = |k: usize| if k == 0 { 0.0 } else { t(k) - t(k - 1) };
        let span_out = |k: usize| if k + 1 >= n { 0.0 } else { t(k + 1) - t(k) };
        let end_chord = |k: usize| if k == 0 { chord_out(k) } else { chord_in(k) };
        // Outgoing tangent at key k (source derivative of the segment leaving k).
        let outgoing = |k: usize| {
            let [tension, cont, bias] = self.tcb[k];
            let (a, b) = if k == 0 || k + 1 >= n { (end_chord(k), end_chord(k)) } else { (chord_in(k), chord_out(k)) };
            let d = 0.5 * (1.0 - tension) * ((1.0 + bias) * (1.0 + cont) * a + (1.0 - bias) * (1.0 - cont) * b);
            d * spacing(span_in(k), span_out(k), true)
        };
        let incoming = |k: usize| {
            let [tension, cont, bias] = self.tcb[k];
            let (a, b) = if k == 0 || k + 1 >= n { (end_chord(k), end_chord(k)) } else { (chord_in(k), chord_out(k)) };
            let d = 0.5 * (1.0 - tension) * ((1.0 + bias) * (1.0 - cont) * a + (1.0 - bias) * (1.0 + cont) * b);
            d * spacing(span_in(k), span_out(k), false)
        };
        (outgoing(k0), incoming(k0 + 1))
    }
}

/// Kochanek–Bartels' correction for keys at uneven times: the tangent at a key is scaled
/// by `2·Δout / (Δin + Δout)` when leaving it and `2·Δin / (Δin + Δout)` when arriving,
/// so speed is continuous across it. At an end key (one span zero) no scaling applies.
fn spacing(span_in: f32, span_out: f32, leaving: bool) -> f32 {
    if span_in == 0.0 || span_out == 0.0 {
        return 1.0;
    }
    let own = if leaving { span_out } else { span_in };
    2.0 * own / (span_in + span_out)
}

fn quat(v: &[f32]) -> Quat {
    Quat::from_xyzw(v[0], v[1], v[2], v[3])
}

/// Cubic Hermite basis at `s` in [0, 1] with end values `p0`, `p1` and tangents `m0`,
/// `m1` already in units of the segment.
fn hermite(p0: f32, m0: f32, p1: f32, m1: f32, s: f32) -> f32 {
    let s2 = s * s;
    let s3 = s2 * s;
    (2.0 * s3 - 3.0 * s2 + 1.0) * p0 + (s3 - 2.0 * s2 + s) * m0 + (-2.0 * s3 + 3.0 * s2) * p1 + (s3 - s2) * m1
}
