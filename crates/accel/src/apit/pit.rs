//! The pseudo-interval tree (PIT) of seed 004: an interval tree built online, one
//! interval at a time, with midpoint discriminants and unsorted per-node lists, queried
//! without a stack by climbing parent pointers.
//!
//! Many trees (one per pixel) share one node array and one fragment array; a tree is
//! named by its root index. Invariant (checked by [`IntervalForest::validate_tree`]):
//! every fragment of a node contains the node's discriminant, every fragment of its left
//! subtree ends before it, every fragment of its right subtree starts after it.

use super::node::{Fragment, PitNode, NONE};
use crate::Counter;
use std::ops::ControlFlow;

/// Shape of one tree, as measured by [`IntervalForest::validate_tree`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TreeShape {
    /// Nodes in the tree.
    pub nodes: u32,
    /// Fragments in the tree.
    pub fragments: u32,
    /// Depth of the deepest node (root = 0).
    pub depth: u32,
}

/// Pseudo-interval trees over a shared fragment array.
#[derive(Clone, Debug, Default)]
pub struct IntervalForest {
    /// All nodes of all trees.
    pub nodes: Vec<PitNode>,
    /// All fragments; `next` links the fragments of one node.
    pub frags: Vec<Fragment>,
}

impl IntervalForest {
    /// A forest over `frags`, none of them inserted yet.
    pub fn with_fragments(frags: Vec<Fragment>) -> Self {
        Self { nodes: Vec::new(), frags }
    }

    /// Inserts fragment `frag` (with `zmin <= zmax`) into the tree rooted at `*root`
    /// (`NONE`: empty tree) and returns the depth of the node that stores it. Walks down from the root: a node
    /// whose discriminant the interval contains keeps it (prepended to its list);
    /// otherwise the interval goes left (it ends before) or right (it starts after); an
    /// empty place gets a new node whose discriminant is the interval's midpoint.
    pub fn insert(&mut self, root: &mut u32, frag: u32) -> u32 {
        let Fragment { zmin, zmax, .. } = self.frags[frag as usize];
        debug_assert!(zmin <= zmax, "fragment {frag}: [{zmin}, {zmax}]");
        let mut parent = NONE;
        let mut cur = *root;
        let mut went_left = false;
        let mut depth = 0;
        while cur != NONE {
            let n = &mut self.nodes[cur as usize];
            if zmin <= n.disc && n.disc <= zmax {
                self.frags[frag as usize].next = n.first;
                n.first = frag;
                return depth;
            }
            parent = cur;
            went_left = zmax < n.disc;
            cur = if went_left { n.left } else { n.right };
            depth += 1;
        }
        // Midpoint in f64, rounded into the interval (it is one of its points); max/min
        // rather than clamp, which would panic on a reversed interval.
        let disc = (((zmin as f64 + zmax as f64) * 0.5) as f32).max(zmin).min(zmax);
        let id = self.nodes.len() as u32;
        self.nodes.push(PitNode { disc, left: NONE, right: NONE, parent, first: frag });
        self.frags[frag as usize].next = NONE;
        if parent == NONE {
            *root = id;
        } else if went_left {
            self.nodes[parent as usize].left = id;
        } else {
            self.nodes[parent as usize].right = id;
        }
        depth
    }

    /// Calls `visit` with the index of every fragment of the tree at `root` whose interval
    /// meets `[qa, qb]`, until it breaks; counts visited nodes and reported fragments. Preorder without a stack, as in the seed: a
    /// node's list is scanned when the walk arrives from its parent; the left subtree
    /// can hold overlaps only if `qa < disc`, the right one only if `qb > disc`.
    #[inline]
    pub fn query<C: Counter>(
        &self,
        root: u32,
        qa: f32,
        qb: f32,
        c: &mut C,
        mut visit: impl FnMut(u32) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let mut cur = root;
        let mut from = NONE;
        // Each step crosses a tree edge, each edge at most twice: this bounds any tree.
        let mut steps = 2 * self.nodes.len() + 2;
        while cur != NONE && steps > 0 {
            steps -= 1;
            let n = &self.nodes[cur as usize];
            let next = if from == n.parent {
                c.node();
                let mut f = n.first;
                while f != NONE {
                    let fr = &self.frags[f as usize];
                    if fr.overlaps(qa, qb) {
                        c.triangles(1);
                        visit(f)?;
                    }
                    f = fr.next;
                }
                if qa < n.disc && n.left != NONE {
                    n.left
                } else if qb > n.disc && n.right != NONE {
                    n.right
                } else {
                    n.parent
                }
            } else if from == n.left && qb > n.disc && n.right != NONE {
                n.right
            } else {
                n.parent
            };
            from = cur;
            cur = next;
        }
        ControlFlow::Continue(())
    }

    /// Checks the tree at `root`: parent links, child order, every fragment inside its
    /// node's constraints, list lengths bounded. Returns its shape, or what is broken.
    /// `seen_nodes` / `seen_frags` (sized like the arrays) catch sharing between trees.
    pub fn validate_tree(
        &self,
        root: u32,
        seen_nodes: &mut [bool],
        seen_frags: &mut [bool],
    ) -> Result<TreeShape, String> {
        let mut shape = TreeShape::default();
        if root == NONE {
            return Ok(shape);
        }
        // (node, parent, exclusive lower bound, exclusive upper bound, depth)
        let mut stack = vec![(root, NONE, f32::NEG_INFINITY, f32::INFINITY, 0u32)];
        while let Some((id, parent, lo, hi, depth)) = stack.pop() {
            let n = self.nodes.get(id as usize).ok_or_else(|| format!("node {id} out of range"))?;
            if std::mem::replace(&mut seen_nodes[id as usize], true) {
                return Err(format!("node {id} reached twice"));
            }
            if n.parent != parent {
                return Err(format!("node {id}: parent {} but reached from {parent}", n.parent));
            }
            if !(n.disc > lo && n.disc < hi) {
                return Err(format!("node {id}: discriminant {} outside ({lo}, {hi})", n.disc));
            }
            shape.nodes += 1;
            shape.depth = shape.depth.max(depth);
            let mut f = n.first;
            if f == NONE {
                return Err(format!("node {id} has no fragment"));
            }
            while f != NONE {
                let fr = self.frags.get(f as usize).ok_or_else(|| format!("node {id}: fragment {f} out of range"))?;
                if std::mem::replace(&mut seen_frags[f as usize], true) {
                    return Err(format!("fragment {f} reached twice"));
                }
                if !(fr.zmin <= n.disc && n.disc <= fr.zmax && fr.zmin > lo && fr.zmax < hi) {
                    return Err(format!(
                        "fragment {f} [{}, {}] in node {id} (disc {}, bounds ({lo}, {hi}))",
                        fr.zmin, fr.zmax, n.disc
                    ));
                }
                shape.fragments += 1;
                f = fr.next;
            }
            if n.left != NONE {
                stack.push((n.left, id, lo, n.disc, depth + 1));
            }
            if n.right != NONE {
                stack.push((n.right, id, n.disc, hi, depth + 1));
            }
        }
        Ok(shape)
    }
}
