//! The scene-level intersector: every geometry of a frame behind one closest-hit and one
//! any-hit query that answer with surface hits.
//!
//! A [`Geometry`] is anything rays can hit — the frame's triangles through an
//! acceleration structure today; distance fields and instanced meshes (a top-level
//! structure over bottom-level ones) are further geometries behind the same trait, so
//! integrators have one shading path whatever they hit.

use crate::{cone, GeometryRef, RayCone, SurfaceHit};
use dynray_accel::Accel;
use dynray_geom::{Aabb, Hit, Ray, Vec2, Vec3};
use dynray_scene::{Color, Frame, Material};

/// Something rays can hit, with its own primitive numbering.
pub trait Geometry: Sync {
    /// Closest hit along `ray` within `[tmin, tmax]`, as a primitive-level [`Hit`]
    /// (`prim` in this geometry's numbering, `u`, `v` its surface parameters).
    fn intersect(&self, ray: &Ray) -> Hit;

    /// [`Geometry::intersect`] of each of a batch of coherent rays (camera rays in pixel
    /// order) into `hits`, exactly: a geometry whose structure traces packets uses them;
    /// the default asks one ray at a time. `hits.len() == rays.len()`.
    fn intersect_coherent_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        for (r, h) in rays.iter().zip(hits) {
            *h = self.intersect(r);
        }
    }

    /// True when anything of this geometry lies on `ray` within `[tmin, tmax]`.
    fn occluded(&self, ray: &Ray) -> bool;

    /// The surface at `hit` (a hit this geometry returned for `ray`); `None` when the
    /// hit names no valid primitive. `geometry` is this geometry's index in the scene.
    fn surface<'a>(&'a self, ray: &Ray, hit: &Hit, geometry: u32) -> Option<SurfaceHit<'a>>;

    /// [`Geometry::surface`] for a ray whose footprint is `cone` ([`RayCone`]): a
    /// geometry with textures filters its lookup by the footprint at the hit (mipmaps,
    /// docs/rendering.md "Texture filtering"). The default ignores the cone, right for
    /// geometry without texture coordinates.
    fn surface_cone<'a>(&'a self, ray: &Ray, hit: &Hit, geometry: u32, cone: &RayCone) -> Option<SurfaceHit<'a>> {
        let _ = cone;
        self.surface(ray, hit, geometry)
    }

    /// Bounds of everything the geometry holds.
    fn bounds(&self) -> Aabb;
}

/// Every geometry of a frame; the closest hit over all of them wins, equal `t` going to
/// the lower geometry index (then, inside one geometry, to the lower primitive, as every
/// acceleration structure does).
pub struct SceneIntersector<'a> {
    geometries: Vec<Box<dyn Geometry + 'a>>,
    bounds: Aabb,
}

impl<'a> SceneIntersector<'a> {
    /// A scene of the given geometries (geometry `i` reports `GeometryRef::geometry == i`).
    pub fn new(geometries: Vec<Box<dyn Geometry + 'a>>) -> Self {
        let bounds = geometries.iter().fold(Aabb::EMPTY, |b, g| b.union(&g.bounds()));
        Self { geometries, bounds }
    }

    /// The frame's triangles through `accel`, which must be built on `frame.mesh`.
    pub fn triangles(frame: &'a Frame, accel: &'a dyn Accel) -> Self {
        Self::new(vec![Box::new(TriangleGeometry::new(frame, accel))])
    }

    /// Closest surface hit along `ray`, or `None` when it escapes. Textures are looked
    /// up at a point (the finest mip level); [`Self::intersect_cone`] filters them.
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceHit<'_>> {
        self.intersect_cone(ray, &RayCone::POINT)
    }

    /// [`Self::intersect`] of a ray whose footprint is `cone`: the same hit, its texture
    /// filtered over the footprint at the hit.
    pub fn intersect_cone(&self, ray: &Ray, cone: &RayCone) -> Option<SurfaceHit<'_>> {
        let mut best: Option<(usize, Hit)> = None;
        let mut r = *ray;
        for (i, g) in self.geometries.iter().enumerate() {
            let hit = g.intersect(&r);
            if hit.is_hit() && best.is_none_or(|(_, b)| hit.t < b.t) {
                // Later geometries only need to beat this hit strictly; shrinking the
                // interval lets their structures cull.
                r.tmax = hit.t;
                best = Some((i, hit));
            }
        }
        let (i, hit) = best?;
        self.geometries[i].surface_cone(ray, &hit, i as u32, cone)
    }

    /// [`Self::intersect`] of each of a batch of coherent rays (a tile's camera rays, in
    /// pixel order), with the same answers: each geometry traces the whole batch through
    /// its coherent path (packets, where its structure has them), later geometries over
    /// intervals shortened by the earlier ones' hits exactly as `intersect` shortens them.
    pub fn intersect_coherent(&self, rays: &[Ray]) -> Vec<Option<SurfaceHit<'_>>> {
        self.intersect_coherent_cones(rays, &[])
    }

    /// [`Self::intersect_coherent`] with a footprint per ray: `cones[i]` is `rays[i]`'s
    /// ([`Self::intersect_cone`]); rays past the end of `cones` (all of them for an
    /// empty slice) look textures up at a point.
    pub fn intersect_coherent_cones(&self, rays: &[Ray], cones: &[RayCone]) -> Vec<Option<SurfaceHit<'_>>> {
        let mut best: Vec<Option<(usize, Hit)>> = vec![None; rays.len()];
        let mut shortened = rays.to_vec();
        let mut hits = vec![Hit::MISS; rays.len()];
        for (i, g) in self.geometries.iter().enumerate() {
            g.intersect_coherent_into(&shortened, &mut hits);
            for ((hit, b), r) in hits.iter().zip(&mut best).zip(&mut shortened) {
                if hit.is_hit() && b.is_none_or(|(_, bh)| hit.t < bh.t) {
                    r.tmax = hit.t;
                    *b = Some((i, *hit));
                }
            }
        }
        best.into_iter()
            .zip(rays)
            .enumerate()
            .map(|(k, (b, ray))| {
                let cone = cones.get(k).unwrap_or(&RayCone::POINT);
                b.and_then(|(i, hit)| self.geometries[i].surface_cone(ray, &hit, i as u32, cone))
            })
            .collect()
    }

    /// True when anything lies on `ray` within `[tmin, tmax]` (shadow rays).
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.geometries.iter().any(|g| g.occluded(ray))
    }

    /// Bounds of the whole scene (empty for a scene with nothing in it).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }
}

/// The frame's triangle mesh behind an acceleration structure built on it.
pub struct TriangleGeometry<'a> {
    frame: &'a Frame,
    accel: &'a dyn Accel,
    /// Used where a triangle's material index names no material.
    fallback: Material,
}

impl<'a> TriangleGeometry<'a> {
    /// The triangles of `frame.mesh`, traced through `accel` (built on that mesh).
    pub fn new(frame: &'a Frame, accel: &'a dyn Accel) -> Self {
        Self { frame, accel, fallback: Material::default() }
    }
}

impl Geometry for TriangleGeometry<'_> {
    fn intersect(&self, ray: &Ray) -> Hit {
        self.accel.intersect(ray)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.accel.occluded(ray)
    }

    fn intersect_coherent_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        self.accel.intersect_coherent_into(rays, hits);
    }

    fn surface<'a>(&'a self, ray: &Ray, hit: &Hit, geometry: u32) -> Option<SurfaceHit<'a>> {
        self.surface_cone(ray, hit, geometry, &RayCone::POINT)
    }

    fn surface_cone<'a>(&'a self, ray: &Ray, hit: &Hit, geometry: u32, cone: &RayCone) -> Option<SurfaceHit<'a>> {
        if !hit.is_hit() {
            return None;
        }
        let mesh = &self.frame.mesh;
        let prim = hit.prim as usize;
        let [i0, i1, i2] = *mesh.indices.get(prim)?;
        let vertex = |i: u32| mesh.positions.get(i as usize).map(|p| Vec3::from_array(*p));
        let (p0, p1, p2) = (vertex(i0)?, vertex(i1)?, vertex(i2)?);
        let (u, v) = (hit.u, hit.v);
        let w = 1.0 - u - v;
        let p = p0 * w + p1 * u + p2 * v;
        let mut ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        if ng == Vec3::ZERO || !ng.is_finite() {
            // A degenerate triangle has no plane: face the ray.
            ng = -ray.dir.normalize_or_zero();
        }
        // Vertex normals when present; zero (or unusable) ones mean "geometric normal"
        // (see `Scene::frame`, which pads actors without normals with zeros).
        let interpolated = mesh.normals.as_ref().and_then(|ns| {
            let n = |i: u32| ns.get(i as usize).map(|n| Vec3::from_array(*n));
            let s = n(i0)? * w + n(i1)? * u + n(i2)? * v;
            (s.is_finite() && s.length_squared() > 1e-12).then(|| s.normalize())
        });
        let corners = mesh.uvs.as_ref().and_then(|t| {
            let c = |i: u32| t.get(i as usize).map(|c| Vec2::from_array(*c));
            Some([c(i0)?, c(i1)?, c(i2)?])
        });
        let texcoords = corners.map(|[t0, t1, t2]| t0 * w + t1 * u + t2 * v);
        let material = self
            .frame
            .materials_of
            .get(prim)
            .and_then(|&m| self.frame.materials.get(m as usize))
            .unwrap_or(&self.fallback);
        // Without texture coordinates there is nothing to look a texture up with (the
        // barycentrics would stretch it over each triangle): untextured. Only a textured
        // hit pays for its footprint (the cone's width at the hit, in uv units).
        let texel = match (texcoords, corners, &material.diffuse_texture) {
            (Some(uv), Some(tc), Some(_)) => {
                let uv_width = if *cone == RayCone::POINT {
                    0.0
                } else {
                    let dist = hit.t * ray.dir.length();
                    cone::uv_width([p0, p1, p2], tc, ray.dir, cone.width_at(dist))
                };
                material.diffuse_texel_filtered(&self.frame.textures, uv, uv_width)
            }
            _ => Color::ONE,
        };
        Some(SurfaceHit {
            t: hit.t,
            p,
            ng,
            ns: interpolated.unwrap_or(ng),
            uv: texcoords.unwrap_or(Vec2::new(u, v)),
            material,
            texel,
            at: GeometryRef { geometry, instance: 0, prim: hit.prim },
        })
    }

    fn bounds(&self) -> Aabb {
        self.frame.mesh.bounds()
    }
}
