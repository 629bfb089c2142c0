//! Refit: new vertex positions, same triangles, same tree; blocks re-copied from the mesh
//! and every child box recomputed bottom-up.

use super::block::LANES;
use super::node::{is_leaf, leaf_blocks, WideNode};
use super::WideTree;
use crate::BuildError;
use dynray_geom::{Aabb, TriangleMesh};
use rayon::prelude::*;

impl<N: WideNode> WideTree<N> {
    /// Brings the tree up to date with moved vertices. The topology (which triangles share
    /// a leaf, which children a node has) is kept, so a large deformation leaves a valid
    /// but slower tree; hits stay exact because every box is rebuilt from the new
    /// triangles. On an unchanged mesh it reproduces the built boxes exactly (the built
    /// boxes are the same unions), except in a pre-split tree: there a leaf's box becomes
    /// the union of its whole triangles, no longer of their parts (valid, looser).
    pub(super) fn refit(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        if mesh.triangle_count() != self.triangles {
            return Err(BuildError::TopologyChanged { built: self.triangles, given: mesh.triangle_count() });
        }
        mesh.validate()?;
        self.blocks.par_iter_mut().with_min_len(1024).for_each(|b| {
            for lane in 0..LANES {
                if !b.is_pad(lane) {
                    let id = b.ids[lane];
                    b.set(lane, &mesh.triangle(id as usize), id);
                }
            }
        });
        // Interior children sit after their parent (collapse.rs emits them so), so one reverse
        // sweep sees every child node before its parent.
        for i in (0..self.nodes.len()).rev() {
            for lane in 0..self.nodes[i].count() {
                let c = self.nodes[i].child(lane);
                let b = if is_leaf(c) {
                    let (first, count) = leaf_blocks(c);
                    self.blocks[first..first + count].iter().fold(Aabb::EMPTY, |b, x| b.union(&x.bounds()))
                } else {
                    let child = &self.nodes[c as usize];
                    debug_assert!(c as usize > i, "child {c} before parent {i}");
                    (0..child.count()).fold(Aabb::EMPTY, |b, k| b.union(&child.child_box(k)))
                };
                self.nodes[i].set_box(lane, &b);
            }
        }
        Ok(())
    }
}
