//! Geometry that is not a triangle mesh renders through the same intersector and the
//! same Whitted shading as triangles: an analytic sphere beside a triangle floor, lit by
//! one light, casting its shadow on the floor and seen in the AOVs as geometry 1.

mod common;

use common::*;
use dynray_accel::Brute;
use dynray_geom::{Aabb, Hit, Ray, Vec2, Vec3};
use dynray_render::{
    render_with, Aov, AovIntegrator, Geometry, GeometryRef, RenderOptions, SceneIntersector, SurfaceHit,
    TriangleGeometry, Whitted,
};
use dynray_scene::{Color, Material};

/// A sphere solved in closed form (no triangles): prim 0, uv = (longitude, latitude) / π.
struct Sphere {
    centre: Vec3,
    radius: f32,
    material: Material,
}

impl Sphere {
    fn hit_t(&self, ray: &Ray) -> Option<f32> {
        let oc = ray.origin - self.centre;
        let (a, b, c) = (ray.dir.dot(ray.dir), oc.dot(ray.dir), oc.dot(oc) - self.radius * self.radius);
        let disc = b * b - a * c;
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        [(-b - s) / a, (-b + s) / a].into_iter().find(|t| *t >= ray.tmin && *t <= ray.tmax)
    }
}

impl Geometry for Sphere {
    fn intersect(&self, ray: &Ray) -> Hit {
        self.hit_t(ray).map_or(Hit::MISS, |t| Hit { t, u: 0.0, v: 0.0, prim: 0 })
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.hit_t(ray).is_some()
    }

    fn surface<'a>(&'a self, ray: &Ray, hit: &Hit, geometry: u32) -> Option<SurfaceHit<'a>> {
        let p = ray.at(hit.t);
        let n = ((p - self.centre) / self.radius).normalize();
        let uv = Vec2::new(n.z.atan2(n.x) / std::f32::consts::PI, n.y.acos() / std::f32::consts::PI);
        Some(SurfaceHit {
            t: hit.t,
            p,
            ng: n,
            ns: n,
            uv,
            material: &self.material,
            texel: Color::ONE,
            at: GeometryRef { geometry, instance: 0, prim: 0 },
        })
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(self.centre - Vec3::splat(self.radius), self.centre + Vec3::splat(self.radius))
    }
}

fn floor() -> dynray_geom::TriangleMesh {
    let p = vec![[-4.0, 0.0, -4.0], [4.0, 0.0, -4.0], [4.0, 0.0, 4.0], [-4.0, 0.0, 4.0]];
    dynray_geom::TriangleMesh::new(p, vec![[0, 2, 1], [0, 3, 2]])
}

#[test]
fn an_analytic_sphere_shades_and_shadows_like_triangles() {
    let matte = Material { diffuse: Color::splat(0.8), ..black() };
    let red = Material { diffuse: Color::new(0.9, 0.1, 0.1), ..black() };
    let frame = frame(
        vec![(floor(), matte)],
        vec![point(Vec3::new(0.0, 3.0, 6.0), Color::ONE)],
        look(Vec3::new(0.0, 6.0, 6.0), Vec3::ZERO, 50.0),
        (48, 48),
        env(Color::ZERO, Color::ZERO),
    );
    let brute = Brute::build(&frame.mesh).unwrap();
    let sphere = Sphere { centre: Vec3::new(0.0, 1.0, 0.0), radius: 1.0, material: red };
    let scene = SceneIntersector::new(vec![Box::new(TriangleGeometry::new(&frame, &brute)), Box::new(sphere)]);
    let whitted = Whitted::new(&frame, &scene);
    let (film, stats) = render_with(&frame, &whitted, &RenderOptions::default());
    assert!(stats.shadow_rays > 0);

    let prim = render_with(&frame, &AovIntegrator::new(Aov::Prim, &scene), &RenderOptions::default()).0;
    let depth = render_with(&frame, &AovIntegrator::new(Aov::Depth, &scene), &RenderOptions::default()).0;
    // The image centre looks at the sphere's front: red, lit from below the camera, nearer
    // than the floor.
    let c = film.get(24, 24).unwrap();
    assert!(c.x > 0.25 && c.x > 4.0 * c.y && c.x > 4.0 * c.z, "centre should be the lit red sphere: {c}");
    let centre_ray = dynray_render::CameraRays::new(&frame.camera, 48, 48).primary(24, 24);
    assert_eq!(prim.get(0, 0).unwrap().x, -1.0, "the top-left corner sees the sky");
    assert_eq!(scene.intersect(&centre_ray).map(|h| h.at.geometry), Some(1));
    assert_eq!(prim.get(24, 24).unwrap().x, 0.0);
    assert!(depth.get(24, 24).unwrap().x < (centre_ray.origin - Vec3::ZERO).length());

    // The floor under the sphere is occluded upwards; floor points near the camera are lit,
    // and the floor right behind the sphere, seen past its top, lies in its shadow (the
    // light is lower than the eye, so the shadow reaches further than the hidden floor).
    let shadowed = Ray::with_interval(Vec3::new(0.5, 1e-3, 0.5), Vec3::Y, 0.0, 10.0);
    assert!(scene.occluded(&shadowed), "the sphere must occlude the floor under it");
    let lit_corner = film.get(2, 46).unwrap();
    assert!(lit_corner.max_element() > 0.1, "floor near the camera should be lit: {lit_corner}");
    let camera = dynray_render::CameraRays::new(&frame.camera, 48, 48);
    let geometry_at = |y| scene.intersect(&camera.primary(24, y)).map(|h| h.at.geometry);
    let behind = (0..24).rev().find(|&y| geometry_at(y) == Some(0)).expect("floor above the sphere in the image");
    let below_shadow = film.get(24, behind).unwrap();
    assert!(below_shadow.max_element() < 1e-6, "floor just behind the sphere should be shadowed: {below_shadow}");
}

#[test]
fn equal_distances_go_to_the_lower_geometry_index() {
    struct Wall(Material, u32);
    impl Geometry for Wall {
        fn intersect(&self, ray: &Ray) -> Hit {
            // The plane z = 0, as a ray parameter.
            let t = -ray.origin.z / ray.dir.z;
            if t >= ray.tmin && t <= ray.tmax {
                Hit { t, u: 0.0, v: 0.0, prim: self.1 }
            } else {
                Hit::MISS
            }
        }
        fn occluded(&self, ray: &Ray) -> bool {
            self.intersect(ray).is_hit()
        }
        fn surface<'a>(&'a self, ray: &Ray, hit: &Hit, geometry: u32) -> Option<SurfaceHit<'a>> {
            Some(SurfaceHit {
                t: hit.t,
                p: ray.at(hit.t),
                ng: Vec3::Z,
                ns: Vec3::Z,
                uv: Vec2::ZERO,
                material: &self.0,
                texel: Color::ONE,
                at: GeometryRef { geometry, instance: 0, prim: hit.prim },
            })
        }
        fn bounds(&self) -> Aabb {
            Aabb::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0))
        }
    }
    let scene = SceneIntersector::new(vec![Box::new(Wall(black(), 7)), Box::new(Wall(black(), 9))]);
    let hit = scene.intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z)).unwrap();
    assert_eq!((hit.at.geometry, hit.at.prim, hit.t), (0, 7, 5.0));
}
