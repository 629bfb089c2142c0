//! obvhs 0.4 (pure Rust): its CWBVH (8-wide compressed, SIMD traversal) and its BVH2,
//! both built by its PLOC builder with the `medium_build` preset its examples use (parallel
//! through rayon, feature `parallel`), triangles reordered into leaf order as its
//! cornell_box example does (no index indirection while tracing); its Möller–Trumbore
//! `Triangle::intersect`; any hit through `ray_traverse_miss`.

use super::{par_chunks_into, parts, Competitor};
use anyhow::{bail, Result};
use dynray_accel::BatchQuery;
use dynray_geom::{Hit, Ray, TriangleMesh};
use obvhs::bvh2::builder::build_bvh2_from_tris;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::RayHit;
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;
use std::time::Duration;

/// obvhs's triangle: three `Vec3A` (16 bytes each; glam's SIMD vector, w unused).
const _: () = assert!(std::mem::size_of::<Triangle>() == 48);

/// Our mesh as obvhs triangles. `Vec3A` is `Pod` (glam's `bytemuck` feature, which
/// obvhs enables), so four floats cast into one without naming obvhs's glam version.
fn triangles(mesh: &TriangleMesh) -> Vec<Triangle> {
    mesh.indices
        .iter()
        .map(|t| {
            let p = |i: u32| {
                let [x, y, z] = mesh.positions[i as usize];
                bytemuck::cast([x, y, z, 0.0f32])
            };
            Triangle { v0: p(t[0]), v1: p(t[1]), v2: p(t[2]) }
        })
        .collect()
}

fn obvhs_ray(r: &Ray) -> obvhs::ray::Ray {
    let (o, d, tmin, tmax) = parts(r);
    obvhs::ray::Ray::new(
        bytemuck::cast([o[0], o[1], o[2], 0.0f32]),
        bytemuck::cast([d[0], d[1], d[2], 0.0f32]),
        tmin,
        tmax,
    )
}

/// The triangles in the BVH's leaf order and the map back to mesh indices.
fn reorder(tris: &[Triangle], primitive_indices: &[u32]) -> Result<(Vec<Triangle>, Vec<u32>)> {
    if primitive_indices.len() != tris.len() {
        // Only spatial splits (off in medium_build) make references outnumber triangles.
        bail!("obvhs: {} primitive references for {} triangles", primitive_indices.len(), tris.len());
    }
    Ok((primitive_indices.iter().map(|&i| tris[i as usize]).collect(), primitive_indices.to_vec()))
}

/// What the two obvhs layouts offer a traced structure: their node bytes, their leaf
/// order, and their closest-hit and any-hit traversals over leaf-ordered triangles.
trait Layout: Send + Sync + 'static {
    fn node_bytes(&self) -> usize;
    fn primitive_indices(&self) -> &[u32];
    fn closest(&self, ray: obvhs::ray::Ray, hit: &mut RayHit, tris: &[Triangle]) -> bool;
    fn missed(&self, ray: obvhs::ray::Ray, tris: &[Triangle]) -> bool;
}

impl Layout for obvhs::cwbvh::CwBvh {
    fn node_bytes(&self) -> usize {
        std::mem::size_of_val(self.nodes.as_slice())
    }
    fn primitive_indices(&self) -> &[u32] {
        &self.primitive_indices
    }
    fn closest(&self, ray: obvhs::ray::Ray, hit: &mut RayHit, tris: &[Triangle]) -> bool {
        self.ray_traverse(ray, hit, |ray, id| tris[id].intersect(ray))
    }
    fn missed(&self, ray: obvhs::ray::Ray, tris: &[Triangle]) -> bool {
        self.ray_traverse_miss(ray, |ray, id| tris[id].intersect(ray))
    }
}

impl Layout for obvhs::bvh2::Bvh2 {
    fn node_bytes(&self) -> usize {
        std::mem::size_of_val(self.nodes.as_slice())
    }
    fn primitive_indices(&self) -> &[u32] {
        &self.primitive_indices
    }
    fn closest(&self, ray: obvhs::ray::Ray, hit: &mut RayHit, tris: &[Triangle]) -> bool {
        self.ray_traverse(ray, hit, |ray, id| tris[id].intersect(ray))
    }
    fn missed(&self, ray: obvhs::ray::Ray, tris: &[Triangle]) -> bool {
        self.ray_traverse_miss(ray, |ray, id| tris[id].intersect(ray))
    }
}

/// A built obvhs structure with its leaf-ordered triangles and the map back to ours.
struct Leaves<L> {
    bvh: L,
    tris: Vec<Triangle>,
    original: Vec<u32>,
}

impl<L: Layout> Leaves<L> {
    fn new(tris: &[Triangle], bvh: L) -> Result<Self> {
        let (tris, original) = reorder(tris, bvh.primitive_indices())?;
        Ok(Self { bvh, tris, original })
    }
}

impl<L: Layout> Leaves<L> {
    fn memory_bytes(&self) -> usize {
        self.bvh.node_bytes()
            + std::mem::size_of_val(self.bvh.primitive_indices())
            + std::mem::size_of_val(self.tris.as_slice())
            + std::mem::size_of_val(self.original.as_slice())
    }

    /// The adapter's answer for the bench: obvhs has its own any-hit query.
    fn built(self) -> super::Built {
        let memory_bytes = Some(self.memory_bytes());
        super::Built { query: Box::new(self), memory_bytes, any_hit: true }
    }
}

/// `u` and `v` are NaN on a hit: obvhs's `Triangle::intersect` returns the distance only
/// (its `RayHit` has no barycentrics), and computing them again here would add work to
/// the timed pass that obvhs's own users would not do. The bench compares `t` and the
/// triangle, never `u`, `v`.
impl<L: Layout> BatchQuery for Leaves<L> {
    fn intersect_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        par_chunks_into(rays, hits, |rays, hits| {
            for (r, o) in rays.iter().zip(hits) {
                let mut hit = RayHit::none();
                *o = if r.tmin <= r.tmax && self.bvh.closest(obvhs_ray(r), &mut hit, &self.tris) {
                    Hit { t: hit.t, u: f32::NAN, v: f32::NAN, prim: self.original[hit.primitive_id as usize] }
                } else {
                    Hit::MISS
                };
            }
        });
    }

    fn occluded_into(&self, rays: &[Ray], out: &mut [bool]) {
        par_chunks_into(rays, out, |rays, out| {
            for (r, o) in rays.iter().zip(out) {
                *o = r.tmin <= r.tmax && !self.bvh.missed(obvhs_ray(r), &self.tris);
            }
        });
    }
}

/// `obvhs cwbvh`.
pub struct ObvhsCwBvh;

impl Competitor for ObvhsCwBvh {
    fn name(&self) -> &'static str {
        "obvhs"
    }
    fn variant(&self) -> &'static str {
        "cwbvh"
    }
    fn describe(&self) -> String {
        "obvhs 0.4 CwBvh (8-wide compressed nodes, SIMD traversal): build_cwbvh_from_tris, medium_build \
         (PLOC + reinsertion, parallel), leaf-ordered triangles; ray_traverse / ray_traverse_miss"
            .into()
    }
    fn build(&self, mesh: &TriangleMesh) -> Result<super::Built> {
        let tris = triangles(mesh);
        let bvh = build_cwbvh_from_tris(&tris, BvhBuildParams::medium_build(), &mut Duration::default());
        Ok(Leaves::new(&tris, bvh)?.built())
    }
}

/// `obvhs bvh2`.
pub struct ObvhsBvh2;

impl Competitor for ObvhsBvh2 {
    fn name(&self) -> &'static str {
        "obvhs"
    }
    fn variant(&self) -> &'static str {
        "bvh2"
    }
    fn describe(&self) -> String {
        "obvhs 0.4 Bvh2: build_bvh2_from_tris, medium_build (PLOC + reinsertion + leaf collapse, parallel), \
         leaf-ordered triangles; ray_traverse / ray_traverse_miss"
            .into()
    }
    fn build(&self, mesh: &TriangleMesh) -> Result<super::Built> {
        let tris = triangles(mesh);
        let bvh = build_bvh2_from_tris(&tris, BvhBuildParams::medium_build(), &mut Duration::default());
        Ok(Leaves::new(&tris, bvh)?.built())
    }
}
