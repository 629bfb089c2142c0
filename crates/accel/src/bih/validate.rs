//! Self-check of a built or refitted BIH: structure, coverage, clip planes, depth.

use super::traverse::STACK;
use super::Bih;
use dynray_geom::Aabb;

/// A broken invariant, with the node where it was found.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("invalid BIH at node {node}: {what}")]
pub struct InvalidBih {
    /// Node index.
    pub node: usize,
    /// What is wrong, with the values.
    pub what: String,
}

impl Bih {
    /// Checks every invariant traversal relies on: the pre-order layout (left child =
    /// parent + 1, right child after the left subtree, or = parent + 1 in a one-child
    /// node whose other plane is infinite), leaves covering the primitive
    /// slots exactly once and in order, no empty leaf, every triangle inside its parents'
    /// clip planes, the scene box holding everything, depth within the traversal stack,
    /// and `prim_ids` a permutation of the mesh's triangles.
    pub(crate) fn check_invariants(&self) -> Result<(), InvalidBih> {
        let err = |node: usize, what: String| Err(InvalidBih { node, what });
        if self.nodes.is_empty() {
            return err(0, "no nodes".into());
        }
        let mut seen = vec![false; self.prim_ids.len()];
        for &id in &self.prim_ids {
            match seen.get_mut(id as usize) {
                Some(s) if !*s => *s = true,
                _ => return err(0, format!("prim_ids is not a permutation (triangle {id})")),
            }
        }
        if self.tris.len() != self.prim_ids.len() {
            return err(0, format!("{} triangles but {} ids", self.tris.len(), self.prim_ids.len()));
        }
        let mut next_slot = 0usize;
        let (end, bounds, depth) = self.check(0, 0, &mut next_slot)?;
        if end != self.nodes.len() {
            return err(end, format!("{} nodes stored, {end} reachable", self.nodes.len()));
        }
        if next_slot != self.tris.len() {
            return err(0, format!("leaves cover {next_slot} of {} triangles", self.tris.len()));
        }
        if depth != self.depth || depth as usize > STACK {
            return err(0, format!("depth {depth} (recorded {}), stack holds {STACK}", self.depth));
        }
        if !self.bounds.contains(&bounds) {
            return err(0, format!("scene box {:?} does not hold {:?}", self.bounds, bounds));
        }
        Ok(())
    }

    /// Checks the subtree at `i`; returns (one past its last node, its triangles' box,
    /// its deepest leaf's depth counted from the root).
    fn check(&self, i: usize, depth: u32, next_slot: &mut usize) -> Result<(usize, Aabb, u32), InvalidBih> {
        let err = |what: String| Err(InvalidBih { node: i, what });
        let Some(n) = self.nodes.get(i) else { return err("node index out of range".into()) };
        if depth as usize > STACK {
            return err(format!("depth {depth} exceeds the traversal stack ({STACK})"));
        }
        if n.is_leaf() {
            let (first, count) = (n.index() as usize, n.count as usize);
            if count == 0 || first != *next_slot || first + count > self.tris.len() {
                return err(format!("leaf [{first}, +{count}) but next slot is {next_slot}"));
            }
            *next_slot += count;
            let b = self.tris[first..first + count].iter().fold(Aabb::EMPTY, |b, t| b.union(&t.bounds()));
            return Ok((i + 1, b, depth));
        }
        if n.count != 0 {
            return err(format!("interior node with count {}", n.count));
        }
        let (lend, lb, ld) = self.check(i + 1, depth + 1, next_slot)?;
        let a = n.axis();
        if n.index() as usize == i + 1 {
            // One-child node: exactly one plane is infinite and the other bounds the child.
            let ok = match (n.clip[0] == f32::NEG_INFINITY, n.clip[1] == f32::INFINITY) {
                (false, true) => lb.max[a] <= n.clip[0],
                (true, false) => lb.min[a] >= n.clip[1],
                _ => false,
            };
            if !ok {
                return err(format!("one-child node with clip {:?} around child {lb:?} on axis {a}", n.clip));
            }
            return Ok((lend, lb, ld));
        }
        if n.index() as usize != lend {
            return err(format!("right child {} but left subtree ends at {lend}", n.index()));
        }
        let (rend, rb, rd) = self.check(lend, depth + 1, next_slot)?;
        if lb.max[a] > n.clip[0] || rb.min[a] < n.clip[1] {
            return err(format!(
                "clip planes {:?} on axis {a} do not bound the children ({} / {})",
                n.clip, lb.max[a], rb.min[a]
            ));
        }
        Ok((rend, lb.union(&rb), ld.max(rd)))
    }
}
