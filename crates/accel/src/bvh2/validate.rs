//! Self-check of a built or refitted BVH, which also measures its shape.

use super::{traverse::STACK_CAPACITY, Bvh};
use dynray_geom::TriangleMesh;

/// A broken invariant, with the node where it was found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("BVH invariant broken at node {node}: {what}")]
pub struct InvalidBvh {
    /// Index of the offending node (0 for array-level problems).
    pub node: u32,
    /// What is wrong, with the values involved.
    pub what: String,
}

/// Shape and quality of a valid tree.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BvhStats {
    /// All nodes, leaves included.
    pub nodes: usize,
    /// Leaves.
    pub leaves: usize,
    /// Depth of the deepest leaf (root = 0).
    pub max_depth: u32,
    /// As [`crate::AccelStats::leaf_sizes`] (built by [`crate::LeafSizes`]).
    pub leaf_sizes: Vec<usize>,
    /// SAH cost (Eq. 2.1 summed over the tree with the build's `K_T`, `K_I`), relative to
    /// the root's area; `None` when the root box has no area.
    pub sah_cost: Option<f64>,
}

impl Bvh {
    /// Checks every structural invariant (children inside parents and after them in the
    /// array, every node reached once, every leaf-order triangle referenced exactly once,
    /// ids a permutation, indices in range, depth within the traversal stack) and that the
    /// leaf triangles are exact copies of `mesh`'s. Returns the tree's shape.
    pub(crate) fn check_invariants(&self, mesh: &TriangleMesh) -> Result<BvhStats, InvalidBvh> {
        let stats = self.check_shape()?;
        if mesh.triangle_count() != self.tris.len() {
            return Err(bad(0, format!("mesh has {} triangles, tree {}", mesh.triangle_count(), self.tris.len())));
        }
        for (i, (t, &id)) in self.tris.iter().zip(&self.ids).enumerate() {
            if *t != mesh.triangle(id as usize) {
                return Err(bad(0, format!("leaf triangle {i} is not a copy of mesh triangle {id}")));
            }
        }
        Ok(stats)
    }

    /// The invariants that need no mesh; also what [`crate::Accel::stats`] reports.
    pub(super) fn check_shape(&self) -> Result<BvhStats, InvalidBvh> {
        let (nodes, n) = (&self.nodes, self.tris.len());
        if nodes.is_empty() || n == 0 || self.ids.len() != n {
            return Err(bad(0, format!("{} nodes, {} triangles, {} ids", nodes.len(), n, self.ids.len())));
        }
        let mut seen_id = vec![false; n];
        for &id in &self.ids {
            if id as usize >= n || std::mem::replace(&mut seen_id[id as usize], true) {
                return Err(bad(0, format!("triangle id {id} out of range or repeated")));
            }
        }
        let root_area = nodes[0].bounds().surface_area() as f64;
        let (kt, ki) = (self.params.traversal_cost as f64, self.params.intersection_cost as f64);
        let mut sah = 0.0f64;
        let mut stats = BvhStats::default();
        let mut sizes = crate::LeafSizes::new();
        let mut covered = vec![false; n];
        let mut reached = vec![false; nodes.len()];
        reached[0] = true;
        let mut stack = vec![(0usize, 0u32)];
        while let Some((i, depth)) = stack.pop() {
            let node = &nodes[i];
            let b = node.bounds();
            if b.is_empty() {
                return Err(bad(i, format!("empty box {b:?}")));
            }
            stats.nodes += 1;
            stats.max_depth = stats.max_depth.max(depth);
            let area = b.surface_area() as f64;
            if node.is_leaf() {
                let (first, count) = (node.index as usize, node.count as usize);
                if first + count > n {
                    return Err(bad(i, format!("leaf range {first}..{} beyond {n} triangles", first + count)));
                }
                for (k, t) in self.tris[first..first + count].iter().enumerate() {
                    if std::mem::replace(&mut covered[first + k], true) {
                        return Err(bad(i, format!("triangle slot {} in two leaves", first + k)));
                    }
                    if !b.contains(&t.bounds()) {
                        return Err(bad(i, format!("triangle slot {} sticks out of {b:?}", first + k)));
                    }
                }
                stats.leaves += 1;
                sizes.add(count);
                sah += ki * count as f64 * area;
            } else {
                let l = node.index as usize;
                if l <= i || l + 1 >= nodes.len() {
                    return Err(bad(
                        i,
                        format!("children {l}, {} out of range (parent {i}, {} nodes)", l + 1, nodes.len()),
                    ));
                }
                if depth as usize + 1 >= STACK_CAPACITY {
                    return Err(bad(i, format!("depth {} reaches the stack capacity {STACK_CAPACITY}", depth + 1)));
                }
                for c in [l, l + 1] {
                    if std::mem::replace(&mut reached[c], true) {
                        return Err(bad(i, format!("child {c} has two parents")));
                    }
                    if !b.contains(&nodes[c].bounds()) {
                        return Err(bad(i, format!("child {c} box {:?} outside {b:?}", nodes[c].bounds())));
                    }
                    stack.push((c, depth + 1));
                }
                sah += kt * area;
            }
        }
        if stats.nodes != nodes.len() {
            return Err(bad(0, format!("{} of {} nodes unreachable", nodes.len() - stats.nodes, nodes.len())));
        }
        if let Some(slot) = covered.iter().position(|c| !c) {
            return Err(bad(0, format!("triangle slot {slot} in no leaf")));
        }
        if stats.max_depth != self.depth {
            return Err(bad(
                0,
                format!("recorded depth {} but the deepest leaf is at {}", self.depth, stats.max_depth),
            ));
        }
        stats.leaf_sizes = sizes.finish();
        stats.sah_cost = (root_area > 0.0).then(|| sah / root_area);
        Ok(stats)
    }
}

fn bad(node: usize, what: String) -> InvalidBvh {
    InvalidBvh { node: node as u32, what }
}
