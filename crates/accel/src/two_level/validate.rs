//! What a two-level structure checks of itself: the top tree (every instance in one leaf,
//! child boxes inside parents, depth within the stack), instance boxes holding their
//! parts, every frame triangle held exactly once, world-space parts holding the frame's
//! own vertex values, and each part's own validation.

use super::{PartSpace, TwoLevel};
use crate::BvhNode;
use dynray_geom::TriangleMesh;

/// Depth of the deepest top-level leaf (root = 0; 0 for an empty tree).
pub(crate) fn top_depth(top: &[BvhNode]) -> u32 {
    let mut deepest = 0;
    let mut todo = if top.is_empty() { vec![] } else { vec![(0usize, 0u32)] };
    while let Some((n, d)) = todo.pop() {
        deepest = deepest.max(d);
        if !top[n].is_leaf() {
            let l = top[n].index as usize;
            todo.push((l, d + 1));
            todo.push((l + 1, d + 1));
        }
    }
    deepest
}

impl TwoLevel {
    /// Checks the invariants against `mesh`, the frame last built or updated on.
    pub(crate) fn check(&self, mesh: &TriangleMesh) -> Result<(), String> {
        if mesh.triangle_count() as u32 != self.triangles {
            return Err(format!("built over {} triangles, mesh has {}", self.triangles, mesh.triangle_count()));
        }
        // The top tree: each instance reached once, boxes nested.
        let mut seen = vec![false; self.instances.len()];
        let mut todo = if self.top.is_empty() { vec![] } else { vec![(0usize, 0u32)] };
        while let Some((n, depth)) = todo.pop() {
            if depth as usize >= super::top::STACK {
                return Err(format!("top node {n} at depth {depth}, beyond the stack of {}", super::top::STACK));
            }
            let node = self.top.get(n).ok_or(format!("top node {n} out of range"))?;
            if node.is_leaf() {
                let i = *self.order.get(node.index as usize).ok_or(format!("leaf {n}: bad order index"))? as usize;
                let inst = self.instances.get(i).ok_or(format!("leaf {n}: instance {i} out of range"))?;
                if std::mem::replace(&mut seen[i], true) {
                    return Err(format!("instance {i} in two leaves"));
                }
                if !node.bounds().contains(&inst.bounds) {
                    return Err(format!("leaf {n}'s box does not hold instance {i}'s"));
                }
            } else {
                let l = node.index as usize;
                for c in [l, l + 1] {
                    let child = self.top.get(c).ok_or(format!("node {n}: child {c} out of range"))?;
                    if !node.bounds().contains(&child.bounds()) {
                        return Err(format!("node {n}: child {c} outside its box"));
                    }
                    todo.push((c, depth + 1));
                }
            }
        }
        if let Some(i) = seen.iter().position(|s| !s) {
            return Err(format!("instance {i} reached by no leaf"));
        }
        // Every frame triangle held once.
        let mut held = vec![0u8; mesh.triangle_count()];
        for (k, inst) in self.instances.iter().enumerate() {
            let part = self.parts.get(inst.part as usize).ok_or(format!("instance {k}: no part {}", inst.part))?;
            let n = part.live.triangle_count() as u32;
            let prims: Box<dyn Iterator<Item = u32>> = match &part.space {
                PartSpace::World { prims, .. } => Box::new(prims.iter().copied()),
                PartSpace::Local { .. } => Box::new(inst.first_prim..inst.first_prim + n),
            };
            for p in prims {
                let h = held.get_mut(p as usize).ok_or(format!("instance {k}: triangle {p} out of range"))?;
                *h += 1;
            }
            let expected = match inst.to_world {
                Some(m) => super::transformed_bounds(&part.bounds, &m),
                None => part.bounds,
            };
            if inst.bounds != expected {
                return Err(format!("instance {k}'s box is not its part's (placed)"));
            }
        }
        if let Some(p) = held.iter().position(|&h| h != 1) {
            return Err(format!("frame triangle {p} held {} times", held[p]));
        }
        // World parts hold the frame's own vertices; each part checks itself.
        for (k, part) in self.parts.iter().enumerate() {
            let own = part.live.mesh();
            if let PartSpace::World { prims, .. } = &part.space {
                for (i, &p) in prims.iter().enumerate() {
                    if own.triangle(i) != mesh.triangle(p as usize) {
                        return Err(format!("part {k}: triangle {i} differs from frame triangle {p}"));
                    }
                }
            }
            part.live.accel().validate(&own).map_err(|e| format!("part {k}: {e}"))?;
        }
        Ok(())
    }
}
