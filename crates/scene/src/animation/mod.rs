//! Animation: what moves in a scene, on which time axis, and how a frame is posed.
//!
//! Every source of motion maps onto the same few pieces, so one evaluation
//! ([`crate::Scene::frame_into`]) serves them all:
//! - a transform hierarchy ([`Rig`]: [`Node`]s, [`Clip`]s of keyframe [`Channel`]s,
//!   [`Skin`]s) — glTF nodes and skins, BART's `x` transforms, the scene language's
//!   keyframed actors, lights and camera;
//! - per actor, the node that places it ([`crate::Actor::node`]) and what deforms its
//!   vertices ([`crate::Actor::deform`], a [`Deformation`]: keyed vertices, morph
//!   targets, skinning);
//! - lights and the camera placed by nodes ([`Animation::light_nodes`],
//!   [`Animation::camera_node`]);
//! - a [`Timeline`]: which times the frames of `dynray animate` and `--frame K` are.
//!
//! A channel's keys ([`ChannelTrack`]) are one of two kinds, each with its own rules:
//! - [`Track`]: dynray's keyframes, for glTF and the scene language (step, linear/slerp,
//!   glTF cubic spline, Kochanek–Bartels through every key);
//! - [`BartTrack`]: BART's (AFF) tracks, evaluated as BART's reference C code does
//!   (Kochanek–Bartels between the second and the second-to-last key, squad on
//!   quaternions for rotations; `bart_track.rs`, `bart_quat.rs`).
//!
//! Triangle count and order never change with time, so structures can refit.

mod bart_quat;
mod bart_track;
mod deform;
mod rig;
mod track;

pub use bart_track::{AxisAngle, BartKey, BartTrack, BART_MIN_KEYS};
pub use deform::{Deformation, Morph, MorphTarget, SkinBinding, VertexKeys};
pub use rig::{Channel, ChannelTarget, ChannelTrack, Clip, Node, NodePose, Rig, RigError, Skin};
pub use track::{Interpolation, Track, TrackError};

/// Which times the frames of an animation are: frame `k` is at `start + k / frame_rate`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timeline {
    /// Time of frame 0, in seconds on the scene's own axis.
    pub start: f32,
    /// Frames in the animation (at least 1).
    pub frames: u32,
    /// Frames per second.
    pub frame_rate: f32,
}

impl Default for Timeline {
    /// One frame at time 0, 24 frames a second (the scene language's defaults).
    fn default() -> Self {
        Timeline { start: 0.0, frames: 1, frame_rate: 24.0 }
    }
}

impl Timeline {
    /// The time of frame `k`.
    pub fn time_of(&self, k: u32) -> f32 {
        // f64 so late frames of long animations land on their exact time.
        (self.start as f64 + k as f64 / self.frame_rate as f64) as f32
    }

    /// The timeline whose `frames` frames run from `start` to `end` inclusive (BART's
    /// `a start end frames`; one frame sits at `start`).
    pub fn spanning(start: f32, end: f32, frames: u32) -> Timeline {
        let frames = frames.max(1);
        let rate = if frames > 1 && end > start { (frames - 1) as f32 / (end - start) } else { 24.0 };
        Timeline { start, frames, frame_rate: rate }
    }

    /// Frames at `frame_rate` covering `start..=end` (a glTF clip's key range).
    pub fn covering(start: f32, end: f32, frame_rate: f32) -> Timeline {
        // `as u32` saturates; the frame at `start` is added without wrapping past u32::MAX
        // (`--fps 5e9` on a 1 s clip asks for more frames than a u32 counts).
        let frames = (((end - start).max(0.0) as f64 * frame_rate as f64 + 1e-4).floor() as u32).saturating_add(1);
        Timeline { start, frames, frame_rate }
    }
}

/// The scene-wide part of animation; actors carry their own node and deformation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Animation {
    /// Nodes, clips, skins.
    pub rig: Rig,
    /// Which times the frames are.
    pub timeline: Timeline,
    /// `(light, node)`: light `light` of [`crate::Scene::lights`] is given in the node's
    /// space and moves with it.
    pub light_nodes: Vec<(usize, u32)>,
    /// The camera is given in this node's space and moves with it.
    pub camera_node: Option<u32>,
}

impl crate::Scene {
    /// Checks the animation against the scene (every node, skin, light and camera index
    /// in range; each deformation's arrays the size of its mesh; the rig's own checks,
    /// [`Rig::validate`]), so that [`crate::Scene::frame_into`] never panics. Loaders call
    /// it and add the file name to the message.
    pub fn validate_animation(&self) -> Result<(), String> {
        let anim = &self.animation;
        anim.rig.validate().map_err(|e| e.to_string())?;
        let nodes = anim.rig.nodes.len();
        let node_ok = |n: u32| (n as usize) < nodes;
        for (i, a) in self.actors.iter().enumerate() {
            let name = a.name.as_deref().map(|n| format!(" ({n})")).unwrap_or_default();
            if let Some(n) = a.node.filter(|&n| !node_ok(n)) {
                return Err(format!("actor {i}{name}: node {n} does not exist ({nodes} nodes)"));
            }
            if let Some(d) = &a.deform {
                d.validate(a.mesh.vertex_count(), &anim.rig).map_err(|m| format!("actor {i}{name}: {m}"))?;
            }
        }
        for &(light, node) in &anim.light_nodes {
            if light >= self.lights.len() || !node_ok(node) {
                return Err(format!("light {light} on node {node}: no such light or node"));
            }
        }
        if let Some(n) = anim.camera_node.filter(|&n| !node_ok(n)) {
            return Err(format!("camera node {n} does not exist ({nodes} nodes)"));
        }
        if !(anim.timeline.frame_rate > 0.0 && anim.timeline.frame_rate.is_finite())
            || anim.timeline.frames == 0
            || !anim.timeline.start.is_finite()
        {
            return Err(format!("bad timeline: {:?}", anim.timeline));
        }
        Ok(())
    }

    /// Marks [`crate::Motion::Dynamic`] every actor whose node moves under the active
    /// clip or that has a deformation (and leaves the others as they are).
    pub fn mark_moving_actors(&mut self) {
        let moves = self.animation.rig.animated_nodes();
        for a in &mut self.actors {
            let node_moves = a.node.is_some_and(|n| moves.get(n as usize).copied().unwrap_or(false));
            if node_moves || a.deform.is_some() {
                a.motion = crate::Motion::Dynamic;
            }
        }
    }

    /// Whether anything changes with time: a dynamic actor, or a light or camera on a
    /// moving node.
    pub fn is_animated(&self) -> bool {
        let moves = self.animation.rig.animated_nodes();
        let on_moving = |n: u32| moves.get(n as usize).copied().unwrap_or(false);
        self.actors.iter().any(|a| a.motion == crate::Motion::Dynamic)
            || self.animation.light_nodes.iter().any(|&(_, n)| on_moving(n))
            || self.animation.camera_node.is_some_and(on_moving)
    }

    /// Chooses the clip played by name (`--clip NAME`) and makes the timeline cover its
    /// keys at the timeline's frame rate; the error lists the names there are. Actors the
    /// new clip moves are marked dynamic.
    pub fn select_clip(&mut self, name: &str) -> Result<(), String> {
        let clips = &self.animation.rig.clips;
        match clips.iter().position(|c| c.name.as_deref() == Some(name)) {
            Some(i) => {
                self.animation.rig.active_clip = i;
                // A clip's frames cover its keys (glTF's clips each have their own).
                if let Some((start, end)) = self.animation.rig.clips[i].range() {
                    self.animation.timeline = Timeline::covering(start, end, self.animation.timeline.frame_rate);
                }
                self.mark_moving_actors();
                Ok(())
            }
            None => {
                let names: Vec<String> = clips
                    .iter()
                    .enumerate()
                    .map(|(i, c)| c.name.clone().unwrap_or_else(|| format!("#{i} (unnamed)")))
                    .collect();
                if names.is_empty() {
                    Err(format!("no clip named `{name}`: the file has no animation clips"))
                } else {
                    Err(format!("no clip named `{name}` (clips: {})", names.join(", ")))
                }
            }
        }
    }
}
