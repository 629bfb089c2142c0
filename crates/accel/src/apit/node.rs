//! The two flat record types of the A-PIT: fragments (per-pixel depth intervals of a
//! triangle) and pseudo-interval-tree nodes, laid out as the seed's GPU arrays.

use bytemuck::{Pod, Zeroable};

/// "No index": the end of a list, a missing child, the parent of a root, an empty pixel.
pub const NONE: u32 = u32::MAX;

/// The part of one triangle inside one pixel frustum: its depth interval and triangle.
///
/// Depth is the distance along the face axis from the observer (`w`, see `cube.rs`),
/// rounded outwards to `f32`, so the interval contains the depth of every point of the
/// triangle inside the (slightly dilated) frustum.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Fragment {
    /// Smallest depth of the triangle inside the frustum.
    pub zmin: f32,
    /// Largest depth of the triangle inside the frustum.
    pub zmax: f32,
    /// Triangle index in the mesh.
    pub tri: u32,
    /// Next fragment of the same list (a pixel's list, or a tree node's), or [`NONE`].
    pub next: u32,
}

// The seed's fragment record {zmin, zmax, triangle, successor}: 4 words, no padding.
const _: () = assert!(std::mem::size_of::<Fragment>() == 16);

impl Fragment {
    /// True when `[zmin, zmax]` meets the closed query interval `[qa, qb]`.
    #[inline(always)]
    pub fn overlaps(&self, qa: f32, qb: f32) -> bool {
        self.zmin <= qb && self.zmax >= qa
    }
}

/// A pseudo-interval-tree node: the fragments stored here all contain `disc`; those of
/// the left subtree end before it, those of the right subtree start after it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PitNode {
    /// Discriminant: the midpoint of the first interval that reached this node.
    pub disc: f32,
    /// Left child (intervals with `zmax < disc`), or [`NONE`].
    pub left: u32,
    /// Right child (intervals with `zmin > disc`), or [`NONE`].
    pub right: u32,
    /// Parent, or [`NONE`] at a pixel's root: the stackless query climbs through it.
    pub parent: u32,
    /// First fragment of this node's unsorted list (never [`NONE`]: a node is created
    /// by the interval that it then stores).
    pub first: u32,
}

// The seed's node record {discriminant, left, right, parent, first fragment}: 5 words.
const _: () = assert!(std::mem::size_of::<PitNode>() == 20);
