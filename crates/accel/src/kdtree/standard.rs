//! `KdTree`: the SAH kd-tree with the standard stack traversal (seed 000's "Standard").

use super::build::build;
use super::node::KdNode;
use super::params::KdTreeParams;
use super::tree::Tree;
use crate::InvalidStructure;
use crate::{Accel, AccelStats, BuildError, Counter, NoCount, OutlineBox, TraversalCounts};
use dynray_geom::{Hit, PreparedRay, Ray, TriangleMesh};

/// SAH kd-tree traversed front to back with a stack (`--accel kdtree`).
#[derive(Clone, Debug)]
pub struct KdTree {
    pub(super) tree: Tree,
}

impl KdTree {
    /// Builds with [`KdTreeParams::default`].
    pub fn build(mesh: &TriangleMesh) -> Result<Self, BuildError> {
        Self::build_with(mesh, &KdTreeParams::default())
    }

    /// Builds with the given parameters.
    pub fn build_with(mesh: &TriangleMesh, params: &KdTreeParams) -> Result<Self, BuildError> {
        let tree = build(mesh, params)?;
        #[cfg(debug_assertions)]
        tree.check_invariants().map_err(|e| BuildError::Limit(format!("kd-tree failed validation: {e}")))?;
        Ok(Self { tree })
    }

    /// Parameters the tree was built with.
    pub fn params(&self) -> &KdTreeParams {
        &self.tree.params
    }

    /// The nodes, depth-first (root first), as a GPU upload or a test would read them.
    pub fn nodes(&self) -> &[KdNode] {
        &self.tree.nodes
    }

    fn traverse<C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        let r = PreparedRay::new(ray);
        match self.tree.bounds.clip(&r, ray.tmin, ray.tmax) {
            Some((t0, t1)) => self.tree.intersect_stack(&r, t0, t1, Hit::MISS, c),
            None => Hit::MISS,
        }
    }
}

impl Accel for KdTree {
    fn validate(&self, _mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        let invalid = |e| InvalidStructure::new(self.name(), e);
        self.tree.check_invariants().map_err(invalid)?;
        Ok(self.stats())
    }

    fn name(&self) -> &'static str {
        "kdtree"
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        self.traverse(ray, &mut NoCount)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        let r = PreparedRay::new(ray);
        self.tree.bounds.clip(&r, ray.tmin, ray.tmax).is_some_and(|(t0, t1)| self.tree.occluded_stack(&r, t0, t1))
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        self.traverse(ray, counts)
    }

    fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes()
    }

    fn stats(&self) -> AccelStats {
        self.tree.stats(0)
    }

    /// A kd-tree cannot be refitted (its planes partition space): it is rebuilt.
    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        if mesh.triangle_count() != self.tree.tris.len() {
            return Err(BuildError::TopologyChanged { built: self.tree.tris.len(), given: mesh.triangle_count() });
        }
        *self = Self::build_with(mesh, &self.tree.params)?;
        Ok(())
    }

    /// The cells, split by split (outline.rs).
    fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        self.tree.outline(max_depth, out);
    }
}
