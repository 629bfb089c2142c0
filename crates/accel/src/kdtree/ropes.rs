//! Rope construction with the Ropes++ optimisation (Popov, Günther, Seidel, Slusallek,
//! "Stackless KD-Tree Traversal for High Performance GPU Ray Tracing", EG 2007, §3).
//!
//! Ropes are passed down from the root: a node's children inherit its ropes, and each
//! child's rope across the split plane names its sibling. Before a node passes its ropes
//! on, each one is pushed down the neighbour's subtree as long as a single child still
//! covers the whole face ("Ropes++"): a child beside the face when the neighbour's split
//! is parallel to it, otherwise the child on whose side the whole face lies. The rope
//! then lands on the deepest node adjacent to the entire face, so a traversal that
//! follows it has the fewest nodes left to descend.

use super::node::{LeafRopes, NO_ROPE};
use super::tree::Tree;
use dynray_geom::Aabb;

/// The rope record of every leaf, by leaf index.
pub fn build_ropes(tree: &Tree) -> Vec<LeafRopes> {
    let mut out = vec![LeafRopes { bounds: Aabb::EMPTY, ropes: [NO_ROPE; 6] }; tree.leaf_count()];
    // Explicit stack: (node, box, ropes inherited from the parent).
    let mut stack = vec![(0u32, tree.bounds, [NO_ROPE; 6])];
    while let Some((i, b, mut ropes)) = stack.pop() {
        for (face, rope) in ropes.iter_mut().enumerate() {
            *rope = optimise(tree, *rope, face, &b);
        }
        let n = tree.nodes[i as usize];
        if n.is_leaf() {
            out[n.leaf_index() as usize] = LeafRopes { bounds: b, ropes };
            continue;
        }
        let (a, p) = (n.axis(), n.split());
        let (left, right) = (i + 1, n.right());
        let (mut lb, mut rb) = (b, b);
        lb.max[a] = p;
        rb.min[a] = p;
        let mut lr = ropes;
        lr[2 * a + 1] = right;
        let mut rr = ropes;
        rr[2 * a] = left;
        stack.push((right, rb, rr));
        stack.push((left, lb, lr));
    }
    out
}

/// Pushes a rope across face `face` of box `b` down to the deepest node that still
/// covers the whole face.
fn optimise(tree: &Tree, mut rope: u32, face: usize, b: &Aabb) -> u32 {
    let face_axis = face / 2;
    while rope != NO_ROPE {
        let n = tree.nodes[rope as usize];
        if n.is_leaf() {
            break;
        }
        let (a, p) = (n.axis(), n.split());
        let (left, right) = (rope + 1, n.right());
        rope = if a == face_axis {
            // The neighbour lies below a min face (take its upper child) or above a max face.
            if face & 1 == 0 {
                right
            } else {
                left
            }
        } else if p >= b.max[a] {
            left
        } else if p <= b.min[a] {
            right
        } else {
            break;
        };
    }
    rope
}
