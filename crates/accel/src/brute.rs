//! Brute force: every ray against every triangle. The oracle all structures must match.

use crate::InvalidStructure;
use crate::{Accel, AccelStats, BuildError, Counter, NoCount, TraversalCounts};
use dynray_geom::{Hit, PreparedRay, Ray, Triangle, TriangleMesh};

/// Tests every triangle, in index order.
pub struct Brute {
    tris: Vec<Triangle>,
}

impl Brute {
    /// Copies the mesh's triangles.
    pub fn build(mesh: &TriangleMesh) -> Result<Self, BuildError> {
        mesh.validate()?;
        Ok(Self { tris: mesh.triangles().collect() })
    }

    fn traverse<C: Counter>(&self, ray: &Ray, c: &mut C) -> Hit {
        let r = PreparedRay::new(ray);
        let mut best = Hit::MISS;
        c.node();
        c.triangles(self.tris.len() as u32);
        for (i, tri) in self.tris.iter().enumerate() {
            // Strict `<`: scanning in index order keeps the lower index on equal `t`.
            if let Some((t, u, v)) = tri.intersect(&r, best.t.min(ray.tmax)) {
                if t < best.t {
                    best = Hit { t, u, v, prim: i as u32 };
                }
            }
        }
        best
    }
}

impl Accel for Brute {
    fn validate(&self, mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        if self.tris.len() != mesh.triangle_count() {
            let e = format!("{} triangles copied, mesh has {}", self.tris.len(), mesh.triangle_count());
            return Err(InvalidStructure::new(self.name(), e));
        }
        if let Some(i) = (0..self.tris.len()).find(|&i| self.tris[i] != mesh.triangle(i)) {
            return Err(InvalidStructure::new(self.name(), format!("triangle {i} is not a copy of the mesh's")));
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
        let r = PreparedRay::new(ray);
        self.tris.iter().any(|t| t.intersect(&r, ray.tmax).is_some())
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        self.traverse(ray, counts)
    }

    fn memory_bytes(&self) -> usize {
        self.tris.len() * std::mem::size_of::<Triangle>()
    }

    fn stats(&self) -> AccelStats {
        AccelStats {
            nodes: 1,
            leaves: 1,
            max_depth: 0,
            primitive_refs: self.tris.len(),
            leaf_sizes: Vec::new(),
            sah_cost: None,
            memory_bytes: self.memory_bytes(),
            extra: Vec::new(),
        }
    }

    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        if mesh.triangle_count() != self.tris.len() {
            return Err(BuildError::TopologyChanged { built: self.tris.len(), given: mesh.triangle_count() });
        }
        mesh.validate()?;
        self.tris.clear();
        self.tris.extend(mesh.triangles());
        Ok(())
    }
}
