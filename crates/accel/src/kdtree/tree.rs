//! The arrays of a built kd-tree, shared by the standard and the Ropes++ traversal.

use super::node::KdNode;
use super::params::KdTreeParams;
use dynray_geom::{Aabb, Triangle};

/// A built kd-tree: nodes depth-first, leaf ranges, triangle references, and one copy of
/// each triangle in mesh order.
///
/// Triangles are shared by index (`tris[prim_ids[k]]`) rather than copied per reference:
/// with 2–3 references per triangle a per-reference copy would cost 36 bytes each instead
/// of 4, and the traversal needs the index anyway for the tie-break.
#[derive(Clone, Debug)]
pub struct Tree {
    /// Nodes; the root is node 0.
    pub nodes: Vec<KdNode>,
    /// Leaf `i` references `prim_ids[leaf_starts[i]..leaf_starts[i + 1]]`.
    pub leaf_starts: Vec<u32>,
    /// Triangle indices, leaf by leaf, ascending within a leaf.
    pub prim_ids: Vec<u32>,
    /// The mesh's triangles in mesh order.
    pub tris: Vec<Triangle>,
    /// The root's box: the box of all triangles.
    pub bounds: Aabb,
    /// Depth of the deepest leaf (root = 0).
    pub depth: u32,
    /// Parameters the tree was built with (`update` rebuilds with them).
    pub params: KdTreeParams,
}

impl Tree {
    /// Number of leaves.
    pub fn leaf_count(&self) -> usize {
        self.leaf_starts.len() - 1
    }

    /// Triangle references of leaf `leaf`.
    #[inline(always)]
    pub fn leaf_prims(&self, leaf: u32) -> &[u32] {
        let l = leaf as usize;
        &self.prim_ids[self.leaf_starts[l] as usize..self.leaf_starts[l + 1] as usize]
    }

    /// Bytes of every array.
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.nodes.len() * size_of::<KdNode>()
            + self.leaf_starts.len() * size_of::<u32>()
            + self.prim_ids.len() * size_of::<u32>()
            + self.tris.len() * size_of::<Triangle>()
    }

    /// Calls `f(node index, node box, depth)` for every node, parents before children.
    pub fn walk(&self, mut f: impl FnMut(u32, &Aabb, u32)) {
        let mut stack = vec![(0u32, self.bounds, 0u32)];
        while let Some((i, b, d)) = stack.pop() {
            f(i, &b, d);
            let n = self.nodes[i as usize];
            if !n.is_leaf() {
                let (mut l, mut r) = (b, b);
                l.max[n.axis()] = n.split();
                r.min[n.axis()] = n.split();
                stack.push((n.right(), r, d + 1));
                stack.push((i + 1, l, d + 1));
            }
        }
    }
}
