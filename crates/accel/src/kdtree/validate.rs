//! Self-checks of a built kd-tree and its ropes, and the figures `stats()` reports.

use super::node::{LeafRopes, NO_ROPE};
use super::traverse::STACK_SIZE;
use super::tree::Tree;
use crate::AccelStats;
use dynray_geom::Aabb;

impl Tree {
    /// Checks every invariant the traversals rely on; the message names the first broken
    /// one with its values.
    pub(crate) fn check_invariants(&self) -> Result<(), String> {
        let n_nodes = self.nodes.len();
        let n_leaves = self.leaf_count();
        if n_nodes == 0 {
            return Err("no nodes".into());
        }
        // Structure first, so that the walk below terminates: children after parents.
        for (i, n) in self.nodes.iter().enumerate() {
            if n.is_leaf() {
                if n.leaf_index() as usize >= n_leaves {
                    return Err(format!("node {i}: leaf index {} of {n_leaves}", n.leaf_index()));
                }
            } else if !(n.right() as usize > i + 1 && (n.right() as usize) < n_nodes) {
                return Err(format!("node {i}: right child {} not in ({}, {n_nodes})", n.right(), i + 1));
            }
        }
        if self.leaf_starts[0] != 0 || self.leaf_starts.windows(2).any(|w| w[0] > w[1]) {
            return Err("leaf ranges are not consecutive".into());
        }
        if *self.leaf_starts.last().unwrap() as usize != self.prim_ids.len() {
            return Err("leaf ranges do not end at the reference count".into());
        }
        let mut seen_node = vec![false; n_nodes];
        let mut seen_leaf = vec![false; n_leaves];
        let mut referenced = vec![false; self.tris.len()];
        let mut depth = 0;
        let mut err = None;
        self.walk(|i, b, d| {
            if err.is_some() {
                return;
            }
            depth = depth.max(d);
            if std::mem::replace(&mut seen_node[i as usize], true) {
                err = Some(format!("node {i} reached twice"));
                return;
            }
            let n = self.nodes[i as usize];
            if !n.is_leaf() {
                let (a, p) = (n.axis(), n.split());
                if !(p > b.min[a] && p < b.max[a]) {
                    err = Some(format!("node {i}: split {p} on axis {a} not inside ({}, {})", b.min[a], b.max[a]));
                }
                return;
            }
            let leaf = n.leaf_index();
            if std::mem::replace(&mut seen_leaf[leaf as usize], true) {
                err = Some(format!("leaf {leaf} reached twice"));
                return;
            }
            let prims = self.leaf_prims(leaf);
            if prims.windows(2).any(|w| w[0] >= w[1]) {
                err = Some(format!("leaf {leaf}: references not strictly ascending"));
                return;
            }
            for &p in prims {
                let Some(tri) = self.tris.get(p as usize) else {
                    err = Some(format!("leaf {leaf}: triangle {p} of {}", self.tris.len()));
                    return;
                };
                referenced[p as usize] = true;
                if tri.bounds().intersection(b).is_empty() {
                    err = Some(format!("leaf {leaf}: triangle {p} lies outside the leaf box {b:?}"));
                    return;
                }
            }
        });
        if let Some(e) = err {
            return Err(e);
        }
        if let Some(i) = seen_node.iter().position(|&s| !s) {
            return Err(format!("node {i} unreachable"));
        }
        if let Some(i) = referenced.iter().position(|&s| !s) {
            return Err(format!("triangle {i} referenced by no leaf"));
        }
        if depth != self.depth || depth as usize >= STACK_SIZE {
            return Err(format!("depth {depth} (recorded {}), stack holds {STACK_SIZE}", self.depth));
        }
        Ok(())
    }

    /// Checks that every rope crosses exactly its leaf's face and lands on the deepest
    /// node covering it, and that only faces on the root's boundary have none.
    pub(crate) fn check_ropes(&self, ropes: &[LeafRopes]) -> Result<(), String> {
        if ropes.len() != self.leaf_count() {
            return Err(format!("{} rope records for {} leaves", ropes.len(), self.leaf_count()));
        }
        let mut boxes = vec![Aabb::EMPTY; self.nodes.len()];
        self.walk(|i, b, _| boxes[i as usize] = *b);
        for (leaf, lr) in ropes.iter().enumerate() {
            for (face, &rope) in lr.ropes.iter().enumerate() {
                let (a, upper) = (face / 2, face % 2 == 1);
                let plane = if upper { lr.bounds.max[a] } else { lr.bounds.min[a] };
                let on_root = plane == if upper { self.bounds.max[a] } else { self.bounds.min[a] };
                if rope == NO_ROPE {
                    if !on_root {
                        return Err(format!("leaf {leaf} face {face}: no rope inside the root box"));
                    }
                    continue;
                }
                let Some(t) = boxes.get(rope as usize) else {
                    return Err(format!("leaf {leaf} face {face}: rope {rope} out of range"));
                };
                let beside = if upper { t.min[a] == plane } else { t.max[a] == plane };
                let covers =
                    (0..3).filter(|&k| k != a).all(|k| t.min[k] <= lr.bounds.min[k] && t.max[k] >= lr.bounds.max[k]);
                if !beside || !covers {
                    return Err(format!(
                        "leaf {leaf} face {face}: rope node {rope} box {t:?} misses face of {:?}",
                        lr.bounds
                    ));
                }
                let n = self.nodes[rope as usize];
                let cuts_face = !n.is_leaf()
                    && n.axis() != a
                    && n.split() > lr.bounds.min[n.axis()]
                    && n.split() < lr.bounds.max[n.axis()];
                if !n.is_leaf() && !cuts_face {
                    return Err(format!("leaf {leaf} face {face}: rope node {rope} could be pushed deeper"));
                }
            }
        }
        Ok(())
    }

    /// Shape figures; `extra_bytes` is what a variant adds (ropes).
    pub fn stats(&self, extra_bytes: usize) -> AccelStats {
        let mut sizes = crate::LeafSizes::new();
        let mut empty = 0;
        for l in 0..self.leaf_count() as u32 {
            let k = self.leaf_prims(l).len();
            sizes.add(k);
            empty += (k == 0) as usize;
        }
        let leaf_sizes = sizes.finish();
        let root_area = self.bounds.surface_area() as f64;
        let p = &self.params;
        let mut sah = 0.0f64;
        self.walk(|i, b, _| {
            let n = self.nodes[i as usize];
            let area = b.surface_area() as f64;
            sah += if n.is_leaf() {
                area * p.intersection_cost as f64 * self.leaf_prims(n.leaf_index()).len() as f64
            } else {
                area * p.traversal_cost as f64
            };
        });
        let refs = self.prim_ids.len();
        let memory = self.memory_bytes() + extra_bytes;
        AccelStats {
            nodes: self.nodes.len(),
            leaves: self.leaf_count(),
            max_depth: self.depth,
            primitive_refs: refs,
            leaf_sizes,
            sah_cost: (root_area > 0.0).then(|| sah / root_area),
            memory_bytes: memory,
            extra: vec![
                ("empty leaves".into(), empty.to_string()),
                ("refs per triangle".into(), format!("{:.3}", refs as f64 / self.tris.len() as f64)),
                ("depth limit".into(), p.depth_limit(self.tris.len()).to_string()),
                ("rope bytes".into(), extra_bytes.to_string()),
            ],
        }
    }
}
