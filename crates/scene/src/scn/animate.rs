//! Keyframed transforms (a dynray extension of seed 003, docs §5.3): the `animate { … }`
//! block of objects, lights and the camera, and how it becomes nodes and channels of
//! the scene's rig.
//!
//! Parsing keeps key times as written (`key T` seconds or `frame K`): the frame rate can
//! be set by a `settings` statement later in the file, so times are resolved and checked
//! against the timeline only when the scene is built ([`AnimSpec::channels`]). An animated
//! thing gets one TRS node whose channels are the block's keys, between the transforms
//! written before `animate` (a fixed child node) and those written after it (a fixed
//! parent node): `after · animated(t) · before`, the written order of every transform.

use super::diag::{did_you_mean, Diag, FileId};
use super::parser::{Parser, Span, R};
use super::value::Value;
use crate::animation::{Channel, ChannelTarget, ChannelTrack, Interpolation, Node, NodePose, Rig, Track};
use glam::{DMat4, DQuat, DVec3};

/// Largest `settings { frames N }`.
pub const MAX_FRAMES: i64 = 1_000_000;

/// How an `animate` block goes from key to key (`interpolation …`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Interp {
    /// `linear`: straight lines, slerp for rotations (the default).
    Linear,
    /// `smooth`: Catmull–Rom, or Kochanek–Bartels with per-key `tension continuity bias`.
    Smooth,
    /// `step`: hold each key until the next.
    Step,
}

/// When a key is, as written.
#[derive(Clone, Copy, Debug)]
pub(crate) enum KeyTime {
    /// `key T`: seconds.
    Seconds(f64),
    /// `frame K`: `K / frame_rate` seconds.
    Frame(u32),
}

/// One `key … { … }`.
#[derive(Clone, Debug)]
pub(crate) struct Key {
    pub at: KeyTime,
    /// `key T` / `frame K`, for errors.
    pub span: Span,
    pub translate: Option<DVec3>,
    /// The key's rotations composed in written order.
    pub rotate: Option<DQuat>,
    pub scale: Option<DVec3>,
    /// Tension, continuity, bias (`smooth` only).
    pub tcb: [f64; 3],
    /// The first of `tension`/`continuity`/`bias` given, for the error when the block
    /// is not `smooth`.
    pub tcb_span: Option<(String, Span)>,
}

/// A parsed `animate` block.
#[derive(Clone, Debug)]
pub(crate) struct AnimSpec {
    pub interp: Interp,
    pub keys: Vec<Key>,
    pub file: FileId,
    /// The word `animate`.
    pub span: Span,
}

/// The animation's time axis as the file sets it, for checking keys.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Axis {
    pub frames: u32,
    pub frame_rate: f64,
}

impl Axis {
    /// Time of the last frame.
    fn end(&self) -> f64 {
        (self.frames - 1) as f64 / self.frame_rate
    }
}

const KEY_OPS: [&str; 9] =
    ["translate", "rotate", "rotate_x", "rotate_y", "rotate_z", "scale", "tension", "continuity", "bias"];

impl Parser<'_> {
    /// `animate { [interpolation linear|smooth|step] (key T | frame K) { op* } … }`; the
    /// keyword `animate` is at `span` and already consumed.
    pub(crate) fn animate(&mut self, span: Span) -> R<AnimSpec> {
        let mut interp = Interp::Linear;
        let mut keys = Vec::new();
        let block = self.block("animate", &["interpolation", "key", "frame"], &["key", "frame"], |p, key, kspan| {
            match key {
                "interpolation" => interp = p.interpolation()?,
                "key" => {
                    let t = p.real("key time (seconds)")?;
                    let at = kspan.start..p.prev_end();
                    keys.push(p.key_body(KeyTime::Seconds(t), at)?);
                }
                "frame" => {
                    let k = p.int("key frame", 0, MAX_FRAMES - 1)? as u32;
                    let at = kspan.start..p.prev_end();
                    keys.push(p.key_body(KeyTime::Frame(k), at)?);
                }
                other => return Err(p.unhandled(kspan, other, "animate")),
            }
            Ok(())
        })?;
        if keys.is_empty() {
            return Err(self
                .err(block, "`animate` has no keys")
                .label("expected at least one `key T { … }` or `frame K { … }`"));
        }
        if interp != Interp::Smooth {
            if let Some((what, s)) = keys.iter().find_map(|k| k.tcb_span.clone()) {
                return Err(self
                    .err(s, format!("`{what}` applies only to `interpolation smooth`"))
                    .label("Kochanek–Bartels parameters shape a smooth curve")
                    .note("add `interpolation smooth` to the `animate` block, or remove the parameter"));
            }
        }
        Ok(AnimSpec { interp, keys, file: self.file, span })
    }

    /// `linear | smooth | step` after `interpolation`.
    fn interpolation(&mut self) -> R<Interp> {
        const WORDS: [&str; 3] = ["linear", "smooth", "step"];
        let (word, span) = self.name("`linear`, `smooth` or `step` after `interpolation`")?;
        match word.as_str() {
            "linear" => Ok(Interp::Linear),
            "smooth" => Ok(Interp::Smooth),
            "step" => Ok(Interp::Step),
            other => {
                let mut d = self
                    .err(span, format!("unknown interpolation `{other}`"))
                    .label("expected `linear`, `smooth` or `step`");
                if let Some(s) = did_you_mean(other, WORDS) {
                    d = d.note(format!("did you mean `{s}`?"));
                }
                Err(d)
            }
        }
    }

    /// The `{ op* }` of one key.
    fn key_body(&mut self, at: KeyTime, span: Span) -> R<Key> {
        let mut key = Key { at, span, translate: None, rotate: None, scale: None, tcb: [0.0; 3], tcb_span: None };
        let rotations = ["rotate", "rotate_x", "rotate_y", "rotate_z"];
        let block = self.block("key", &KEY_OPS, &rotations, |p, op, ospan| {
            let step = match op {
                "translate" => {
                    key.translate = Some(p.vector64("key translation")?);
                    return Ok(());
                }
                "scale" => {
                    key.scale = Some(p.key_scale()?);
                    return Ok(());
                }
                "tension" | "continuity" | "bias" => {
                    let x =
                        p.real_f32(&format!("key {op}"), "it must lie in [-1, 1]", |x| (-1.0..=1.0).contains(&x))?;
                    let i = ["tension", "continuity", "bias"].iter().position(|w| *w == op).unwrap_or(0);
                    key.tcb[i] = x as f64;
                    key.tcb_span.get_or_insert((op.to_string(), ospan));
                    return Ok(());
                }
                "rotate" => p.key_rotate()?,
                "rotate_x" => DQuat::from_rotation_x(p.real("rotate_x angle (degrees)")?.to_radians()),
                "rotate_y" => DQuat::from_rotation_y(p.real("rotate_y angle (degrees)")?.to_radians()),
                "rotate_z" => DQuat::from_rotation_z(p.real("rotate_z angle (degrees)")?.to_radians()),
                other => return Err(p.unhandled(ospan, other, "key")),
            };
            // Rotations of one key compose in the order written (first applied first).
            key.rotate = Some(step * key.rotate.unwrap_or(DQuat::IDENTITY));
            Ok(())
        })?;
        if key.translate.is_none() && key.rotate.is_none() && key.scale.is_none() {
            return Err(self
                .err(block, "this key sets nothing")
                .label("expected `translate`, `rotate`, `rotate_x`, `rotate_y`, `rotate_z` or `scale`"));
        }
        Ok(key)
    }

    /// `rotate <axis> angle` in a key: about the axis through the animation's origin.
    fn key_rotate(&mut self) -> R<DQuat> {
        let start = self.span().start;
        let axis = self.vector64("rotation axis")?;
        let axis_span = start..self.prev_end();
        if axis == DVec3::ZERO {
            return Err(self
                .err(axis_span, "rotation axis is the zero vector")
                .label("expected a non-zero axis direction"));
        }
        let (angle, span) = self.expr()?;
        match angle {
            Value::Real(deg) if deg.is_finite() => Ok(DQuat::from_axis_angle(axis.normalize(), deg.to_radians())),
            Value::Vector(_) => Err(self
                .err(axis_span.start..span.end, "a key's `rotate` takes an axis and an angle, not a base point")
                .label("expected `rotate <axis> degrees`")
                .note("keys rotate about the origin of the animation's space; put a `transform { translate … }` after `animate` to move the pivot")),
            other => Err(self
                .err(span, format!("rotation angle (degrees) must be a finite real, found {}", describe(&other)))
                .label("expected the angle in degrees")),
        }
    }

    /// `scale <x, y, z>` or `scale s` in a key; no factor may be zero.
    fn key_scale(&mut self) -> R<DVec3> {
        let (v, span) = self.expr()?;
        let f = match v {
            Value::Real(s) => DVec3::splat(s),
            Value::Vector(v) => v,
            Value::Color(_) => {
                return Err(self
                    .err(span, "type mismatch: key scale must be a vector or a real, found a colour")
                    .label("expected `<x, y, z>` or one factor"))
            }
        };
        if !f.is_finite() || f.abs().max_element() > f32::MAX as f64 {
            return Err(self
                .err(span, format!("key scale {f} is too large for single precision"))
                .label("out of range"));
        }
        if f.x == 0.0 || f.y == 0.0 || f.z == 0.0 {
            return Err(self
                .err(span, format!("scale factors {f} contain a zero"))
                .label("expected non-zero factors (a zero flattens the object)"));
        }
        Ok(f)
    }
}

fn describe(v: &Value) -> String {
    match v {
        Value::Real(x) => format!("{x}"),
        other => format!("a {}", other.type_name()),
    }
}

impl AnimSpec {
    /// Key times in seconds (`f32`, as tracks hold them), checked against `axis`: inside
    /// `[0, (frames − 1) / frame_rate]`, strictly increasing.
    fn times(&self, axis: Axis) -> Result<Vec<f32>, Diag> {
        let end = axis.end();
        let mut out: Vec<f32> = Vec::with_capacity(self.keys.len());
        for (i, k) in self.keys.iter().enumerate() {
            let t = match k.at {
                KeyTime::Seconds(t) => t,
                KeyTime::Frame(f) => f as f64 / axis.frame_rate,
            };
            // A key written as the last frame's time in decimals (`1.9583`) still counts.
            let slack = 1e-6 * end.max(1.0);
            if !(t >= -slack && t <= end + slack) {
                return Err(Diag::new(self.file, k.span.clone(), format!("key at {t} s is outside the animation"))
                    .label(format!("expected a time from 0 to {end} s"))
                    .note(format!(
                        "the animation has {} frame(s) at {} frames a second, so it runs from 0 to {end} s; \
                         set its length with `settings {{ frames N frame_rate R }}`",
                        axis.frames, axis.frame_rate
                    )));
            }
            let t32 = t.clamp(0.0, end) as f32;
            if let Some(&prev) = out.last() {
                let first = &self.keys[i - 1].span;
                if t32 == prev {
                    return Err(Diag::new(self.file, k.span.clone(), format!("duplicate key at {t} s"))
                        .label("a second key at this time")
                        .also(self.file, first.clone(), "the first key at this time"));
                }
                if t32 < prev {
                    return Err(Diag::new(
                        self.file,
                        k.span.clone(),
                        format!("key at {t} s comes after a key at {prev} s"),
                    )
                    .label("keys must be in increasing time order")
                    .also(self.file, first.clone(), "the previous key"));
                }
            }
            out.push(t32);
        }
        Ok(out)
    }

    /// The block's channels on node `node`: one per property some key sets, over the keys
    /// that set it.
    fn channels(&self, node: u32, axis: Axis) -> Result<Vec<Channel>, Diag> {
        let times = self.times(axis)?;
        let mut out = Vec::new();
        let fail = |e: crate::animation::TrackError| {
            Diag::new(self.file, self.span.clone(), format!("this animation cannot be used: {e}"))
        };
        for target in [ChannelTarget::Translation, ChannelTarget::Rotation, ChannelTarget::Scale] {
            let mut ts = Vec::new();
            let mut values = Vec::new();
            let mut tcb = Vec::new();
            for (k, &t) in self.keys.iter().zip(&times) {
                let v: Option<Vec<f64>> = match target {
                    ChannelTarget::Translation => k.translate.map(|v| v.to_array().to_vec()),
                    ChannelTarget::Scale => k.scale.map(|v| v.to_array().to_vec()),
                    _ => k.rotate.map(|q| q.to_array().to_vec()),
                };
                if let Some(v) = v {
                    ts.push(t);
                    values.extend(v.iter().map(|&x| x as f32));
                    tcb.push(k.tcb.map(|x| x as f32));
                }
            }
            if ts.is_empty() {
                continue;
            }
            let width = if target == ChannelTarget::Rotation { 4 } else { 3 };
            let track = match self.interp {
                Interp::Linear => Track::new(ts, width, values, Interpolation::Linear),
                Interp::Step => Track::new(ts, width, values, Interpolation::Step),
                Interp::Smooth => Track::tcb(ts, width, values, tcb),
            }
            .map_err(fail)?;
            let track = if target == ChannelTarget::Rotation { track.into_rotation().map_err(fail)? } else { track };
            out.push(Channel { node, target, track: ChannelTrack::Keyframes(track) });
        }
        Ok(out)
    }

    /// Adds the nodes placing something animated by this block to `rig`, its channels to
    /// `channels`: a fixed parent for `after` (unless the identity), the animated node,
    /// and a fixed child for `before` (unless the identity). Returns the animated node
    /// (where things already in `before`'s space hang) and the innermost node.
    pub(crate) fn add_nodes(
        &self,
        rig: &mut Rig,
        channels: &mut Vec<crate::animation::Channel>,
        name: Option<&str>,
        before: DMat4,
        after: DMat4,
        axis: Axis,
    ) -> Result<(u32, u32), Diag> {
        let push = |rig: &mut Rig, parent: Option<u32>, rest: NodePose| {
            rig.nodes.push(Node { name: name.map(str::to_string), parent, rest, rest_weights: Vec::new() });
            rig.nodes.len() as u32 - 1
        };
        let parent = (after != DMat4::IDENTITY).then(|| push(rig, None, NodePose::Matrix(after.as_mat4())));
        let animated = push(rig, parent, NodePose::IDENTITY);
        channels.extend(self.channels(animated, axis)?);
        let leaf = if before != DMat4::IDENTITY {
            push(rig, Some(animated), NodePose::Matrix(before.as_mat4()))
        } else {
            animated
        };
        Ok((animated, leaf))
    }
}
