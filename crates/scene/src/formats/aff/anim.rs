//! BART's animation: keyframe blocks (`k name { transl … rot … scale … }`), the animated
//! transforms (`x name { … }`) they drive, the animated camera (`k camera`), and the
//! animation range (`a start end frames`).
//!
//! Each key is `time x y z tension continuity bias` (`rot`: `time ax ay az angle° t c b`).
//! Translation and scale become [`Track::tcb`] Kochanek–Bartels tracks, as in BART.
//! Rotation keys are converted from axis–angle to unit quaternions and interpolated by a
//! Kochanek–Bartels spline on the quaternion components (neighbours put in one
//! hemisphere, the result normalised: [`Track::into_rotation`]). BART's reference code
//! runs its Kochanek–Bartels spline on quaternions too, with spherical (squad-like)
//! blending; ours passes through the same key orientations with the same tangent rule
//! and differs only in angular speed between keys, which on BART's densely keyed data is
//! far below a pixel — and it keeps one spline implementation for every quantity.
//! Angles of a whole turn or more are kept (`rot` 0° → 360° → 720° spins twice): keys
//! closer than 180° apart, as BART's are, give quaternions that never flip.
//!
//! Keys at the same time as the previous one (BART's files repeat the first and last
//! keys, and the kitchen's wheels some inner ones) are dropped, and so are keys earlier
//! than a key before them (one robot track runs 42…48 twice), each with one warning per
//! track: BART's data has both, and the rest of such tracks is usable.
//!
//! Keys may lie beyond the `a` range (BART pads tracks by a key at each end to shape
//! the spline's ends, and some robot tracks run past the end). A track of several keys
//! lying wholly before the start or after the end is an error naming its nearest key
//! ("a key outside the animation range"): no frame could show any of it.

use super::lexer::Tokens;
use crate::animation::{Channel, ChannelTarget, Clip, Node, NodePose, Rig, Track};
use crate::{LoadError, Warning};
use glam::{Quat, Vec3};
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
        out.push(Channel { node, target, track });
    }
    Ok(())
}

/// One track from its keys (module docs: duplicates, order, range, rotations).
fn track(
    block: &KeyBlock,
    keys: &[RawKey],
    target: ChannelTarget,
    what: &str,
    range: Option<&Range>,
    warnings: &mut Vec<Warning>,
) -> Result<Track, LoadError> {
    let err = |line: usize, m: String| LoadError::parse(&block.path, Some(line), m);
    if keys.is_empty() {
        return Err(err(block.line, format!("`{what}` has no keys")));
    }
    let mut kept: Vec<RawKey> = Vec::with_capacity(keys.len());
    let (mut repeated, mut backwards) = (None, None);
    for k in keys {
        if let Some(prev) = kept.last() {
            if k.time == prev.time {
                if k.value != prev.value || k.tcb != prev.tcb {
                    repeated = repeated.or(Some(k.line));
                }
                continue;
            }
            if k.time < prev.time {
                backwards = backwards.or(Some((k.line, k.time, prev.time)));
                continue;
            }
        }
        kept.push(*k);
    }
    if let Some(line) = repeated {
        warnings.push(Warning::new(
            &block.path,
            Some(line),
            format!("`{what}`: keys repeating the previous key's time with other values are ignored (the first here)"),
        ));
    }
    if let Some((line, time, prev)) = backwards {
        warnings.push(Warning::new(
            &block.path,
            Some(line),
            format!("`{what}`: key at time {time} comes after a key at time {prev}; keys not after every earlier key are ignored"),
        ));
    }
    if let Some(r) = range {
        // Tracks may run past the range (BART pads them, and authors keys beyond the
        // end); a track of several keys that the range never reaches only ever shows
        // one held value, so its keys are a mistake.
        let (first, last) = (kept[0], *kept.last().expect("a track has keys"));
        let outside = if kept.len() < 2 {
            None
        } else if last.time < r.start {
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
                     and so are all the track's keys: no frame shows them",
                    k.time,
                    r.start,
                    r.end,
                    r.path.display(),
                    r.line
                ),
            ));
        }
    }
    let times: Vec<f32> = kept.iter().map(|k| k.time).collect();
    let tcb: Vec<[f32; 3]> = kept.iter().map(|k| k.tcb).collect();
    let rotation = target == ChannelTarget::Rotation;
    let mut values = Vec::with_capacity(kept.len() * 4);
    for k in &kept {
        if rotation {
            let [x, y, z, deg] = k.value;
            let axis = Vec3::new(x, y, z);
            let q = if axis.length_squared() > 0.0 {
                Quat::from_axis_angle(axis.normalize(), deg.to_radians())
            } else if deg == 0.0 {
                Quat::IDENTITY
            } else {
                return Err(err(k.line, format!("`{what}` key at time {}: the rotation axis is zero", k.time)));
            };
            values.extend_from_slice(&q.to_array());
        } else {
            values.extend_from_slice(&k.value[..3]);
        }
    }
    let width = if rotation { 4 } else { 3 };
    let made = Track::tcb(times, width, values, tcb).and_then(|t| if rotation { t.into_rotation() } else { Ok(t) });
    made.map_err(|e| err(keys[0].line, format!("`{what}`: {e}")))
}
