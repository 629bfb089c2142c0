//! Queries through the two levels: the top tree in world space, then each instance's part
//! with the ray in the part's space, the closest hit kept by the engine's order (smaller
//! `t`, then the lower *frame* triangle).

use super::{Instance, TwoLevel};
use crate::{Accel, AccelStats, BuildError, Counter, InvalidStructure, NoCount, OutlineBox, TraversalCounts};
use dynray_geom::{Hit, PreparedRay, Ray, TriangleMesh};

impl Instance {
    /// `ray` in the part's space: the same ray for a world-space part; for an instance,
    /// origin and direction through the world-to-local matrix (the direction not
    /// normalised, so `t` means the same point in both spaces).
    #[inline]
    pub fn local_ray(&self, ray: &Ray) -> Ray {
        match &self.to_local {
            None => *ray,
            Some(m) => Ray {
                origin: m.transform_point3(ray.origin),
                dir: m.transform_vector3(ray.dir),
                tmin: ray.tmin,
                tmax: ray.tmax,
            },
        }
    }
}

impl TwoLevel {
    /// Frame triangle of part-local triangle `prim` of instance `inst`.
    #[inline]
    fn frame_prim(&self, inst: &Instance, prim: u32) -> u32 {
        match &self.parts[inst.part as usize].space {
            super::PartSpace::World { prims, .. } => prims[prim as usize],
            super::PartSpace::Local { .. } => inst.first_prim + prim,
        }
    }

    /// Visits the instances whose boxes the ray enters before `limit()`, nearer boxes
    /// first; `visit` returns true to stop.
    #[inline]
    fn walk<C: Counter>(
        &self,
        ray: &Ray,
        c: &mut C,
        limit: impl Fn() -> f32,
        mut visit: impl FnMut(&Instance, &mut C) -> bool,
    ) {
        if self.top.is_empty() {
            return;
        }
        let r = PreparedRay::new(ray);
        let mut stack = [0u32; super::top::STACK];
        let mut len = 0;
        let mut node = 0usize;
        loop {
            c.node();
            let n = &self.top[node];
            if n.is_leaf() {
                let inst = &self.instances[self.order[n.index as usize] as usize];
                if visit(inst, c) {
                    return;
                }
            } else {
                let (a, b) = (n.index as usize, n.index as usize + 1);
                let tmax = limit();
                let ta = self.top[a].bounds().intersect(&r, tmax);
                let tb = self.top[b].bounds().intersect(&r, tmax);
                match (ta, tb) {
                    (Some(x), Some(y)) => {
                        let (near, far) = if y < x { (b, a) } else { (a, b) };
                        stack[len] = far as u32;
                        len += 1;
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = b;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop, skipping subtrees the closest hit so far has moved beyond.
            loop {
                if len == 0 {
                    return;
                }
                len -= 1;
                node = stack[len] as usize;
                if self.top[node].bounds().intersect(&r, limit()).is_some() {
                    break;
                }
            }
        }
    }

    fn closest<C: Counter>(&self, ray: &Ray, c: &mut C, count: bool) -> Hit {
        if self.top.is_empty() || self.top[0].bounds().intersect(&PreparedRay::new(ray), ray.tmax).is_none() {
            return Hit::MISS;
        }
        let best = std::cell::Cell::new(Hit::MISS);
        self.walk(
            ray,
            c,
            || best.get().t.min(ray.tmax),
            |inst, c| {
                let mut local = inst.local_ray(ray);
                // Inclusive: an equal `t` on a lower frame triangle must still be found.
                local.tmax = best.get().t.min(ray.tmax);
                let accel = self.parts[inst.part as usize].live.accel();
                let h = if count {
                    let mut n = TraversalCounts::default();
                    let h = accel.intersect_counted(&local, &mut n);
                    c.triangles(n.triangles as u32);
                    c.nodes(n.nodes);
                    h
                } else {
                    accel.intersect(&local)
                };
                if h.is_hit() {
                    let prim = self.frame_prim(inst, h.prim);
                    if Hit::is_closer(h.t, prim, &best.get()) {
                        best.set(Hit { prim, ..h });
                    }
                }
                false
            },
        );
        best.get()
    }

    /// The one instance, when it is all the top level holds and its part is in world space.
    fn single_world_instance(&self) -> Option<&Instance> {
        match (self.instances.as_slice(), self.top.len()) {
            ([inst], 1) if inst.to_local.is_none() => Some(inst),
            _ => None,
        }
    }

    /// The instanced oracle: every instance's part searched by brute force (its own
    /// triangles, the ray mapped into its space), the closest kept in the engine's order.
    /// Equal to brute force over the frame where every part is in world space.
    pub fn intersect_brute(&self, ray: &Ray, local_meshes: &dyn Fn(u32) -> TriangleMesh) -> Hit {
        let mut best = Hit::MISS;
        for inst in &self.instances {
            let mesh = local_meshes(inst.part);
            let r = dynray_geom::PreparedRay::new(&inst.local_ray(ray));
            for (i, tri) in mesh.triangles().enumerate() {
                if let Some((t, u, v)) = tri.intersect(&r, ray.tmax) {
                    let prim = self.frame_prim(inst, i as u32);
                    if Hit::is_closer(t, prim, &best) {
                        best = Hit { t, u, v, prim };
                    }
                }
            }
        }
        best
    }

    /// The triangles of part `part` as it was last built or updated on (its own space).
    pub fn part_mesh(&self, part: u32) -> TriangleMesh {
        self.parts[part as usize].live.mesh()
    }
}

impl Accel for TwoLevel {
    fn name(&self) -> &'static str {
        self.spec.kind.name()
    }

    fn intersect(&self, ray: &Ray) -> Hit {
        self.closest(ray, &mut NoCount, false)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        let mut hit = false;
        self.walk(
            ray,
            &mut NoCount,
            || ray.tmax,
            |inst, _| {
                hit = self.parts[inst.part as usize].live.accel().occluded(&inst.local_ray(ray));
                hit
            },
        );
        hit
    }

    /// A frame whose only part is in world space (a single moving actor and nothing else)
    /// hands a coherent batch to that part's own coherent path, so packets reach its
    /// structure; each hit is then renumbered and the top level's box test applied as
    /// `intersect` applies them. Any other layout answers one ray at a time.
    fn intersect_coherent_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        crate::batch::check_batch_lengths(rays.len(), hits.len());
        let Some(inst) = self.single_world_instance() else {
            for (r, h) in rays.iter().zip(hits) {
                *h = self.intersect(r);
            }
            return;
        };
        let part = self.parts[inst.part as usize].live.accel();
        // `closest` hands the part `min(∞, tmax)`: a NaN `tmax` becomes ∞.
        if rays.iter().any(|r| r.tmax.is_nan()) {
            let local: Vec<Ray> = rays.iter().map(|r| Ray { tmax: f32::INFINITY.min(r.tmax), ..*r }).collect();
            part.intersect_coherent_into(&local, hits);
        } else {
            part.intersect_coherent_into(rays, hits);
        }
        let root = self.top[0].bounds();
        for (r, h) in rays.iter().zip(hits) {
            if h.is_hit() {
                *h = if root.intersect(&PreparedRay::new(r), r.tmax).is_some() {
                    Hit { prim: self.frame_prim(inst, h.prim), ..*h }
                } else {
                    Hit::MISS
                };
            }
        }
    }

    fn traces_packets(&self) -> bool {
        self.single_world_instance().is_some_and(|i| self.parts[i.part as usize].live.accel().traces_packets())
    }

    fn intersect_counted(&self, ray: &Ray, counts: &mut TraversalCounts) -> Hit {
        self.closest(ray, counts, true)
    }

    fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.top.len() * size_of::<crate::BvhNode>()
            + self.order.len() * 4
            + self.instances.len() * size_of::<Instance>()
            + self.parts.iter().map(|p| p.live.accel().memory_bytes()).sum::<usize>()
    }

    fn stats(&self) -> AccelStats {
        let parts: Vec<AccelStats> = self.parts.iter().map(|p| p.live.accel().stats()).collect();
        let depth = super::validate::top_depth(&self.top);
        let mut leaf_sizes = Vec::new();
        for s in &parts {
            if leaf_sizes.len() < s.leaf_sizes.len() {
                leaf_sizes.resize(s.leaf_sizes.len(), 0);
            }
            leaf_sizes.iter_mut().zip(&s.leaf_sizes).for_each(|(a, b)| *a += b);
        }
        AccelStats {
            nodes: self.top.len() + parts.iter().map(|s| s.nodes).sum::<usize>(),
            leaves: parts.iter().map(|s| s.leaves).sum(),
            max_depth: depth + parts.iter().map(|s| s.max_depth).max().unwrap_or(0),
            primitive_refs: parts.iter().map(|s| s.primitive_refs).sum(),
            leaf_sizes,
            sah_cost: None,
            memory_bytes: self.memory_bytes(),
            extra: vec![
                ("parts".into(), self.parts.len().to_string()),
                ("instances".into(), self.instances.len().to_string()),
                ("top_nodes".into(), self.top.len().to_string()),
            ],
        }
    }

    fn validate(&self, mesh: &TriangleMesh) -> Result<AccelStats, InvalidStructure> {
        self.check(mesh).map_err(|e| InvalidStructure::new(self.name(), e))?;
        Ok(self.stats())
    }

    /// A two-level structure follows its actors, whose transforms a mesh does not carry:
    /// [`super::LiveScene::update`] brings it to a new frame.
    fn update(&mut self, _: &TriangleMesh) -> Result<(), BuildError> {
        Err(BuildError::Spec {
            spec: format!("{} (two-level)", self.spec),
            message: "a two-level structure is updated from the frame's actors (LiveScene::update), not from a mesh"
                .into(),
        })
    }

    /// The top-level tree down to the instances' world boxes, nothing below (outline.rs).
    fn outline(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        self.outline_top(max_depth, out);
    }
}
