//! Hostile frames render without panicking and without NaN pixels.

mod common;

use common::*;
use dynray_accel::Brute;
use dynray_render::{render, RenderOptions};
use dynray_scene::shapes::{cuboid, uv_sphere};
use dynray_scene::{Color, Environment, LightKind, Material};
use glam::Vec3;

fn no_nan(film: &dynray_render::Film) -> bool {
    film.pixels().iter().all(|c| !c.is_nan())
}

#[test]
fn nan_materials_lights_and_settings_give_no_nan_pixels() {
    let nasty = Material {
        name: "nasty".into(),
        ambient: Color::new(f32::NAN, 1.0, f32::INFINITY),
        diffuse: Color::splat(f32::INFINITY),
        spot: Color::ONE,
        shine: f32::NAN,
        specular: Color::new(0.5, f32::NAN, 0.0),
        transparency: Color::splat(0.5),
        ior: f32::NAN,
        diffuse_texture: None,
        emission: Color::ZERO,
        bsdf: None,
    };
    let mut f = frame(
        vec![
            (uv_sphere(Vec3::ZERO, 1.0, 8, 16), nasty),
            (cuboid(Vec3::new(0.0, -2.0, 0.0), Vec3::splat(3.0), Vec3::ZERO), black()),
        ],
        vec![
            point(Vec3::new(0.0, 0.0, 0.5), Color::ONE), // inside the sphere
            point(Vec3::splat(f32::NAN), Color::ONE),
            directional(Vec3::ZERO, Color::ONE),
            directional(Vec3::NEG_Y, Color::splat(f32::NAN)),
        ],
        look(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0),
        (24, 18),
        Environment { background: Color::ONE, ambient: Color::ONE, ior: -3.0 },
    );
    f.lights.push(dynray_scene::Light {
        kind: LightKind::Point { position: Vec3::Y * 3.0, falloff: 40 },
        color: Color::ONE,
        emitter_stand_in: false,
    });
    f.settings.min_weight = f32::NAN;
    let (film, _) = render_brute(&f);
    assert!(no_nan(&film));
}

#[test]
fn broken_material_ids_and_short_normals_fall_back() {
    let mut f = frame(
        vec![(uv_sphere(Vec3::ZERO, 1.0, 8, 16), Material { diffuse: Color::ONE, ..black() })],
        vec![point(Vec3::new(0.0, 0.0, 5.0), Color::ONE)],
        look(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0),
        (16, 16),
        env(Color::ZERO, Color::ONE),
    );
    let accel = Brute::build(&f.mesh).unwrap();
    f.materials_of.iter_mut().for_each(|m| *m = 99);
    f.mesh.normals.as_mut().unwrap().truncate(3);
    let (film, _) = render(&f, &accel, &RenderOptions::default());
    assert!(no_nan(&film));
    // The default material is light grey; the sphere's centre is lit.
    assert!(film.get(8, 8).unwrap().x > 0.5, "{}", film.get(8, 8).unwrap());
}

#[test]
fn facing_mirrors_with_absurd_recursion_terminate() {
    let mirror = Material { specular: Color::ONE, ..black() };
    let mut f = frame(
        vec![
            (cuboid(Vec3::new(0.0, 0.0, -2.0), Vec3::new(50.0, 50.0, 0.1), Vec3::ZERO), mirror.clone()),
            (cuboid(Vec3::new(0.0, 0.0, 2.0), Vec3::new(50.0, 50.0, 0.1), Vec3::ZERO), mirror),
        ],
        vec![],
        look(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), 1.0), // narrow: no ray drifts off the mirrors
        (4, 4),
        env(Color::ONE, Color::ONE),
    );
    f.settings.max_recursion_level = u32::MAX;
    f.settings.min_weight = 0.0;
    let (film, stats) = render_brute(&f);
    assert!(no_nan(&film));
    // Capped at 64 levels: 63 bounces per pixel.
    assert_eq!(stats.secondary_rays, 16 * (dynray_render::MAX_LEVEL_CAP as u64 - 1));
}

#[test]
fn empty_image_renders_nothing() {
    let mut f = frame(
        vec![(uv_sphere(Vec3::ZERO, 1.0, 4, 8), black())],
        vec![],
        look(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0),
        (0, 7),
        env(Color::ZERO, Color::ONE),
    );
    f.settings.width = 0;
    let (film, stats) = render_brute(&f);
    assert_eq!((film.width(), film.height(), stats.total_rays(), stats.tiles), (0, 7, 0, 0));
}
