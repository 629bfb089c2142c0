//! Refit: new vertex positions, same triangles, same tree; boxes recomputed bottom-up.

use super::Bvh;
use crate::BuildError;
use dynray_geom::{Aabb, TriangleMesh};
use rayon::prelude::*;

impl Bvh {
    /// Brings the tree up to date with moved vertices: re-copies every leaf triangle from
    /// `mesh` and recomputes every box from its children. The topology (which triangles
    /// share a leaf) is kept, so a large deformation leaves a valid but slower tree; hits
    /// stay exact because the boxes are rebuilt from the new triangles.
    pub fn refit(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        if mesh.triangle_count() != self.tris.len() {
            return Err(BuildError::TopologyChanged { built: self.tris.len(), given: mesh.triangle_count() });
        }
        mesh.validate()?;
        let ids = &self.ids;
        self.tris.par_iter_mut().with_min_len(4096).enumerate().for_each(|(i, t)| *t = mesh.triangle(ids[i] as usize));
        // Children always sit at higher indices than their parent (pairs are appended
        // after the parent in depth-first order), so one reverse sweep sees children first.
        for i in (0..self.nodes.len()).rev() {
            let n = self.nodes[i];
            let b = if n.is_leaf() {
                let tris = &self.tris[n.index as usize..(n.index + n.count) as usize];
                tris.iter().fold(Aabb::EMPTY, |b, t| b.union(&t.bounds()))
            } else {
                let l = n.index as usize;
                debug_assert!(l > i, "child {l} before parent {i}");
                self.nodes[l].bounds().union(&self.nodes[l + 1].bounds())
            };
            self.nodes[i].set_bounds(&b);
        }
        #[cfg(debug_assertions)]
        if let Err(e) = self.check_invariants(mesh) {
            panic!("refit produced an invalid BVH: {e}");
        }
        Ok(())
    }
}
