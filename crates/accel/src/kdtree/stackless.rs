//! `KdTreeRopes`: the same SAH kd-tree with leaf boxes and ropes, traversed without a
//! stack (seed 000's "Ropes++" baseline).

use super::build::build;
use super::node::LeafRopes;
use super::params::KdTreeParams;
use super::ropes::build_ropes;
use super::traverse::down;
use super::traverse_ropes::walk;
use super::tree::Tree;
use crate::InvalidStructure;
use crate::{Accel, AccelStats, BuildError, Counter, NoCount, OutlineBox, TraversalCounts};
use dynray_geom::{Hit, PreparedRay, Ray, TriangleMesh};

/// SAH kd-tree with Ropes++ stackless traversal (`--accel kdtree-ropes`).
#[derive(Clone, Debug)]
pub struct KdTreeRopes {
    tree: Tree,
    /// Per leaf (by leaf index): its box and six ropes.
    ropes: Vec<LeafRopes>,
}

impl KdTreeRopes {
    /// Builds with [`KdTreeParams::default`].
    pub fn build(mesh: &TriangleMesh) -> Result<Self, BuildError> {
        Self::build_with(mesh, &KdTreeParams::default())
    }

    /// Builds the tree, then its ropes.
    pub fn build_with(mesh: &TriangleMesh, params: &KdTreeParams) -> Result<Self, BuildError> {
        let tree = build(mesh, params)?;
        let ropes = build_ropes(&tree);
        let this = Self { tree, ropes };
        #[cfg(debug_assertions)]
        this.check().map_err(|e| BuildError::Limit(format!("kd-tree ropes failed validation: {e}")))?;
        Ok(this)
    }

    fn check(&self) -> Result<(), String> {
        self.tree.check_invariants()?;
        self.tree.check_ropes(&self.ropes)
    }

    /// Parameters the tree was built with.
    pub fn params(&self) -> &KdTreeParams {
        &self.tree.params
    }

    /// True when the ray's closest-hit walk finished on ropes alone, false when it met an
    /// ambiguous edge or corner and handed over to the stack traversal (for the bench).
    pub fn walk_is_stackless(&self, ray: &Ray) -> bool {
        let r = PreparedRay::new(ray);
        let Some((t0, t1)) = self.tree.bounds.clip(&r, ray.tmin, ray.tmax) else { return true };
        let mut best = Hit::MISS;
        let visit = |prims: &[u32], t_exit: f32, _: &mut NoCount| self.test_leaf(&r, prims, t_exit, &mut best);
        walk(&self.tree, &self.ropes, &r, t0, t1, &mut NoCount, visit).is_none()
    }

    /// Tests a leaf's triangles; true when the best hit is strictly before the leaf's
    /// conservative exit, so no later leaf can hold a closer or equal one.
    #[inline(always)]
    fn test_leaf(&self, r: &PreparedRay, prims: &[u32], t_exit: f32, best: &mut Hit) -> bool {
        best.closest_of(r, prims.iter().map(|&id| (&self.tree.tris[id as usize], id)));
        best.t < down(t_exit)
    }

    fn traverse<C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        let r = PreparedRay::new(ray);
        let Some((t0, t1)) = self.tree.bounds.clip(&r, ray.tmin, ray.tmax) else { return Hit::MISS };
        let mut best = Hit::MISS;
        let visit = |prims: &[u32], t_exit: f32, c: &mut C| {
            c.triangles(prims.len() as u32);
            self.test_leaf(&r, prims, t_exit, &mut best)
        };
        match walk(&self.tree, &self.ropes, &r, t0, t1, c, visit) {
            None => best,
            Some(t) => self.tree.intersect_stack(&r, down(t).max(t0), t1, best, c),
        }
    }
}

impl Accel for KdTreeRopes {
    fn validate(&self, _mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        let invalid = |e| InvalidStructure::new(self.name(), e);
        self.check().map_err(invalid)?;
        Ok(self.stats())
    }

    fn name(&self) -> &'static str {
        "kdtree-ropes"
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        self.traverse(ray, &mut NoCount)
    }

    /// The same rope walk, ended by the first triangle hit anywhere in `[tmin, tmax]`.
    fn occluded(&self, ray: &Ray) -> bool {
        let r = PreparedRay::new(ray);
        let Some((t0, t1)) = self.tree.bounds.clip(&r, ray.tmin, ray.tmax) else { return false };
        let mut hit = false;
        let visit = |prims: &[u32], _: f32, _: &mut NoCount| {
            let tris = &self.tree.tris;
            hit = prims.iter().any(|&id| tris[id as usize].intersect(&r, ray.tmax).is_some());
            hit
        };
        match walk(&self.tree, &self.ropes, &r, t0, t1, &mut NoCount, visit) {
            None => hit,
            Some(t) => self.tree.occluded_stack(&r, down(t).max(t0), t1),
        }
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        self.traverse(ray, counts)
    }

    fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes() + self.rope_bytes()
    }

    fn stats(&self) -> AccelStats {
        self.tree.stats(self.rope_bytes())
    }

    /// Rebuilt, ropes included: a kd-tree cannot be refitted.
    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        if mesh.triangle_count() != self.tree.tris.len() {
            return Err(BuildError::TopologyChanged { built: self.tree.tris.len(), given: mesh.triangle_count() });
        }
        *self = Self::build_with(mesh, &self.tree.params)?;
        Ok(())
    }

    /// The cells of the tree, as `kdtree` draws them (outline.rs); ropes are not drawn.
    fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        self.tree.outline(max_depth, out);
    }
}

impl KdTreeRopes {
    fn rope_bytes(&self) -> usize {
        self.ropes.len() * std::mem::size_of::<LeafRopes>()
    }
}
