//! Serialised octree records: the seed's leaf record of 32-bit words, the per-leaf box,
//! and the compact internal-node array used by point location and the top-down descent.

use bytemuck::{Pod, Zeroable};
use dynray_geom::Aabb;
use glam::Vec3;

/// Leaf record layout in the `records` word array (seed Eq. 3):
/// `tCount | tOffset | i | nCount | N…`.
/// - `tCount`, `tOffset`: the leaf's run in the triangle arrays;
/// - `i`: leaf index into the box array;
/// - `nCount`: 4 bits per face `f` at bits `4f..4f+4` (face ids of `tables.rs`), holding
///   0 (root boundary), 1 (one same-size or larger neighbour), 4 (four half-size
///   neighbours, in `neighbor_slot` order) or [`LOCATE`] (unbalanced trees only: more
///   than four leaves touch the face, find the next leaf by point location);
/// - `N…`: the neighbours' record addresses, face 0 first, without padding.
pub const REC_T_COUNT: usize = 0;
/// Word offset of `tOffset` in a record.
pub const REC_T_OFFSET: usize = 1;
/// Word offset of the leaf index `i` in a record.
pub const REC_LEAF: usize = 2;
/// Word offset of `nCount` in a record.
pub const REC_N_COUNT: usize = 3;
/// Word offset of the first neighbour address in a record.
pub const REC_LINKS: usize = 4;

/// `nCount` nibble of a face whose neighbours are too many to link (unbalanced builds).
pub const LOCATE: u32 = 0xF;

/// Neighbour count of face `f` from a record's `nCount` word.
#[inline(always)]
pub fn nibble(n_count: u32, face: usize) -> u32 {
    (n_count >> (4 * face)) & 0xF
}

/// Number of link words stored before face `f`'s links (a nibble of [`LOCATE`] stores none).
#[inline(always)]
pub fn links_before(n_count: u32, face: usize) -> usize {
    (0..face).map(|k| link_words(nibble(n_count, k))).sum()
}

/// Link words a face with this nibble stores.
#[inline(always)]
pub fn link_words(n: u32) -> usize {
    if n == LOCATE {
        0
    } else {
        n as usize
    }
}

/// Box of one leaf, plus its integer cell so traversal can clamp point location to it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LeafBox {
    /// Smallest corner. Shared faces of adjacent leaves are bit-identical (see build.rs).
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
    /// `[x, y, z, depth]`: the cell at its own depth (coordinates `< 2^depth`).
    pub cell: [u16; 4],
}

// 24 bytes of box + 8 of cell, no padding. The paper used 16 (min + edge); we keep both
// corners so shared faces compare exactly, and the cell for clamped point location.
const _: () = assert!(std::mem::size_of::<LeafBox>() == 32);

impl LeafBox {
    /// The box as an [`Aabb`].
    #[inline(always)]
    pub fn aabb(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }

    /// Depth of the leaf (root = 0).
    #[inline(always)]
    pub fn depth(&self) -> u32 {
        self.cell[3] as u32
    }
}

/// Internal node: eight child references, octant `bx | by<<1 | bz<<2` (bit set = upper
/// half on that axis). A reference with [`LEAF_BIT`] set is `LEAF_BIT | record address`,
/// otherwise the index of another internal node.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct InnerNode {
    /// Child references.
    pub child: [u32; 8],
}

// Eight u32: one 32-byte cache-line half per node.
const _: () = assert!(std::mem::size_of::<InnerNode>() == 32);

/// Marks a child reference (or the root reference) as a leaf record address.
pub const LEAF_BIT: u32 = 1 << 31;
