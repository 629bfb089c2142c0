//! BIH refit: new clip planes for moved vertices, same topology (`Accel::update`).
//!
//! The seed rebuilds every frame; a refit is the cheaper alternative W-K mention for
//! small motions. The tree keeps its triangle-to-leaf assignment; each clip plane becomes
//! again the exact extent of its subtree's triangles on the node's axis, so traversal
//! stays exact (only its efficiency degrades as the motion grows). Subtrees are
//! disjoint slices of the pre-order node array, so the top levels refit in parallel.

use super::node::BihNode;
use super::Bih;
use crate::BuildError;
use dynray_geom::{Aabb, Triangle, TriangleMesh};
use rayon::prelude::*;

/// Subtrees with at least this many nodes refit their two halves with `rayon::join`.
const PARALLEL_MIN: usize = 2048;

impl Bih {
    /// Recomputes the triangles and every clip plane from `mesh`, which must have the
    /// same triangles (index lists) as the mesh the tree was built on.
    pub fn refit(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        if mesh.triangle_count() != self.tris.len() {
            return Err(BuildError::TopologyChanged { built: self.tris.len(), given: mesh.triangle_count() });
        }
        mesh.validate()?;
        let ids = &self.prim_ids;
        self.tris.par_iter_mut().zip(ids.par_iter()).for_each(|(t, &id)| *t = mesh.triangle(id as usize));
        self.bounds = refit_subtree(&mut self.nodes, 0, &self.tris);
        #[cfg(debug_assertions)]
        if let Err(e) = self.check_invariants() {
            panic!("refit produced an invalid BIH: {e}");
        }
        Ok(())
    }
}

/// Refits the subtree whose root is `nodes[0]` (global index `base`) and returns the
/// union of its triangles' boxes.
fn refit_subtree(nodes: &mut [BihNode], base: u32, tris: &[Triangle]) -> Aabb {
    let n = nodes[0];
    if n.is_leaf() {
        let first = n.index() as usize;
        return tris[first..first + n.count as usize].iter().fold(Aabb::EMPTY, |b, t| b.union(&t.bounds()));
    }
    let a = n.axis();
    if n.index() == base + 1 {
        // One-child node: keep the infinite plane, move the other to the child's extent.
        let cb = refit_subtree(&mut nodes[1..], base + 1, tris);
        let c = &mut nodes[0].clip;
        if c[1] == f32::INFINITY {
            c[0] = cb.max[a];
        } else {
            c[1] = cb.min[a];
        }
        return cb;
    }
    let right_local = (n.index() - base) as usize;
    let (head, rest) = nodes.split_at_mut(1);
    let (left, right) = rest.split_at_mut(right_local - 1);
    let (lb, rb) = if left.len() + right.len() >= PARALLEL_MIN {
        rayon::join(|| refit_subtree(left, base + 1, tris), || refit_subtree(right, n.index(), tris))
    } else {
        (refit_subtree(left, base + 1, tris), refit_subtree(right, n.index(), tris))
    };
    head[0].clip = [lb.max[a], rb.min[a]];
    lb.union(&rb)
}
