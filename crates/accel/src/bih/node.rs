//! The 16-byte BIH node of seed 000 §2.2, and its bit encoding.

use bytemuck::{Pod, Zeroable};

/// One node of the Bounding Interval Hierarchy, interior or leaf.
///
/// Encoding (seed 000 §2.2, `BIH_Node`):
/// - `child`: bits 0–1 are the flag, `00` = split on x, `01` = y, `10` = z, `11` = leaf;
///   bits 2–31 are an index (`child >> 2`). For an interior node the index is the
///   **right** child's node index; the left child is always the next node (`parent + 1`),
///   because the tree is stored in depth-first pre-order. For a leaf the index is the
///   first entry of the leaf's run in the primitive arrays (`Bih::tris`/`prim_ids`).
/// - `count`: number of triangles of a leaf (never 0: the builder never stores an empty
///   leaf, see `build.rs`); 0 and unused for interior nodes.
/// - `clip`: interior only. `clip[0]` is the left child's upper bound on the split axis
///   (the largest coordinate of any triangle in the left subtree), `clip[1]` the right
///   child's lower bound (the smallest coordinate of any triangle in the right subtree).
///   The two intervals may overlap (`clip[0] > clip[1]`) or leave a gap that traversal
///   skips. Both are zero in a leaf.
/// - One-child node (an empty-space cut, `BihParams::empty_cut`): the right index equals
///   `parent + 1`, i.e. both children are the same node, and one plane is infinite:
///   `clip = [c, +∞]` keeps the child below `c`, `clip = [−∞, c]` keeps it above `c`.
///   Traversal needs no special case: the infinite plane gives the missing side an
///   empty interval (for a ray parallel to the axis at worst a redundant, harmless
///   second visit of the child).
///
/// Indices are therefore limited to `2^30 - 1` ([`MAX_INDEX`]); the builder checks this.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BihNode {
    /// `index << 2 | flag`, see the type's documentation.
    pub child: u32,
    /// Triangles in a leaf; 0 in an interior node.
    pub count: u32,
    /// Interior: `[left upper clip plane, right lower clip plane]` on the split axis.
    pub clip: [f32; 2],
}

// Seed 000's node is exactly 16 bytes (4 + 4 + 2·4), so four fit a 64-byte cache line
// and the array uploads to the GPU unchanged; a BVH node with a full box needs 24 more.
const _: () = assert!(std::mem::size_of::<BihNode>() == 16);

/// The flag value (two low bits of `child`) that marks a leaf.
pub const LEAF_FLAG: u32 = 3;

/// Largest node or primitive index the 30-bit field can hold.
pub const MAX_INDEX: u32 = (1 << 30) - 1;

impl BihNode {
    /// An interior node splitting on `axis` (0..3) whose right child is node `right`.
    #[inline]
    pub fn interior(axis: usize, right: u32, clip_left: f32, clip_right: f32) -> Self {
        debug_assert!(axis < 3, "axis {axis}");
        debug_assert!(right <= MAX_INDEX, "right child {right} exceeds 30 bits");
        Self { child: right << 2 | axis as u32, count: 0, clip: [clip_left, clip_right] }
    }

    /// A leaf holding `count` triangles starting at primitive slot `first`.
    #[inline]
    pub fn leaf(first: u32, count: u32) -> Self {
        debug_assert!(first <= MAX_INDEX, "leaf start {first} exceeds 30 bits");
        Self { child: first << 2 | LEAF_FLAG, count, clip: [0.0; 2] }
    }

    /// True for a leaf.
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.child & 3 == LEAF_FLAG
    }

    /// Split axis of an interior node (0 = x, 1 = y, 2 = z).
    #[inline(always)]
    pub fn axis(&self) -> usize {
        (self.child & 3) as usize
    }

    /// Right child (interior) or first primitive slot (leaf).
    #[inline(always)]
    pub fn index(&self) -> u32 {
        self.child >> 2
    }

    /// Moves an interior node's right-child index by `by` nodes (used when subtrees
    /// built in parallel are concatenated); leaves are left alone because their
    /// primitive slots are already absolute.
    #[inline]
    pub(crate) fn shift(&mut self, by: u32) {
        if !self.is_leaf() {
            self.child += by << 2;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoding_round_trips() {
        let n = BihNode::interior(2, 12345, -1.0, 2.0);
        assert!(!n.is_leaf());
        assert_eq!((n.axis(), n.index(), n.clip), (2, 12345, [-1.0, 2.0]));
        let l = BihNode::leaf(MAX_INDEX, 7);
        assert!(l.is_leaf());
        assert_eq!((l.index(), l.count), (MAX_INDEX, 7));
        let mut s = BihNode::interior(1, 5, 0.0, 0.0);
        s.shift(10);
        assert_eq!((s.axis(), s.index()), (1, 15));
    }
}
