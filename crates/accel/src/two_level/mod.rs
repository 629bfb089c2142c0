//! Two levels: a small top-level BVH over instances, each a bottom-level structure (any
//! [`crate::AccelKind`]) over part of a frame — seed 003's split of static and dynamic
//! actors, and rigid instancing.
//!
//! A frame's actors ([`ActorGeometry`]) fall into parts ([`SceneLayout`] says how):
//! - every [`ActorMotion::Static`] actor goes into one world-space part, built once;
//! - every [`ActorMotion::Deforming`] actor (skin, morph, BART `tpa`, physics) gets a
//!   world-space part of its own, refit or rebuilt each frame by the update policy;
//! - every [`ActorMotion::Rigid`] actor is, under [`SceneLayout::Instanced`], an instance:
//!   a part built once over its *local* vertices (shared by every actor with the same
//!   local mesh) and a transform; rays are taken into local space, so rigid motion costs
//!   only the top-level rebuild. Under [`SceneLayout::Split`] it is treated as deforming.
//!
//! Exactness. A world-space part holds the frame's own vertex values and the parts are
//! searched with ties going to the lower frame triangle, so hits through world-space parts
//! are bit-identical to brute force over the frame's mesh. An instance is tested in its
//! local space, with the ray mapped by the inverse transform (direction not normalised,
//! so `t` is the same parameter in both spaces): its hits are bit-identical to brute
//! force over the *local* triangles with the mapped ray, which is the instanced oracle
//! ([`TwoLevel::intersect_brute`]); against the flattened frame they name the same
//! triangle and differ in `t` by rounding (docs/animate.md, "Scene layouts").

mod build;
mod live;
mod outline;
mod top;
mod traverse;
mod validate;

#[cfg(test)]
mod tests;

pub use live::{LiveScene, PartUpdates};

use crate::Accel;
use dynray_geom::{Aabb, TriangleMesh};
use glam::{Mat4, Vec3};
use std::fmt;
use std::ops::Range;
use std::str::FromStr;

/// How the actors of one frame of a scene are spread over a frame's structures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SceneLayout {
    /// One structure over the whole frame (refit or rebuilt as one).
    Flat,
    /// Static actors in one part built once, every moving actor in a world-space part of
    /// its own; exact against brute force on the frame.
    Split,
    /// [`SceneLayout::Split`], with rigidly moving actors as instances of local-space
    /// parts (rays transformed). The default.
    #[default]
    Instanced,
}

impl SceneLayout {
    /// Names accepted by [`SceneLayout::from_str`].
    pub const NAMES: [&'static str; 3] = ["flat", "split", "instanced"];

    /// The `--scene-accel` spelling.
    pub fn name(self) -> &'static str {
        match self {
            SceneLayout::Flat => "flat",
            SceneLayout::Split => "split",
            SceneLayout::Instanced => "instanced",
        }
    }
}

impl fmt::Display for SceneLayout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for SceneLayout {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "flat" => Ok(SceneLayout::Flat),
            "split" => Ok(SceneLayout::Split),
            "instanced" => Ok(SceneLayout::Instanced),
            _ => Err(format!("unknown scene layout `{s}` (expected flat, split or instanced)")),
        }
    }
}

/// One actor of a frame, as the two-level structure sees it.
#[derive(Clone, Debug)]
pub struct ActorGeometry<'a> {
    /// Its triangles in the frame's mesh (contiguous; actors in actor order).
    pub triangles: Range<u32>,
    /// Its vertices in the frame's mesh; the actor's indices point into this range.
    pub vertices: Range<u32>,
    /// How its geometry may change from frame to frame.
    pub motion: ActorMotion<'a>,
}

/// How an actor's world geometry may change over the frames.
#[derive(Clone, Copy, Debug)]
pub enum ActorMotion<'a> {
    /// The same at every time (the scene promises it).
    Static,
    /// Vertices move independently (skins, morphs, simulation, `tpa` patches).
    Deforming,
    /// Placed by a transform that may change: its world vertices are `to_world` applied to
    /// `local`'s (the frame's own values come from the same product).
    Rigid {
        /// The actor's mesh in its own space (the same triangle order as in the frame).
        local: &'a TriangleMesh,
        /// Object-to-world matrix at this frame (affine, invertible).
        to_world: Mat4,
    },
}

/// A bottom-level structure and the triangles it holds.
pub(crate) struct Part {
    /// The structure (a [`crate::LiveAccel`], so the update policy applies to it).
    pub live: crate::LiveAccel,
    /// What the part's triangles are.
    pub space: PartSpace,
    /// Bounds of the part's vertices in its own space.
    pub bounds: Aabb,
    /// A world-space part's triangles as the frame last gave them (indices rebased to
    /// the part; positions refilled each frame); empty for a local part.
    pub sub: TriangleMesh,
}

/// Which triangles a part holds, and in which space.
pub(crate) enum PartSpace {
    /// Frame triangles in world space: the part's triangle `i` is frame triangle
    /// `prims[i]` (increasing), its vertices are frame vertices `vertices` in order.
    World { actors: Vec<usize>, prims: Vec<u32> },
    /// A local-space mesh shared by the instances whose actors are listed.
    Local { actors: Vec<usize> },
}

/// One placement of a part in the top level.
#[derive(Clone, Copy, Debug)]
pub struct Instance {
    /// Index of its part.
    pub part: u32,
    /// The actor it stands for (`u32::MAX` for the static part, which holds several).
    pub actor: u32,
    /// First frame triangle of the actor (for a local part: local triangle `i` is frame
    /// triangle `first_prim + i`).
    pub first_prim: u32,
    /// World-to-local matrix (`None`: the part is in world space).
    pub to_local: Option<Mat4>,
    /// The actor's object-to-world matrix it was computed from (`None` likewise).
    pub to_world: Option<Mat4>,
    /// Bounds in world space (for an instance, the transformed local box, widened as
    /// `transformed_bounds` says so rounding of the transform cannot cull a hit).
    pub bounds: Aabb,
}

/// A frame's actors as parts under a top-level BVH; see the module docs.
pub struct TwoLevel {
    /// Which `--accel` the parts are.
    spec: crate::AccelSpec,
    pub(crate) parts: Vec<Part>,
    pub(crate) instances: Vec<Instance>,
    /// The top-level tree; leaves hold instance indices through `order`.
    pub(crate) top: Vec<crate::BvhNode>,
    pub(crate) order: Vec<u32>,
    /// Frame triangles covered (for validation).
    pub(crate) triangles: u32,
}

impl TwoLevel {
    /// The structure its parts are (`bvh`, `bih`, …).
    pub fn spec(&self) -> &crate::AccelSpec {
        &self.spec
    }

    /// Parts (bottom-level structures) and instances.
    pub fn counts(&self) -> (usize, usize) {
        (self.parts.len(), self.instances.len())
    }

    /// The instances, in actor order (the static part first).
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// Bottom-level structure `part`.
    pub fn part(&self, part: usize) -> &dyn Accel {
        self.parts[part].live.accel()
    }
}

/// `m` applied to the eight corners of `b`, widened by 1e-4 of the result's magnitude:
/// the top level only culls, and the widening keeps it from culling a ray that the
/// rounding of its mapping into local space brings onto the part (the local structure
/// then decides, exactly). 1e-4 is far above f32 rounding for transforms of moderate
/// condition and costs nothing measurable in culling.
pub(crate) fn transformed_bounds(b: &Aabb, m: &Mat4) -> Aabb {
    if b.is_empty() {
        return *b;
    }
    let mut out = Aabb::EMPTY;
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        );
        out.grow(m.transform_point3(c));
    }
    let scale = out.min.abs().max(out.max.abs()).max_element().max(out.extent().max_element());
    let pad = Vec3::splat(scale * 1e-4 + f32::MIN_POSITIVE);
    Aabb::new(out.min - pad, out.max + pad)
}
