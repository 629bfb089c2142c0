//! Brute force: every ray against every triangle. The oracle all structures must match.
//!
//! The triangles are kept in index order as the wide BVH's 4-triangle blocks and tested
//! by its block kernels (`bvh/scan.rs`): the scalar kernel is `Triangle::intersect` lane
//! by lane, the AVX2 one computes the same bits four at a time (about 4× faster, which is
//! most of the oracle tests' time), and `DYNRAY_FORCE_SCALAR=1` forces the scalar one.

use crate::bvh::{scan, KernelChoice, TriBlock};
use crate::InvalidStructure;
use crate::{Accel, AccelStats, BuildError, Counter, NoCount, OutlineBox, TraversalCounts};
use dynray_geom::{Aabb, Hit, PreparedRay, Ray, TriangleMesh};

/// Tests every triangle, in index order (on equal `t` the lower index wins).
pub struct Brute {
    /// The mesh's triangles in index order, 4 per block (the last block padded).
    blocks: Vec<TriBlock>,
    triangles: usize,
    kernel: KernelChoice,
    /// Box of the triangles, kept for [`Accel::outline`] only (a scan needs none).
    bounds: Aabb,
}

impl Brute {
    /// Copies the mesh's triangles.
    pub fn build(mesh: &TriangleMesh) -> Result<Self, BuildError> {
        mesh.validate()?;
        let mut b = Self { blocks: Vec::new(), triangles: 0, kernel: KernelChoice::detect(), bounds: Aabb::EMPTY };
        b.copy(mesh);
        Ok(b)
    }

    fn copy(&mut self, mesh: &TriangleMesh) {
        let tris: Vec<_> = mesh.triangles().collect();
        let ids: Vec<u32> = (0..tris.len() as u32).collect();
        self.blocks.clear();
        TriBlock::pack(&tris, &ids, &mut self.blocks);
        self.triangles = tris.len();
        self.bounds = tris.iter().fold(Aabb::EMPTY, |b, t| b.union(&t.bounds()));
    }

    /// The block kernel it tests with (`scalar`, `avx2` or `avx512`).
    pub fn kernel(&self) -> &'static str {
        self.kernel.name()
    }

    fn traverse<C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        c.node();
        c.triangles(self.triangles as u32);
        scan::closest(&self.blocks, &PreparedRay::new(ray), self.kernel)
    }
}

impl Accel for Brute {
    fn validate(&self, mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        if self.triangles != mesh.triangle_count() {
            let e = format!("{} triangles copied, mesh has {}", self.triangles, mesh.triangle_count());
            return Err(InvalidStructure::new(self.name(), e));
        }
        let copy = |i: usize| {
            let (b, lane) = (&self.blocks[i / 4], i % 4);
            b.ids[lane] == i as u32 && b.triangle(lane) == mesh.triangle(i)
        };
        if let Some(i) = (0..self.triangles).find(|&i| !copy(i)) {
            return Err(InvalidStructure::new(self.name(), format!("triangle {i} is not a copy of the mesh's")));
        }
        if self.blocks.len() != self.triangles.div_ceil(4)
            || (self.triangles..self.blocks.len() * 4).any(|i| !self.blocks[i / 4].is_pad(i % 4))
        {
            return Err(InvalidStructure::new(self.name(), "the blocks past the last triangle are not padding"));
        }
        Ok(self.stats())
    }

    fn name(&self) -> &'static str {
        "brute"
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        self.traverse(ray, &mut NoCount)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        scan::any(&self.blocks, &PreparedRay::new(ray), self.kernel)
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        self.traverse(ray, counts)
    }

    fn memory_bytes(&self) -> usize {
        self.blocks.len() * std::mem::size_of::<TriBlock>()
    }

    fn stats(&self) -> AccelStats {
        AccelStats {
            nodes: 1,
            leaves: 1,
            max_depth: 0,
            primitive_refs: self.triangles,
            leaf_sizes: Vec::new(),
            sah_cost: None,
            memory_bytes: self.memory_bytes(),
            extra: vec![("kernel".into(), self.kernel().into())],
        }
    }

    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        if mesh.triangle_count() != self.triangles {
            return Err(BuildError::TopologyChanged { built: self.triangles, given: mesh.triangle_count() });
        }
        mesh.validate()?;
        self.copy(mesh);
        Ok(())
    }

    /// One leaf: the box of the mesh (kept by `copy`), which every ray scans whole.
    fn outline(&self, _max_depth: u32, out: &mut Vec<OutlineBox>) {
        if self.triangles > 0 {
            out.push(OutlineBox { depth: 0, bounds: self.bounds, leaf: true });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::outline::checks::{self, Cover};

    #[test]
    fn outline_is_the_mesh_box_as_one_leaf() {
        let mut mesh = checks::mesh();
        let mut brute = Brute::build(&mesh).unwrap();
        assert_eq!(checks::check(&brute, &mesh, Cover::Centroids), 0);
        assert_eq!(checks::outline(&brute, 7), [OutlineBox { depth: 0, bounds: mesh.bounds(), leaf: true }]);
        // An update moves the box with the vertices.
        mesh.positions.iter_mut().for_each(|p| p[1] += 3.0);
        brute.update(&mesh).unwrap();
        assert_eq!(checks::outline(&brute, 0)[0].bounds, mesh.bounds());
    }
}
