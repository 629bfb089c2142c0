//! glTF animations as [`Clip`]s of the scene's rig, and the index checks that must run
//! on the JSON before the gltf crate's wrappers touch animations, skins or morph targets.
//!
//! Each animation becomes a clip (its name kept); each channel a [`Channel`] on the rig
//! node its target became, with a [`Track`] of the sampler's keys: `STEP`, `LINEAR`
//! (slerp for rotations) or `CUBICSPLINE` (in-tangent, value, out-tangent per key).
//! Input times are float scalars, strictly increasing. Outputs follow the spec's table
//! (glTF 2.0 §5.7.2.1): translation and scale float `VEC3`; rotation `VEC4` float or
//! normalised (signed or unsigned) byte or short; weights float or normalised byte or
//! short scalars, one per morph target of the node's mesh per key. Channels on nodes
//! outside the walked scene are ignored with a warning, as are weights channels on nodes
//! without morph targets.

use super::accessor::{check_accessor_with, read_components};
use crate::animation::{Channel, ChannelTarget, ChannelTrack, Clip, Interpolation, NodePose, Rig, Track};
use crate::report::Warning;
use gltf::accessor::{DataType, Dimensions};
use gltf::animation::Property;
use std::path::Path;

/// Checks the indices of animations, skins, node skins and morph targets against the
/// arrays they index, so that the messages name the place (gltf-json's validation
/// reports such errors less clearly, and the wrappers would panic on some).
pub(super) fn check_indices(json: &gltf::json::Root) -> Result<(), String> {
    let (nodes, accessors) = (json.nodes.len(), json.accessors.len());
    let accessor = |what: String, i: usize| {
        if i < accessors {
            Ok(())
        } else {
            Err(format!("{what} names accessor {i}, but there are {accessors}"))
        }
    };
    for (a, anim) in json.animations.iter().enumerate() {
        let label = animation_label(a, anim.name.as_deref());
        for (s, sampler) in anim.samplers.iter().enumerate() {
            accessor(format!("{label} sampler {s}: input"), sampler.input.value())?;
            accessor(format!("{label} sampler {s}: output"), sampler.output.value())?;
        }
        for (c, ch) in anim.channels.iter().enumerate() {
            if ch.sampler.value() >= anim.samplers.len() {
                return Err(format!(
                    "{label} channel {c}: sampler {} does not exist (the animation has {} samplers)",
                    ch.sampler.value(),
                    anim.samplers.len()
                ));
            }
            // gltf-json 1.4 does not validate a channel's target path, and the wrapper's
            // `property()` unwraps it: an unknown path panicked (found by fuzzing).
            if let gltf::json::validation::Checked::Invalid = ch.target.path {
                return Err(format!(
                    "{label} channel {c}: the target path is not one of translation, rotation, scale, weights"
                ));
            }
            if ch.target.node.value() >= nodes {
                return Err(format!(
                    "{label} channel {c}: target node {} does not exist ({nodes} nodes)",
                    ch.target.node.value()
                ));
            }
        }
    }
    for (s, skin) in json.skins.iter().enumerate() {
        let label = skin_label(s, skin.name.as_deref());
        for (j, joint) in skin.joints.iter().enumerate() {
            if joint.value() >= nodes {
                return Err(format!(
                    "{label}: joint {j} names node {}, which does not exist ({nodes} nodes)",
                    joint.value()
                ));
            }
        }
        if let Some(ibm) = skin.inverse_bind_matrices {
            accessor(format!("{label}: inverseBindMatrices"), ibm.value())?;
        }
    }
    for (n, node) in json.nodes.iter().enumerate() {
        if let Some(s) = node.skin.filter(|s| s.value() >= json.skins.len()) {
            return Err(format!("node {n}: skin {} does not exist ({} skins)", s.value(), json.skins.len()));
        }
    }
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (t, target) in prim.targets.iter().flatten().enumerate() {
                for (what, acc) in
                    [("POSITION", target.positions), ("NORMAL", target.normals), ("TANGENT", target.tangents)]
                {
                    if let Some(acc) = acc {
                        accessor(format!("mesh {m} primitive {p}: morph target {t} {what}"), acc.value())?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// Per node of the file, whether some channel of some animation moves its translation,
/// rotation or scale (call after [`check_indices`]). Such nodes keep their TRS in the
/// rig; the others are stored as the exact matrix the static loader always used.
pub(super) fn moved_nodes(json: &gltf::json::Root) -> Vec<bool> {
    let mut moved = vec![false; json.nodes.len()];
    for ch in json.animations.iter().flat_map(|a| &a.channels) {
        let weights = matches!(ch.target.path, gltf::json::validation::Checked::Valid(Property::MorphTargetWeights));
        if !weights {
            if let Some(m) = moved.get_mut(ch.target.node.value()) {
                *m = true;
            }
        }
    }
    moved
}

/// `animation 2 ("Walk")`, or `animation 2` without a name.
pub(super) fn animation_label(a: usize, name: Option<&str>) -> String {
    match name {
        Some(n) => format!("animation {a} ({n:?})"),
        None => format!("animation {a}"),
    }
}

/// `skin 0 ("Armature")`, or `skin 0` without a name.
pub(super) fn skin_label(s: usize, name: Option<&str>) -> String {
    match name {
        Some(n) => format!("skin {s} ({n:?})"),
        None => format!("skin {s}"),
    }
}

/// Every animation of the file as a clip of `rig` (whose nodes are the walked scene's,
/// `rig_of[gltf node]` their indices; each rig node's `rest_weights` gives its number
/// of morph targets).
pub(super) fn read_clips(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    rig: &Rig,
    rig_of: &[Option<u32>],
    path: &Path,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<Clip>, String> {
    let mut clips = Vec::new();
    for anim in document.animations() {
        let label = animation_label(anim.index(), anim.name());
        let mut channels = Vec::new();
        for ch in anim.channels() {
            let here = format!("{label} channel {}", ch.index());
            let gnode = ch.target().node().index();
            let Some(node) = rig_of.get(gnode).copied().flatten() else {
                warnings.push(Warning::new(
                    path,
                    None,
                    format!("{here}: node {gnode} is not in the scene that is shown; channel ignored"),
                ));
                continue;
            };
            let rig_node = &rig.nodes[node as usize];
            let sampler = ch.sampler();
            let input = sampler.input();
            check_accessor_with(&input, Dimensions::Scalar, &[DataType::F32], false, buffers)
                .map_err(|m| format!("{here}: key times (input): {m}"))?;
            let times = read_components(&input, buffers).map_err(|m| format!("{here}: key times (input): {m}"))?;
            const QUANTISED: &[DataType] = &[DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16];
            let (target, width, dims, types) = match ch.target().property() {
                Property::Translation => (ChannelTarget::Translation, 3, Dimensions::Vec3, &[DataType::F32][..]),
                Property::Rotation => (ChannelTarget::Rotation, 4, Dimensions::Vec4, QUANTISED),
                Property::Scale => (ChannelTarget::Scale, 3, Dimensions::Vec3, &[DataType::F32][..]),
                Property::MorphTargetWeights => {
                    (ChannelTarget::Weights, rig_node.rest_weights.len(), Dimensions::Scalar, QUANTISED)
                }
            };
            if width == 0 {
                warnings.push(Warning::new(
                    path,
                    None,
                    format!(
                        "{here}: animates the weights of node {gnode}, which has no morph targets; channel ignored"
                    ),
                ));
                continue;
            }
            if target != ChannelTarget::Weights && matches!(rig_node.rest, NodePose::Matrix(_)) {
                return Err(format!(
                    "{here}: node {gnode} has a matrix, and glTF allows only translation/rotation/scale on animated nodes"
                ));
            }
            let output = sampler.output();
            check_accessor_with(&output, dims, types, true, buffers)
                .map_err(|m| format!("{here}: values (output): {m}"))?;
            if output.data_type() != DataType::F32 && !output.normalized() {
                return Err(format!(
                    "{here}: values (output): accessor {} is an integer type but not normalized",
                    output.index()
                ));
            }
            let cubic = sampler.interpolation() == gltf::animation::Interpolation::CubicSpline;
            let per_key = if target == ChannelTarget::Weights { width } else { 1 } * if cubic { 3 } else { 1 };
            let keys = times.len();
            if output.count() != keys * per_key {
                return Err(format!(
                    "{here}: values (output) accessor {} has {} elements for {keys} key times (expected {}{})",
                    output.index(),
                    output.count(),
                    keys * per_key,
                    if cubic { ", three per key for CUBICSPLINE" } else { "" }
                ));
            }
            let values = read_components(&output, buffers).map_err(|m| format!("{here}: values (output): {m}"))?;
            let track = match sampler.interpolation() {
                gltf::animation::Interpolation::CubicSpline => Track::cubic_spline(times, width, &values),
                gltf::animation::Interpolation::Step => Track::new(times, width, values, Interpolation::Step),
                gltf::animation::Interpolation::Linear => Track::new(times, width, values, Interpolation::Linear),
            };
            let track = if target == ChannelTarget::Rotation { track.and_then(Track::into_rotation) } else { track };
            let track = track.map_err(|e| format!("{here}: {e}"))?;
            channels.push(Channel { node, target, track: ChannelTrack::Keyframes(track) });
        }
        clips.push(Clip { name: anim.name().map(str::to_string), channels });
    }
    Ok(clips)
}
