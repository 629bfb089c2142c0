//! The wide node: `W` child boxes as SoA `f32` arrays (one array per axis and side), so one
//! SIMD register holds one coordinate of every child, and `W` child references.

use bytemuck::{Pod, Zeroable};
use dynray_geom::{Aabb, Vec3};

/// A child reference of a wide node.
///
/// Encoding: bit 31 clear ⇒ interior child, the value is its node index; bit 31 set ⇒ leaf
/// of blocks `first .. first + count` with `first = (ref >> 3) & 0x0FFF_FFFF` and
/// `count = (ref & 7) + 1` (1..=8 blocks of 4 triangles). [`EMPTY`] fills unused slots
/// (lanes `count..W` of [`WideNode::count`]); the builder keeps block indices below
/// `MAX_BLOCKS` so no leaf reads as `EMPTY`.
pub type ChildRef = u32;

/// Bit 31: the child is a leaf.
pub const LEAF_BIT: u32 = 1 << 31;
/// An unused child slot.
pub const EMPTY: ChildRef = u32::MAX;
/// Most blocks one leaf holds (3 bits of the reference).
pub const MAX_LEAF_BLOCKS: u32 = 8;
/// Blocks addressable by a leaf reference, less one so that no leaf equals [`EMPTY`].
pub const MAX_BLOCKS: u32 = (1 << 28) - 1;

/// A leaf reference over `count` blocks starting at `first`.
#[inline]
pub fn leaf_ref(first: u32, count: u32) -> ChildRef {
    assert!((1..=MAX_LEAF_BLOCKS).contains(&count), "leaf of {count} blocks; the reference holds 1..=8");
    assert!(first + count <= MAX_BLOCKS, "block {first} + {count} beyond the {MAX_BLOCKS} a reference addresses");
    LEAF_BIT | (first << 3) | (count - 1)
}

/// `(first block, block count)` of a leaf reference.
#[inline(always)]
pub fn leaf_blocks(r: ChildRef) -> (usize, usize) {
    (((r >> 3) & 0x0FFF_FFFF) as usize, ((r & 7) + 1) as usize)
}

/// True for a leaf reference (including [`EMPTY`], which traversal never reaches).
#[inline(always)]
pub fn is_leaf(r: ChildRef) -> bool {
    r & LEAF_BIT != 0
}

/// What traversal, collapse and validation need of a node of either width.
pub trait WideNode: Pod + Send + Sync + std::fmt::Debug {
    /// Children per node.
    const W: usize;
    /// A node with no children.
    fn empty() -> Self;
    /// Valid children (lanes `0..count`); the rest are [`EMPTY`].
    fn count(&self) -> usize;
    /// Child reference of lane `i`.
    fn child(&self, i: usize) -> ChildRef;
    /// Box of lane `i`.
    fn child_box(&self, i: usize) -> Aabb;
    /// Appends a child (the caller keeps `count < W`).
    fn push(&mut self, r: ChildRef, b: &Aabb);
    /// Replaces the box of lane `i` (refit).
    fn set_box(&mut self, i: usize, b: &Aabb);
    /// Lower corners along `axis`, one lane per child (`W` values).
    fn lo(&self, axis: usize) -> &[f32];
    /// Upper corners along `axis`, one lane per child (`W` values).
    fn hi(&self, axis: usize) -> &[f32];
}

macro_rules! wide_node {
    ($(#[$doc:meta])* $name:ident, $w:literal, $pad:literal, $size:literal) => {
        $(#[$doc])*
        #[repr(C, align(64))]
        #[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
        pub struct $name {
            /// `lo[axis][i]`: smallest coordinate of child `i`'s box (the empty box in
            /// unused lanes, which the lane mask excludes anyway).
            pub lo: [[f32; $w]; 3],
            /// `hi[axis][i]`: largest coordinate of child `i`'s box.
            pub hi: [[f32; $w]; 3],
            /// Child references, see [`ChildRef`].
            pub child: [ChildRef; $w],
            /// Valid children: lanes `0..count`.
            pub count: u32,
            /// Fills the node to a whole number of cache lines.
            pub pad: [u32; $pad],
        }

        // Whole cache lines, no implicit padding (Pod): a node starts on a line and its
        // SoA arrays never straddle more lines than their size needs.
        const _: () = assert!(std::mem::size_of::<$name>() == $size);

        impl WideNode for $name {
            const W: usize = $w;

            fn empty() -> Self {
                Self {
                    lo: [[f32::INFINITY; $w]; 3],
                    hi: [[f32::NEG_INFINITY; $w]; 3],
                    child: [EMPTY; $w],
                    count: 0,
                    pad: [0; $pad],
                }
            }

            #[inline(always)]
            fn count(&self) -> usize {
                self.count as usize
            }

            #[inline(always)]
            fn child(&self, i: usize) -> ChildRef {
                self.child[i]
            }

            fn child_box(&self, i: usize) -> Aabb {
                let (l, h) = (&self.lo, &self.hi);
                Aabb::new(Vec3::new(l[0][i], l[1][i], l[2][i]), Vec3::new(h[0][i], h[1][i], h[2][i]))
            }

            fn push(&mut self, r: ChildRef, b: &Aabb) {
                let i = self.count as usize;
                assert!(i < $w, "a {}-wide node holds {} children", $w, $w);
                self.child[i] = r;
                self.count += 1;
                self.set_box(i, b);
            }

            fn set_box(&mut self, i: usize, b: &Aabb) {
                for a in 0..3 {
                    self.lo[a][i] = b.min[a];
                    self.hi[a][i] = b.max[a];
                }
            }

            #[inline(always)]
            fn lo(&self, axis: usize) -> &[f32] {
                &self.lo[axis]
            }

            #[inline(always)]
            fn hi(&self, axis: usize) -> &[f32] {
                &self.hi[axis]
            }
        }
    };
}

wide_node!(
    /// A 4-wide node: 2 cache lines (4 × 6 floats of boxes, 4 references, the count).
    Node4, 4, 3, 128
);
wide_node!(
    /// An 8-wide node: 4 cache lines (8 × 6 floats of boxes, 8 references, the count).
    Node8, 8, 7, 256
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn leaf_references_round_trip_and_never_equal_empty() {
        for (first, count) in [(0, 1), (5, 8), (MAX_BLOCKS - 8, 8), (MAX_BLOCKS - 1, 1)] {
            let r = leaf_ref(first, count);
            assert!(is_leaf(r) && r != EMPTY, "{first} {count}");
            assert_eq!(leaf_blocks(r), (first as usize, count as usize));
        }
        assert!(!is_leaf(12345));
    }

    #[test]
    fn push_fills_lanes_in_order() {
        let mut n = Node8::empty();
        let b = Aabb::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0));
        n.push(7, &b);
        n.push(leaf_ref(3, 2), &b);
        assert_eq!((n.count(), n.child(0), n.child(2)), (2, 7, EMPTY));
        assert_eq!(n.child_box(1), b);
        assert_eq!((n.lo(2)[0], n.hi(0)[1]), (3.0, 4.0));
    }
}
