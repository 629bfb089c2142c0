//! The kd-tree's flat node encoding and the per-leaf rope records of the Ropes++ variant.

use bytemuck::{Pod, Zeroable};
use dynray_geom::Aabb;

/// "No neighbour": a rope across a face of the root box.
pub const NO_ROPE: u32 = u32::MAX;

/// Flag value of [`KdNode::flags`]'s two low bits that marks a leaf (0, 1, 2 = split axis).
const LEAF: u32 = 3;

/// Largest child or leaf index the 30 bits of [`KdNode::flags`] can hold.
pub const MAX_INDEX: u32 = (1 << 30) - 1;

/// One kd-tree node, interior or leaf, in 8 bytes (the classic layout: Wald's thesis, pbrt).
///
/// Interior: `data` is the split position's `f32` bits; `flags & 3` is the split axis
/// (0 = x, 1 = y, 2 = z); `flags >> 2` is the index of the right child (points with
/// `p[axis] >= split`). The left child (`p[axis] <= split`) is always the next node: nodes
/// are stored depth-first, left subtree first.
///
/// Leaf: `flags & 3 == 3`; `data` is the leaf's index. Its triangle references are
/// `prim_ids[leaf_starts[i]..leaf_starts[i + 1]]` (leaves own consecutive ranges, so the
/// count costs no bits here), and the Ropes++ variant's [`LeafRopes`] record has the same
/// index.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct KdNode {
    /// Split position bits (interior) or leaf index (leaf).
    pub data: u32,
    /// Axis or leaf flag in bits 0..2, right child index in bits 2..32 (interior).
    pub flags: u32,
}

// Two u32: eight nodes share a 64-byte cache line, as in the kd-trees the seed compares
// against ("a well optimised kd-tree node needs 8 bytes", seed 000 §2.9).
const _: () = assert!(std::mem::size_of::<KdNode>() == 8);

impl KdNode {
    /// An interior node; `right` must fit in 30 bits (the builder checks).
    #[inline]
    pub fn interior(axis: usize, split: f32, right: u32) -> Self {
        debug_assert!(axis < 3 && right <= MAX_INDEX, "axis {axis}, right child {right}");
        Self { data: split.to_bits(), flags: axis as u32 | (right << 2) }
    }

    /// A leaf with index `leaf`.
    #[inline]
    pub fn leaf(leaf: u32) -> Self {
        Self { data: leaf, flags: LEAF }
    }

    /// True for a leaf.
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.flags & 3 == LEAF
    }

    /// Split axis of an interior node.
    #[inline(always)]
    pub fn axis(&self) -> usize {
        (self.flags & 3) as usize
    }

    /// Split position of an interior node.
    #[inline(always)]
    pub fn split(&self) -> f32 {
        f32::from_bits(self.data)
    }

    /// Right child of an interior node (the left child is `self index + 1`).
    #[inline(always)]
    pub fn right(&self) -> u32 {
        self.flags >> 2
    }

    /// Leaf index of a leaf.
    #[inline(always)]
    pub fn leaf_index(&self) -> u32 {
        self.data
    }
}

/// What the stackless traversal needs per leaf (Popov et al. 2007): the leaf's box and,
/// per face, the node on the other side ([`NO_ROPE`] on the root's boundary).
///
/// Faces are numbered `2·axis + side`: 0 = −x, 1 = +x, 2 = −y, 3 = +y, 4 = −z, 5 = +z.
/// After the Ropes++ optimisation a rope names the deepest node whose region still covers
/// the whole face, so fewer descent steps follow each rope.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LeafRopes {
    /// The leaf's region.
    pub bounds: Aabb,
    /// Neighbour node index across each face, or [`NO_ROPE`].
    pub ropes: [u32; 6],
}

// 24-byte box + six u32: the "6 pointers per leaf" the seed blames for the Ropes variant's
// memory (41 MB against 14 MB, seed 000 §4.4); no padding, so it uploads as is.
const _: () = assert!(std::mem::size_of::<LeafRopes>() == 48);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoding_round_trips() {
        let n = KdNode::interior(2, -1.5, MAX_INDEX);
        assert!(!n.is_leaf());
        assert_eq!((n.axis(), n.split(), n.right()), (2, -1.5, MAX_INDEX));
        let l = KdNode::leaf(123_456);
        assert!(l.is_leaf());
        assert_eq!(l.leaf_index(), 123_456);
    }
}
