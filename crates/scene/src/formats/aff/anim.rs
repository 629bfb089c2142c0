//! BART's animation: keyframe blocks (`k name { transl … rot … scale … }`), the animated
//! transforms (`x name { … }`) they drive, the animated camera (`k camera`), and the
//! animation range (`a start end frames`).
//!
//! Each key is `time x y z tension continuity bias` (`rot`: `time ax ay az angle° t c b`).
//! Every track becomes a [`BartTrack`], evaluated as BART's reference code evaluates it
//! (`crate::animation::BartTrack` has the rules): a Kochanek–Bartels spline from the
//! second key to the second-to-last — the first and the last only give the end
//! tangents, and the value holds outside — and for rotations the same spline on
//! quaternions, evaluated by squad. So a track needs at least 4 keys, as BART's
//! `parse.c` demands; fewer is an error naming the line of the `transl`, `rot` or `scale`
//! word. Angles of a whole turn or more are kept (`rot` 0° → 360° → 720° spins twice).
//!
//! Keys are kept as written, as the reference keeps them: keys at the time of the
//! previous one (the robots repeat their first and last keys, the kitchen's wheels some
//! inner ones) are neighbours for the tangents, and keys earlier than a key before them
//! (one robot track runs 42…48 twice) are kept with a warning, since such a track is
//! probably a mistake even though the reference evaluates it.
//!
//! Keys may lie beyond the `a` range (the outer keys only shape the ends, and some robot
//! tracks run past the end). A track whose moving part, key 1 to key n−2, lies wholly
//! before the start or after the end is an error naming the nearest such key ("a key
//! outside the animation range"): no frame could show its motion.

use super::lexer::Tokens;
use crate::animation::{
    AxisAngle, BartKey, BartTrack, Channel, ChannelTarget, ChannelTrack, Clip, Node, NodePose, Rig, TrackError,
    BART_MIN_KEYS,
};
use crate::{LoadError, Warning};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// One key as written.
#[derive(Clone, Copy, Debug)]
struct RawKey {
    time: f32,
    value: [f32; 4],
    tcb: [f32; 3],
    line: usize,
}

/// A `k` block.
#[derive(Debug)]
struct KeyBlock {
    path: PathBuf,
    line: usize,
    translation: Option<Vec<RawKey>>,
    rotation: Option<Vec<RawKey>>,
    scale: Option<Vec<RawKey>>,
}

/// The `a` line.
#[derive(Clone, Debug)]
pub(super) struct Range {
    pub start: f32,
    pub end: f32,
    pub frames: u32,
    pub path: PathBuf,
    pub line: usize,
}

/// An `x` transform: its node and where it was opened.
#[derive(Debug)]
struct Animated {
    node: u32,
    name: String,
    path: PathBuf,
    line: usize,
}

/// Keyframe blocks and animated transforms met while parsing.
#[derive(Default)]
pub(super) struct Keyframes {
    blocks: HashMap<String, KeyBlock>,
    animated: Vec<Animated>,
}

impl Keyframes {
    /// Records that node `node` is the animated transform `x name` at `line` of `path`.
    pub fn animated(&mut self, node: u32, name: &str, path: &Path, line: usize) {
        self.animated.push(Animated { node, name: name.to_string(), path: path.to_path_buf(), line });
    }

    /// Reads a `k name { … }` block (after the `k`).
    pub fn read_k(&mut self, t: &mut Tokens<'_>) -> Result<(), LoadError> {
        let name = t.word("the name of the keyframes after `k`")?;
        t.expect("{", &format!("after `k {}`", name.text))?;
        let mut block =
            KeyBlock { path: t.path.to_path_buf(), line: name.line, translation: None, rotation: None, scale: None };
        loop {
            let w = t.word(&format!("`transl`, `rot`, `scale` or `}}` in `k {}`", name.text))?;
            let (slot, width) = match w.text {
                "}" => break,
                "transl" => (&mut block.translation, 3),
                "rot" => (&mut block.rotation, 4),
                "scale" => (&mut block.scale, 3),
                other => {
                    return Err(t.error(
                        w.line,
                        format!("in `k {}`: expected `transl`, `rot`, `scale` or `}}`, found `{other}`", name.text),
                    ))
                }
            };
            if slot.is_some() {
                return Err(t.error(w.line, format!("`k {}`: `{}` given twice", name.text, w.text)));
            }
            let n = t.count(&format!("`{}` key count", w.text))?;
            if n < BART_MIN_KEYS {
                return Err(t.error(
                    w.line,
                    format!(
                        "`{}` in `k {}` has {n} key{}: BART tracks need at least {BART_MIN_KEYS} \
                         (the first and the last only give the end tangents; BART's parse.c refuses fewer)",
                        w.text,
                        name.text,
                        if n == 1 { "" } else { "s" }
                    ),
                ));
            }
            let mut keys = Vec::with_capacity(super::lexer::reserve(t, n, 4 + width));
            for k in 0..n {
                let what = format!("`{}` key {} of {n} in `k {}`", w.text, k + 1, name.text);
                let line = t.line();
                let time = t.number(&format!("{what}: time"))?;
                let mut value = [0.0; 4];
                for v in &mut value[..width] {
                    *v = t.number(&what)?;
                }
                let tcb = [t.number(&what)?, t.number(&what)?, t.number(&what)?];
                keys.push(RawKey { time, value, tcb, line });
            }
            *slot = Some(keys);
        }
        if let Some(b) = self.blocks.get(name.text) {
            // A file included twice (BART's car includes each wheel file twice) defines
            // its keyframes twice from the same place: the same block, kept once.
            if b.path == block.path && b.line == block.line {
                return Ok(());
            }
            return Err(t.error(
                name.line,
                format!("keyframes `{}` defined twice (first at {}:{})", name.text, b.path.display(), b.line),
            ));
        }
        self.blocks.insert(name.text.to_string(), block);
        Ok(())
    }

    /// Adds the clip driving every animated transform to `rig`, and the camera's node when
    /// there is a `k camera` block (returned).
    pub fn build(
        mut self,
        rig: &mut Rig,
        range: Option<&Range>,
        warnings: &mut Vec<Warning>,
    ) -> Result<Option<u32>, LoadError> {
        let mut clip = Clip { name: Some("BART".into()), channels: Vec::new() };
        let mut used: Vec<String> = Vec::new();
        for a in &self.animated {
            let Some(block) = self.blocks.get(&a.name) else {
                warnings.push(Warning::new(
                    &a.path,
                    Some(a.line),
                    format!("transform `x {}` has no keyframes (`k {}`); it stays at the identity", a.name, a.name),
                ));
                continue;
            };
            used.push(a.name.clone());
            channels(block, a.node, range, warnings, &mut clip.channels)?;
        }
        let camera = match self.blocks.remove("camera") {
            Some(block) => {
                let node = rig.nodes.len() as u32;
                rig.nodes.push(Node {
                    name: Some("camera".into()),
                    parent: None,
                    rest: NodePose::IDENTITY,
                    rest_weights: Vec::new(),
                });
                channels(&block, node, range, warnings, &mut clip.channels)?;
                Some(node)
            }
            None => None,
        };
        let mut unused: Vec<(&String, &KeyBlock)> = self.blocks.iter().filter(|(n, _)| !used.contains(n)).collect();
        unused.sort_by_key(|(_, b)| (b.path.clone(), b.line));
        for (name, b) in unused {
            warnings.push(Warning::new(
                &b.path,
                Some(b.line),
                format!("keyframes `k {name}` animate nothing (no `x {name}` transform); ignored"),
            ));
        }
        if !clip.channels.is_empty() {
            rig.clips.push(clip);
            rig.active_clip = 0;
        }
        Ok(camera)
    }
}

/// The channels of `block` on `node`.
fn channels(
    block: &KeyBlock,
    node: u32,
    range: Option<&Range>,
    warnings: &mut Vec<Warning>,
    out: &mut Vec<Channel>,
) -> Result<(), LoadError> {
    let parts = [
        (&block.translation, ChannelTarget::Translation, "transl"),
        (&block.rotation, ChannelTarget::Rotation, "rot"),
        (&block.scale, ChannelTarget::Scale, "scale"),
    ];
    for (keys, target, what) in parts {
        let Some(keys) = keys else { continue };
        let track = track(block, keys, target, what, range, warnings)?;
        out.push(Channel { node, target, track: ChannelTrack::Bart(track) });
    }
    Ok(())
}

/// One track from its keys (module docs: order, range, rotations).
fn track(
    block: &KeyBlock,
    keys: &[RawKey],
    target: ChannelTarget,
    what: &str,
    range: Option<&Range>,
    warnings: &mut Vec<Warning>,
) -> Result<BartTrack, LoadError> {
    let err = |line: usize, m: String| LoadError::parse(&block.path, Some(line), m);
    if keys.len() < BART_MIN_KEYS {
        // `read_k` refuses these; kept so that this function stands on its own.
        let line = keys.first().map_or(block.line, |k| k.line);
        return Err(err(line, format!("`{what}`: {}", TrackError::TooFewBartKeys { keys: keys.len() })));
    }
    if let Some(w) = keys.windows(2).find(|w| w[1].time < w[0].time) {
        warnings.push(Warning::new(
            &block.path,
            Some(w[1].line),
            format!(
                "`{what}`: key at time {} comes after a key at time {}; kept, as BART's reference code keeps it \
                 (each time is evaluated on the first segment ending after it)",
                w[1].time, w[0].time
            ),
        ));
    }
    if let Some(r) = range {
        // The track moves from key 1 to key n−2 and holds outside: a moving part wholly
        // outside the range only ever shows one held value, so its keys are a mistake.
        let (first, last) = (keys[1], keys[keys.len() - 2]);
        let outside = if last.time < r.start {
            Some(last)
        } else if first.time > r.end {
            Some(first)
        } else {
            None
        };
        if let Some(k) = outside {
            return Err(err(
                k.line,
                format!(
                    "`{what}` key at time {} is outside the animation range {}..{} (`a` at {}:{}), \
                     and so are all the keys the track moves through (the second to the second-to-last): \
                     no frame shows its motion",
                    k.time,
                    r.start,
                    r.end,
                    r.path.display(),
                    r.line
                ),
            ));
        }
    }
    let made = if target == ChannelTarget::Rotation {
        let keys: Vec<_> = keys
            .iter()
            .map(|k| {
                let [x, y, z, degrees] = k.value;
                bart_key(k, AxisAngle { axis: [x, y, z], degrees })
            })
            .collect();
        BartTrack::rotation(&keys)
    } else {
        let keys: Vec<_> = keys.iter().map(|k| bart_key(k, [k.value[0], k.value[1], k.value[2]])).collect();
        BartTrack::vector(&keys)
    };
    made.map_err(|e| {
        let line = match e {
            TrackError::NonFiniteTime { key } | TrackError::NonFiniteValue { key } | TrackError::ZeroAxis { key } => {
                keys[key].line
            }
            _ => keys[0].line,
        };
        err(line, format!("`{what}`: {e}"))
    })
}

fn bart_key<V>(k: &RawKey, value: V) -> BartKey<V> {
    BartKey { time: k.time, value, tension: k.tcb[0], continuity: k.tcb[1], bias: k.tcb[2] }
}
