//! The built-in demo scene `dynray render` draws without arguments: a Whitted-style
//! still life of spheres and boxes over a checkerboard, with a mirror sphere, a glass
//! sphere, highlights and two lights, built only from the primitives of `shapes`.

use crate::shapes::{cuboid, uv_sphere};
use crate::{Actor, Camera, Color, Environment, Light, LightKind, Material, Projection, Scene, Settings};
use dynray_geom::Vec3;

/// Sphere detail of [`demo_scene`]: 64 stacks × 128 slices (≈16 k triangles per sphere),
/// smooth at 800 × 600 even in the mirror's reflections.
pub const DEMO_SPHERE_DETAIL: u32 = 64;

/// The demo scene at full detail (800 × 600, up to 6 ray levels).
pub fn demo_scene() -> Scene {
    demo_scene_with(DEMO_SPHERE_DETAIL)
}

/// The demo scene with spheres of `sphere_detail` stacks and `2 × sphere_detail` slices
/// (at least 2 and 4). Low details keep tests that trace it with brute force fast.
pub fn demo_scene_with(sphere_detail: u32) -> Scene {
    let stacks = sphere_detail.max(2);
    let slices = stacks * 2;
    let mut s = Scene::default();
    let mut material = |m: Material| {
        s.materials.push(m);
        s.materials.len() as u32 - 1
    };
    let matte = |name: &str, color: Color, ambient: f32| Material {
        name: name.into(),
        ambient: color * ambient,
        diffuse: color,
        spot: Color::ZERO,
        shine: 1.0,
        specular: Color::ZERO,
        transparency: Color::ZERO,
        ior: 1.0,
        diffuse_texture: None,
        emission: Color::ZERO,
        bsdf: None,
    };
    let cream = material(matte("cream", Color::new(0.85, 0.82, 0.72), 1.0));
    let terracotta =
        material(Material { specular: Color::splat(0.08), ..matte("terracotta", Color::new(0.62, 0.22, 0.12), 1.0) });
    let mirror = material(Material {
        spot: Color::splat(0.9),
        shine: 200.0,
        specular: Color::splat(0.85),
        ..matte("mirror", Color::splat(0.05), 1.0)
    });
    let glass = material(Material {
        spot: Color::splat(1.0),
        shine: 300.0,
        specular: Color::splat(0.1),
        transparency: Color::splat(0.88),
        ior: 1.5,
        ..matte("glass", Color::ZERO, 0.0)
    });
    let red = material(Material {
        spot: Color::splat(0.6),
        shine: 60.0,
        ..matte("red plastic", Color::new(0.75, 0.08, 0.06), 1.0)
    });
    let blue = material(Material {
        spot: Color::splat(0.5),
        shine: 40.0,
        specular: Color::splat(0.15),
        ..matte("blue", Color::new(0.1, 0.25, 0.75), 1.0)
    });
    let gold = material(Material {
        spot: Color::new(1.0, 0.9, 0.6),
        shine: 80.0,
        specular: Color::splat(0.3),
        ..matte("gold", Color::new(0.8, 0.6, 0.2), 1.0)
    });
    let mut actor = |name: &str, mesh, m| s.actors.push(Actor::new(Some(name.into()), mesh, m));

    // Checkerboard floor: 12 × 12 flat tiles of 2 × 2, top face at y = 0.
    let n = 12;
    for i in 0..n {
        for j in 0..n {
            let c = Vec3::new((i as f32 - n as f32 / 2.0 + 0.5) * 2.0, -0.1, (j as f32 - n as f32 / 2.0 + 0.5) * 2.0);
            let m = if (i + j) % 2 == 0 { cream } else { terracotta };
            actor("floor tile", cuboid(c, Vec3::new(2.0, 0.2, 2.0), Vec3::ZERO), m);
        }
    }
    actor("mirror sphere", uv_sphere(Vec3::new(-1.5, 1.3, -1.2), 1.3, stacks, slices), mirror);
    actor("glass sphere", uv_sphere(Vec3::new(0.9, 1.0, 1.6), 1.0, stacks, slices), glass);
    actor("red sphere", uv_sphere(Vec3::new(2.9, 0.8, -1.4), 0.8, stacks, slices), red);
    actor("blue sphere", uv_sphere(Vec3::new(-0.6, 0.45, 2.6), 0.45, stacks, slices), blue);
    actor("gold box", cuboid(Vec3::new(-3.1, 0.7, 0.9), Vec3::splat(1.4), Vec3::new(0.0, 30.0, 0.0)), gold);
    actor("tall box", cuboid(Vec3::new(1.2, 1.5, -4.0), Vec3::new(1.2, 3.0, 1.2), Vec3::new(0.0, -20.0, 0.0)), blue);

    s.lights.push(Light {
        kind: LightKind::Point { position: Vec3::new(7.0, 8.0, 3.0), falloff: 1 },
        color: Color::new(10.0, 9.6, 9.0),
        emitter_stand_in: false,
    });
    s.lights.push(Light {
        kind: LightKind::Directional { direction: Vec3::new(0.6, -1.0, -0.4) },
        color: Color::new(0.25, 0.28, 0.35),
        emitter_stand_in: false,
    });
    s.camera = Some(Camera {
        position: Vec3::new(0.0, 3.4, 9.5),
        look_at: Vec3::new(0.0, 0.9, 0.0),
        up: Vec3::Y,
        projection: Projection::Perspective { fov_y_deg: 42.0 },
        clip: crate::Clip::NONE,
    });
    s.settings = Settings { width: 800, height: 600, max_recursion_level: 6, min_weight: 0.01, spp: None };
    s.environment = Environment { background: Color::new(0.32, 0.48, 0.72), ambient: Color::splat(0.12), ior: 1.0 };
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demo_frame_is_valid_and_sized_by_detail() {
        for detail in [2, 8, DEMO_SPHERE_DETAIL] {
            let s = demo_scene_with(detail);
            let f = s.frame(0.0);
            f.mesh.validate().unwrap();
            assert_eq!(f.materials_of.len(), f.mesh.triangle_count());
            assert!(f.materials_of.iter().all(|&m| (m as usize) < f.materials.len()));
            assert_eq!(f.lights.len(), 2);
            let sphere_tris = 2 * detail as usize * 2 * detail as usize - 2 * 2 * detail as usize;
            assert_eq!(f.mesh.triangle_count(), 144 * 12 + 2 * 12 + 4 * sphere_tris, "detail {detail}");
        }
    }

    #[test]
    fn demo_has_a_mirror_and_a_glass_material_in_use() {
        let f = demo_scene().frame(0.0);
        let used = |pred: &dyn Fn(&Material) -> bool| f.materials_of.iter().any(|&m| pred(&f.materials[m as usize]));
        assert!(used(&|m| m.specular.min_element() > 0.5));
        assert!(used(&|m| m.transparency.min_element() > 0.5 && m.ior > 1.0));
    }
}
