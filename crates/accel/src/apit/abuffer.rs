//! The seed's baseline: the six A-buffers with plain per-pixel fragment lists (linked, as
//! in the GPU per-pixel-list A-buffers the seed cites), each scanned fully by a ray.

use super::build::{build_filed, Base};
use super::node::{Fragment, NONE};
use super::params::{ApitParams, Observer};
use super::query::{any, closest, Candidates};
use crate::InvalidStructure;
use crate::{Accel, AccelStats, BuildError, Counter, NoCount, OutlineBox, TraversalCounts};
use dynray_geom::{Hit, Ray, TriangleMesh, Vec3};
use std::ops::ControlFlow;

/// Six A-buffers on a cube around an observer, without interval trees (`--accel abuffer`).
#[derive(Clone, Debug)]
pub struct ABuffer {
    pub(crate) base: Base,
    /// First fragment of each pixel's list, or [`NONE`] (the seed's entry matrix).
    pub(crate) heads: Vec<u32>,
    /// Fragments; each pixel's list is contiguous and linked through `next`.
    pub(crate) frags: Vec<Fragment>,
}

impl ABuffer {
    /// Rasterises `mesh` into the six A-buffers.
    pub fn build(mesh: &TriangleMesh, params: &ApitParams) -> Result<Self, BuildError> {
        let filed = build_filed(mesh, params)?;
        let mut frags = filed.frags;
        let pixels = filed.base.cube.pixels();
        let mut heads = vec![NONE; pixels];
        for (p, head) in heads.iter_mut().enumerate() {
            let (s, e) = (filed.offsets[p], filed.offsets[p + 1]);
            if s < e {
                *head = s;
                for k in s..e - 1 {
                    frags[k as usize].next = k + 1;
                }
            }
        }
        let me = Self { base: filed.base, heads, frags };
        #[cfg(debug_assertions)]
        if let Err(e) = me.check_invariants() {
            panic!("A-buffer built broken: {e}");
        }
        Ok(me)
    }

    /// Parameters it was built with.
    pub fn params(&self) -> &ApitParams {
        &self.base.params
    }

    fn list_len(&self, p: usize) -> usize {
        let mut n = 0;
        let mut f = self.heads[p];
        while f != NONE && n <= self.frags.len() {
            n += 1;
            f = self.frags[f as usize].next;
        }
        n
    }
}

impl Candidates for ABuffer {
    #[inline]
    fn candidates<C: Counter>(
        &self,
        pixel: usize,
        qa: f32,
        qb: f32,
        c: &mut C,
        mut visit: impl FnMut(u32) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let mut f = self.heads[pixel];
        while f != NONE {
            // Every fragment scanned counts as a visited element (the seed's complexity
            // metric: frustums visited + fragments analysed), overlapping ones as tests.
            c.node();
            let fr = &self.frags[f as usize];
            if fr.overlaps(qa, qb) {
                c.triangles(1);
                visit(fr.tri)?;
            }
            f = fr.next;
        }
        ControlFlow::Continue(())
    }
}

impl Accel for ABuffer {
    fn validate(&self, _mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        let invalid = |e| InvalidStructure::new(self.name(), e);
        self.check_invariants().map_err(invalid)?;
        Ok(self.stats())
    }

    fn name(&self) -> &'static str {
        "abuffer"
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        closest(&self.base, self, ray, &mut NoCount)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        any(&self.base, self, ray)
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        closest(&self.base, self, ray, counts)
    }

    fn memory_bytes(&self) -> usize {
        self.base.memory_bytes() + self.heads.len() * 4 + self.frags.len() * std::mem::size_of::<Fragment>()
    }

    fn stats(&self) -> AccelStats {
        let nonempty = self.heads.iter().filter(|&&h| h != NONE).count();
        AccelStats {
            nodes: nonempty,
            leaves: nonempty,
            max_depth: 0,
            primitive_refs: self.frags.len() + self.base.near.len(),
            leaf_sizes: Base::histogram(
                (0..self.heads.len()).filter(|&p| self.heads[p] != NONE).map(|p| self.list_len(p)),
            ),
            sah_cost: None,
            memory_bytes: self.memory_bytes(),
            extra: self.base.extra(self.frags.len(), nonempty),
        }
    }

    /// Rebuilds: the A-buffers depend on every vertex (and the default observer moves).
    fn update(&mut self, mesh: &TriangleMesh) -> Result<(), BuildError> {
        if mesh.triangle_count() != self.base.tris.len() {
            return Err(BuildError::TopologyChanged { built: self.base.tris.len(), given: mesh.triangle_count() });
        }
        *self = Self::build(mesh, &self.base.params)?;
        Ok(())
    }

    /// Rebuilds with the cube centred on `eye` (seed 004 centres it on the observer every
    /// frame), unless the structure was told `observer=center`. Later plain updates keep
    /// this eye.
    fn update_for_eye(&mut self, mesh: &TriangleMesh, eye: Vec3) -> Result<(), BuildError> {
        if self.base.params.observer != Observer::BoundsCenter {
            self.base.params = self.base.params.with_observer(eye);
        }
        self.update(mesh)
    }

    /// The cube of A-buffers around the observer, one leaf (outline.rs).
    fn outline(&self, _max_depth: u32, out: &mut Vec<OutlineBox>) {
        self.base.outline(out);
    }
}
