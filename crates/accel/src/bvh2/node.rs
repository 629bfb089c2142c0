//! The flat 32-byte BVH node: a box and two `u32`s that say interior or leaf.

use bytemuck::{Pod, Zeroable};
use dynray_geom::{Aabb, Vec3};

/// One node of the flat node array. The root is node 0.
///
/// Encoding (seed 003 §3.5, with the flag the seed left open made explicit):
/// - `count == 0` ⇒ interior: the left child is `nodes[index]`, the right child is
///   `nodes[index + 1]` (children are always allocated as an adjacent pair);
/// - `count > 0` ⇒ leaf: triangles `index .. index + count` of the leaf-ordered arrays.
///
/// `min`/`index` and `max`/`count` form two 16-byte halves, so the GPU reads a node as two
/// `vec4`s and the CPU traversal can pick a box plane by offset (`0..3` or `4..7`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    /// Smallest corner of the box.
    pub min: [f32; 3],
    /// Interior: index of the left child. Leaf: first triangle.
    pub index: u32,
    /// Largest corner of the box.
    pub max: [f32; 3],
    /// 0 for an interior node, else the number of triangles in the leaf.
    pub count: u32,
}

// Two 16-byte halves, no padding: one cache line holds a sibling pair and the GPU reads
// the node unchanged as two vec4 (seed 003 §3.5's "2 × float4").
const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);

impl BvhNode {
    /// An interior node whose children are `nodes[left]` and `nodes[left + 1]`.
    pub fn interior(bounds: &Aabb, left: u32) -> Self {
        Self { min: bounds.min.to_array(), index: left, max: bounds.max.to_array(), count: 0 }
    }

    /// A leaf over triangles `first .. first + count` (`count >= 1`).
    pub fn leaf(bounds: &Aabb, first: u32, count: u32) -> Self {
        debug_assert!(count > 0, "a leaf holds at least one triangle");
        Self { min: bounds.min.to_array(), index: first, max: bounds.max.to_array(), count }
    }

    /// True for a leaf.
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.count != 0
    }

    /// The node's box.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::from_array(self.min), Vec3::from_array(self.max))
    }

    /// Replaces the node's box, keeping its links.
    #[inline]
    pub fn set_bounds(&mut self, b: &Aabb) {
        self.min = b.min.to_array();
        self.max = b.max.to_array();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoding_round_trips() {
        let b = Aabb::new(Vec3::new(-1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.5));
        let i = BvhNode::interior(&b, 7);
        assert!(!i.is_leaf());
        assert_eq!((i.index, i.bounds()), (7, b));
        let l = BvhNode::leaf(&b, 11, 3);
        assert!(l.is_leaf());
        assert_eq!((l.index, l.count, l.bounds()), (11, 3, b));
    }

    #[test]
    fn byte_layout_is_two_vec4() {
        let n = BvhNode::leaf(&Aabb::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0)), 9, 2);
        let w: [u32; 8] = bytemuck::cast(n);
        assert_eq!(f32::from_bits(w[0]), 1.0);
        assert_eq!(w[3], 9);
        assert_eq!(f32::from_bits(w[6]), 6.0);
        assert_eq!(w[7], 2);
    }
}
