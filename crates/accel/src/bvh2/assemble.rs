//! The builder's output before it is one array: the top of the tree (nodes built with
//! `rayon::join`) as linked pairs, its subtrees as node vectors each built by one thread
//! in final order. [`assemble`] writes them into one array in the depth-first order the
//! old scratch-and-compact builder produced (children pairs adjacent, a pair followed by
//! the left child's descendants, then the right one's), so the array does not depend on
//! the thread count, and no `(2n − 1)`-slot scratch array is zeroed and faulted in.

use super::BvhNode;
use dynray_geom::Aabb;

/// A built subtree.
pub(super) enum Part {
    /// Root at `nodes[0]`, descendants after it; interior `index` fields count from
    /// `nodes[0]`, leaf ones are global triangle indices. `deepest`: depth of its deepest
    /// leaf in the whole tree.
    Nodes { nodes: Vec<BvhNode>, deepest: u32 },
    /// An interior node over two parts.
    Pair { bounds: Aabb, kids: Box<[Part; 2]> },
}

/// The node array of the tree `root` (`count` nodes) and the depth of its deepest leaf.
/// One sequential pass of appends: the array is written once, never zeroed first.
pub(super) fn assemble(root: Part, count: usize) -> (Vec<BvhNode>, u32) {
    let mut out = Vec::with_capacity(count);
    out.push(BvhNode::default());
    let depth = place(root, 0, &mut out);
    debug_assert_eq!(out.len(), count);
    (out, depth)
}

/// Writes `part`'s root into `out[slot]` and appends its descendants; returns the depth
/// of its deepest leaf.
fn place(part: Part, slot: usize, out: &mut Vec<BvhNode>) -> u32 {
    match part {
        Part::Nodes { nodes, deepest } => {
            // Local index i >= 1 lands at global out.len() + i - 1.
            let shift = (out.len() - 1) as u32;
            out[slot] = global(nodes[0], shift);
            out.extend(nodes[1..].iter().map(|&n| global(n, shift)));
            deepest
        }
        Part::Pair { bounds, kids } => {
            let [l, r] = *kids;
            let at = out.len();
            out.extend([BvhNode::default(); 2]);
            out[slot] = BvhNode::interior(&bounds, at as u32);
            place(l, at, out).max(place(r, at + 1, out))
        }
    }
}

/// `n` with its interior link moved by `shift` (leaf links are already global).
fn global(mut n: BvhNode, shift: u32) -> BvhNode {
    if !n.is_leaf() {
        n.index += shift;
    }
    n
}
