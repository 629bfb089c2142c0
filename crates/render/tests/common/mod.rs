//! Small scene builders shared by the renderer's integration tests.
#![allow(dead_code)] // each test file uses a different subset

use dynray_accel::Brute;
use dynray_geom::{TriangleMesh, Vec3};
use dynray_render::{render, Film, RenderOptions, RenderStats};
use dynray_scene::{
    Actor, Camera, Clip, Color, Environment, Frame, Light, LightKind, Material, Projection, Scene, Settings,
};

/// A material with every coefficient zero (black, opaque, not reflective), ior 1.
pub fn black() -> Material {
    Material {
        name: "test".into(),
        ambient: Color::ZERO,
        diffuse: Color::ZERO,
        spot: Color::ZERO,
        shine: 1.0,
        specular: Color::ZERO,
        transparency: Color::ZERO,
        ior: 1.0,
        diffuse_texture: None,
        emission: Color::ZERO,
        bsdf: None,
    }
}

/// A frame of `actors` (each mesh with its own material), lights and camera.
pub fn frame(
    actors: Vec<(TriangleMesh, Material)>,
    lights: Vec<Light>,
    camera: Camera,
    (width, height): (u32, u32),
    environment: Environment,
) -> Frame {
    let mut s = Scene { lights, camera: Some(camera), environment, ..Default::default() };
    s.settings = Settings { width, height, max_recursion_level: 10, min_weight: 0.001, spp: None };
    for (mesh, m) in actors {
        s.materials.push(m);
        s.actors.push(Actor::new(None, mesh, s.materials.len() as u32 - 1));
    }
    s.frame(0.0)
}

/// Perspective camera.
pub fn look(position: Vec3, look_at: Vec3, fov_y_deg: f32) -> Camera {
    Camera { position, look_at, up: Vec3::Y, projection: Projection::Perspective { fov_y_deg }, clip: Clip::NONE }
}

/// Parallel camera.
pub fn parallel(position: Vec3, look_at: Vec3, height: f32) -> Camera {
    Camera { position, look_at, up: Vec3::Y, projection: Projection::Parallel { height }, clip: Clip::NONE }
}

/// A point light without attenuation.
pub fn point(position: Vec3, color: Color) -> Light {
    Light { kind: LightKind::Point { position, falloff: 0 }, color, emitter_stand_in: false }
}

/// A directional light travelling along `direction`.
pub fn directional(direction: Vec3, color: Color) -> Light {
    Light { kind: LightKind::Directional { direction }, color, emitter_stand_in: false }
}

/// Environment with the given background and ambient light, medium ior 1.
pub fn env(background: Color, ambient: Color) -> Environment {
    Environment { background, ambient, ior: 1.0 }
}

/// Renders with brute force on the current pool.
pub fn render_brute(frame: &Frame) -> (Film, RenderStats) {
    let accel = Brute::build(&frame.mesh).expect("test scenes are valid meshes");
    render(frame, &accel, &RenderOptions::default())
}

/// Asserts two colours agree within `tol` per channel.
#[track_caller]
pub fn assert_close(got: Color, want: Color, tol: f32, what: &str) {
    assert!((got - want).abs().max_element() <= tol, "{what}: got {got}, want {want}");
}
