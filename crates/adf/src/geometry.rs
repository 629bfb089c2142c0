//! The field as a geometry of the scene-level intersector, so that every integrator and
//! AOV shades it with the engine's materials and lights, alone (`render FILE.adf`) or
//! placed by a `.scn` beside meshes (`adf { file … transform … }`).
//!
//! A placed field is marched in its own space: the ray's origin and direction are mapped
//! by the inverse transform and its direction is left unnormalised, so `t` means the
//! same in both spaces (an affine map keeps ratios along a line) and hits from fields and
//! triangles compare directly. Normals go back by the inverse transpose.

use crate::Adf;
use dynray_geom::{Aabb, Hit, Ray, Vec2, Vec3};
use dynray_render::{Geometry, GeometryRef, SurfaceHit};
use dynray_scene::{Color, Material};
use glam::Mat4;

/// A distance field in a scene with one material (primitive 0, uv = 0).
pub struct AdfGeometry<'a> {
    adf: &'a Adf,
    material: Material,
    /// `(to_world, to_field, normal_to_world)`; `None`: the field is in world space.
    placement: Option<(Mat4, Mat4, Mat4)>,
}

impl<'a> AdfGeometry<'a> {
    /// The field `adf` where it was built, shaded with `material`.
    pub fn new(adf: &'a Adf, material: Material) -> Self {
        Self { adf, material, placement: None }
    }

    /// The field moved by `to_world` (affine, invertible: a `.scn` checks both).
    pub fn placed(adf: &'a Adf, material: Material, to_world: Mat4) -> Self {
        let to_field = to_world.inverse();
        Self { adf, material, placement: Some((to_world, to_field, to_field.transpose())) }
    }

    /// The surface where `ray` (world space) meets the field at `t`, the field's gradient
    /// there being `g` (field space: the CPU's [`Adf::gradient`] or the device's).
    pub fn surface_at(&self, ray: &Ray, t: f32, g: Vec3, geometry: u32) -> SurfaceHit<'_> {
        let g = match &self.placement {
            None => g,
            Some((_, _, normal_to_world)) => normal_to_world.transform_vector3(g),
        };
        let mut n = g.normalize_or_zero();
        if n == Vec3::ZERO || !n.is_finite() {
            // A flat spot of the field (a saddle of the samples): face the ray.
            n = -ray.dir.normalize_or_zero();
        }
        SurfaceHit {
            t,
            p: ray.at(t),
            ng: n,
            ns: n,
            uv: Vec2::ZERO,
            material: &self.material,
            texel: Color::ONE,
            at: GeometryRef { geometry, instance: 0, prim: 0 },
        }
    }

    /// `ray` in the field's space (same `t` interval).
    fn local(&self, ray: &Ray) -> Ray {
        match &self.placement {
            None => *ray,
            Some((_, to_field, _)) => {
                Ray { origin: to_field.transform_point3(ray.origin), dir: to_field.transform_vector3(ray.dir), ..*ray }
            }
        }
    }
}

impl Geometry for AdfGeometry<'_> {
    fn intersect(&self, ray: &Ray) -> Hit {
        self.adf.march(&self.local(ray)).map_or(Hit::MISS, |t| Hit { t, u: 0.0, v: 0.0, prim: 0 })
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.adf.march(&self.local(ray)).is_some()
    }

    fn surface<'a>(&'a self, ray: &Ray, hit: &Hit, geometry: u32) -> Option<SurfaceHit<'a>> {
        if !hit.is_hit() {
            return None;
        }
        let local = self.local(ray);
        let mut hint = 0;
        Some(self.surface_at(ray, hit.t, self.adf.gradient(local.at(hit.t), &mut hint), geometry))
    }

    fn bounds(&self) -> Aabb {
        let b = self.adf.cube().bounds();
        match &self.placement {
            None => b,
            Some((to_world, _, _)) => Aabb::from_points((0..8).map(|i| {
                let corner = Vec3::new(
                    if i & 1 == 0 { b.min.x } else { b.max.x },
                    if i & 2 == 0 { b.min.y } else { b.max.y },
                    if i & 4 == 0 { b.min.z } else { b.max.z },
                );
                to_world.transform_point3(corner)
            })),
        }
    }
}
