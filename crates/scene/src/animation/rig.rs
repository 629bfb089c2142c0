//! The transform hierarchy of an animated scene: nodes with a rest pose, clips of
//! keyframe channels that override parts of it, and skins (joints are nodes).
//!
//! glTF's nodes, BART's `x` transforms and the scene language's keyframed actors all
//! become [`Node`]s. A node's local matrix at time `t` is its rest pose with the active
//! clip's channels replacing translation, rotation or scale (`T · R · S`, glTF's order
//! and BART's); its world matrix is its parent's world matrix times its local one. Nodes
//! are stored parents first ([`Rig::validate`] checks it), so one pass in order
//! evaluates them.
//!
//! A channel's keys are a [`ChannelTrack`]: dynray's keyframes ([`Track`], for glTF and
//! the scene language) or a BART track ([`BartTrack`], evaluated by BART's reference
//! rules). The kind is chosen by the loader, per the format's semantics.

use super::bart_track::BartTrack;
use super::track::{Track, TrackError};
use glam::{Mat4, Quat, Vec3};

/// A node's pose when no channel moves it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NodePose {
    /// A fixed local matrix. Channels cannot animate a matrix node (glTF forbids it);
    /// [`Rig::validate`] rejects one that tries.
    Matrix(Mat4),
    /// Translation, rotation, scale, composed as `T · R · S`.
    Trs {
        /// Translation.
        translation: Vec3,
        /// Rotation (unit quaternion).
        rotation: Quat,
        /// Scale per axis.
        scale: Vec3,
    },
}

impl NodePose {
    /// The identity pose, as TRS (so channels can animate it).
    pub const IDENTITY: NodePose =
        NodePose::Trs { translation: Vec3::ZERO, rotation: Quat::IDENTITY, scale: Vec3::ONE };
}

/// One node of the hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Name from the file, for messages and `--clip`-style lookups.
    pub name: Option<String>,
    /// The parent node; it must come earlier in [`Rig::nodes`].
    pub parent: Option<u32>,
    /// Pose when no channel of the active clip moves it.
    pub rest: NodePose,
    /// Morph-target weights when no channel sets them (glTF `mesh.weights`/`node.weights`).
    pub rest_weights: Vec<f32>,
}

/// What a [`Channel`] animates on its node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChannelTarget {
    /// Translation (3 numbers a key).
    Translation,
    /// Rotation (a unit quaternion `x y z w`, 4 numbers a key).
    Rotation,
    /// Scale (3 numbers a key).
    Scale,
    /// Morph-target weights (one number per target a key).
    Weights,
}

/// The keys of a [`Channel`], and so which rules evaluate them.
#[derive(Clone, Debug, PartialEq)]
pub enum ChannelTrack {
    /// glTF's and the scene language's keyframes (step, linear/slerp, cubic spline,
    /// Kochanek–Bartels through every key).
    Keyframes(Track),
    /// A BART (AFF) track: Kochanek–Bartels between key 1 and key n−2, squad for
    /// rotations, as BART's reference code evaluates it.
    Bart(BartTrack),
}

impl ChannelTrack {
    /// Numbers a value has.
    pub fn width(&self) -> usize {
        match self {
            ChannelTrack::Keyframes(t) => t.width(),
            ChannelTrack::Bart(t) => t.width(),
        }
    }

    /// The times over which the value changes: the first and last key of keyframes; key
    /// 1 and key n−2 of a BART track (outside them it holds).
    pub fn range(&self) -> (f32, f32) {
        match self {
            ChannelTrack::Keyframes(t) => t.range(),
            ChannelTrack::Bart(t) => t.range(),
        }
    }

    /// Writes the value at time `t` into `out` ([`ChannelTrack::width`] numbers).
    pub fn sample_into(&self, t: f32, out: &mut [f32]) {
        match self {
            ChannelTrack::Keyframes(k) => k.sample_into(t, out),
            ChannelTrack::Bart(b) => b.sample_into(t, out),
        }
    }
}

impl From<Track> for ChannelTrack {
    fn from(t: Track) -> Self {
        ChannelTrack::Keyframes(t)
    }
}

impl From<BartTrack> for ChannelTrack {
    fn from(t: BartTrack) -> Self {
        ChannelTrack::Bart(t)
    }
}

/// One animated property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The node, an index into [`Rig::nodes`].
    pub node: u32,
    /// Which property.
    pub target: ChannelTarget,
    /// Its keys.
    pub track: ChannelTrack,
}

/// A named set of channels played together (a glTF animation; `--clip NAME` picks one).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Clip {
    /// Name from the file.
    pub name: Option<String>,
    /// The channels.
    pub channels: Vec<Channel>,
}

impl Clip {
    /// Time of the clip's first and last key over all channels, or `None` without any.
    pub fn range(&self) -> Option<(f32, f32)> {
        self.channels.iter().map(|c| c.track.range()).reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
    }
}

/// A skin: the joints (nodes) that deform a mesh and their inverse bind matrices.
#[derive(Clone, Debug, PartialEq)]
pub struct Skin {
    /// Name from the file.
    pub name: Option<String>,
    /// Joint `j` of a vertex's influences is node `joints[j]`.
    pub joints: Vec<u32>,
    /// `inverse_bind[j]` takes the mesh's bind-pose space to joint `j`'s space.
    pub inverse_bind: Vec<Mat4>,
}

/// Why a rig is unusable; loaders add the file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RigError {
    /// A parent index not before its child (or out of range).
    #[error("node {node}: parent {parent} must be an earlier node")]
    Parent {
        /// The child.
        node: u32,
        /// Its parent index.
        parent: u32,
    },
    /// A channel names a node that does not exist.
    #[error("clip {clip}, channel {channel}: node {node} does not exist ({nodes} nodes)")]
    ChannelNode {
        /// Clip index.
        clip: usize,
        /// Channel index.
        channel: usize,
        /// The node named.
        node: u32,
        /// Nodes there are.
        nodes: usize,
    },
    /// A channel whose values do not fit what it animates.
    #[error("clip {clip}, channel {channel} ({target:?} of node {node}): {message}")]
    ChannelShape {
        /// Clip index.
        clip: usize,
        /// Channel index.
        channel: usize,
        /// The node.
        node: u32,
        /// What it animates.
        target: ChannelTarget,
        /// What is wrong.
        message: String,
    },
    /// A skin joint that does not exist, or joint and matrix counts that differ.
    #[error("skin {skin}: {message}")]
    Skin {
        /// Skin index.
        skin: usize,
        /// What is wrong.
        message: String,
    },
    /// A track could not be made.
    #[error(transparent)]
    Track(#[from] TrackError),
}

/// Nodes, clips and skins of a scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rig {
    /// Nodes, parents first.
    pub nodes: Vec<Node>,
    /// Clips; [`Rig::active_clip`] is the one played.
    pub clips: Vec<Clip>,
    /// The clip [`Rig::world_matrices`] plays, when there are any.
    pub active_clip: usize,
    /// Skins.
    pub skins: Vec<Skin>,
}

impl Rig {
    /// Checks every index and shape the evaluation relies on (so evaluating never
    /// panics): parents first, channels on existing TRS nodes with the right widths,
    /// skin joints in range with one inverse bind matrix each.
    pub fn validate(&self) -> Result<(), RigError> {
        let n = self.nodes.len();
        for (i, node) in self.nodes.iter().enumerate() {
            if let Some(p) = node.parent {
                if p as usize >= i {
                    return Err(RigError::Parent { node: i as u32, parent: p });
                }
            }
        }
        for (c, clip) in self.clips.iter().enumerate() {
            for (k, ch) in clip.channels.iter().enumerate() {
                let Some(node) = self.nodes.get(ch.node as usize) else {
                    return Err(RigError::ChannelNode { clip: c, channel: k, node: ch.node, nodes: n });
                };
                let shape = |message: String| RigError::ChannelShape {
                    clip: c,
                    channel: k,
                    node: ch.node,
                    target: ch.target,
                    message,
                };
                let want = match ch.target {
                    ChannelTarget::Translation | ChannelTarget::Scale => Some(3),
                    ChannelTarget::Rotation => Some(4),
                    ChannelTarget::Weights => None,
                };
                if let Some(w) = want {
                    if ch.track.width() != w {
                        return Err(shape(format!("{} numbers a key, expected {w}", ch.track.width())));
                    }
                    if matches!(node.rest, NodePose::Matrix(_)) {
                        return Err(shape("the node has a matrix, which cannot be animated".into()));
                    }
                }
            }
        }
        for (s, skin) in self.skins.iter().enumerate() {
            if skin.joints.len() != skin.inverse_bind.len() {
                let message =
                    format!("{} joints but {} inverse bind matrices", skin.joints.len(), skin.inverse_bind.len());
                return Err(RigError::Skin { skin: s, message });
            }
            if let Some(j) = skin.joints.iter().find(|&&j| j as usize >= n) {
                return Err(RigError::Skin { skin: s, message: format!("joint node {j} does not exist ({n} nodes)") });
            }
        }
        Ok(())
    }

    /// The active clip, if any.
    pub fn clip(&self) -> Option<&Clip> {
        self.clips.get(self.active_clip)
    }

    /// Per node, whether its world matrix can change with time under the active clip.
    pub fn animated_nodes(&self) -> Vec<bool> {
        let mut moves = vec![false; self.nodes.len()];
        if let Some(clip) = self.clip() {
            for ch in &clip.channels {
                if ch.target != ChannelTarget::Weights {
                    moves[ch.node as usize] = true;
                }
            }
        }
        for i in 0..self.nodes.len() {
            if let Some(p) = self.nodes[i].parent {
                moves[i] |= moves[p as usize];
            }
        }
        moves
    }

    /// Every node's world matrix at time `t` under the active clip, into `out`
    /// (cleared first). Call [`Rig::validate`] once before.
    pub fn world_matrices(&self, t: f32, out: &mut Vec<Mat4>) {
        out.clear();
        let mut poses: Vec<NodePose> = self.nodes.iter().map(|n| n.rest).collect();
        if let Some(clip) = self.clip() {
            let mut v = [0.0f32; 4];
            for ch in &clip.channels {
                let NodePose::Trs { translation, rotation, scale } = &mut poses[ch.node as usize] else { continue };
                match ch.target {
                    ChannelTarget::Translation => {
                        ch.track.sample_into(t, &mut v);
                        *translation = Vec3::new(v[0], v[1], v[2]);
                    }
                    ChannelTarget::Rotation => {
                        ch.track.sample_into(t, &mut v);
                        *rotation = Quat::from_xyzw(v[0], v[1], v[2], v[3]);
                    }
                    ChannelTarget::Scale => {
                        ch.track.sample_into(t, &mut v);
                        *scale = Vec3::new(v[0], v[1], v[2]);
                    }
                    ChannelTarget::Weights => {}
                }
            }
        }
        for (i, node) in self.nodes.iter().enumerate() {
            let local = match poses[i] {
                NodePose::Matrix(m) => m,
                NodePose::Trs { translation, rotation, scale } => {
                    Mat4::from_scale_rotation_translation(scale, rotation, translation)
                }
            };
            let world = match node.parent {
                Some(p) => out[p as usize] * local,
                None => local,
            };
            out.push(world);
        }
    }

    /// Node `node`'s morph weights at time `t` into `out` (its rest weights, replaced by
    /// the active clip's weights channel where it has one; cleared first).
    pub fn weights(&self, node: u32, t: f32, out: &mut Vec<f32>) {
        out.clear();
        let Some(n) = self.nodes.get(node as usize) else { return };
        out.extend_from_slice(&n.rest_weights);
        let channel = self
            .clip()
            .and_then(|c| c.channels.iter().find(|ch| ch.node == node && ch.target == ChannelTarget::Weights));
        if let Some(ch) = channel {
            out.resize(ch.track.width(), 0.0);
            ch.track.sample_into(t, out);
        }
    }
}
