//! Textures as the renderer shows them: a textured quad seen face-on shows the image the
//! right way up in both the Whitted image and the `albedo` AOV, the ambient term is
//! textured too, geometry without uvs stays untextured, and the Duck's albedo is the
//! yellow of its texture rather than the grey it rendered before textures.

mod common;

use common::*;
use dynray_accel::Brute;
use dynray_geom::{TriangleMesh, Vec3};
use dynray_render::{render, render_aov, Aov, RenderOptions};
use dynray_scene::{load_file, Actor, Color, Material, Scene, Settings, Texture, TextureRef};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A unit quad in the z = 0 plane, facing +z, with uvs (0,0) at the bottom-left corner.
fn quad(uvs: bool) -> TriangleMesh {
    let mut m = TriangleMesh::new(
        vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    if uvs {
        m.uvs = Some(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    }
    m
}

/// 2 × 2 texels: top row red, green; bottom row blue, white.
fn quad_texture() -> Arc<Texture> {
    Arc::new(Texture::from_linear("quad", 2, 2, vec![Color::X, Color::Y, Color::Z, Color::ONE]).unwrap())
}

/// The quad seen face-on by a parallel camera that it fills, 6 × 6 pixels: the centres
/// of pixels 1 and 4 are at u (and v) = ¼ and ¾, the texel centres.
fn textured_scene(material: Material, uvs: bool, lights: Vec<dynray_scene::Light>, ambient: Color) -> Scene {
    let mut s = Scene {
        materials: vec![material],
        textures: vec![quad_texture()],
        lights,
        camera: Some(parallel(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 2.0)),
        environment: env(Color::ZERO, ambient),
        settings: Settings { width: 6, height: 6, max_recursion_level: 1, min_weight: 0.01, spp: None },
        ..Default::default()
    };
    s.actors.push(Actor::new(None, quad(uvs), 0));
    s
}

fn textured(diffuse: Color, ambient: Color) -> Material {
    Material { diffuse, ambient, diffuse_texture: Some(TextureRef::new(0)), ..black() }
}

#[test]
fn a_face_on_quad_shows_its_texture_the_right_way_up() {
    // A light along the view direction: every pixel sees diffuse × texel × (n·l = 1).
    let light = directional(Vec3::new(0.0, 0.0, -1.0), Color::ONE);
    let frame = textured_scene(textured(Color::splat(0.5), Color::ZERO), true, vec![light], Color::ZERO).frame(0.0);
    let accel = Brute::build(&frame.mesh).unwrap();
    let (img, _) = render(&frame, &accel, &RenderOptions::default());
    let albedo = render_aov(&frame, &accel, Aov::Albedo, &RenderOptions::default());
    // Pixel (1, 1) is in the image's top-left quarter, (4, 4) in its bottom-right; the
    // texel centres are there, so bilinear filtering gives the texel itself.
    for (x, y, texel, what) in [
        (1, 1, Color::X, "top-left red"),
        (4, 1, Color::Y, "top-right green"),
        (1, 4, Color::Z, "bottom-left blue"),
        (4, 4, Color::ONE, "bottom-right white"),
    ] {
        assert_close(img.get(x, y).unwrap(), texel * 0.5, 1e-4, what);
        assert_close(albedo.get(x, y).unwrap(), texel * 0.5, 1e-4, what);
    }
}

#[test]
fn ambient_light_is_textured_too() {
    let frame = textured_scene(textured(Color::ZERO, Color::splat(0.5)), true, vec![], Color::ONE).frame(0.0);
    let accel = Brute::build(&frame.mesh).unwrap();
    let (img, _) = render(&frame, &accel, &RenderOptions::default());
    assert_close(img.get(1, 1).unwrap(), Color::new(0.5, 0.0, 0.0), 1e-4, "ambient × red");
    assert_close(img.get(1, 4).unwrap(), Color::new(0.0, 0.0, 0.5), 1e-4, "ambient × blue");
}

#[test]
fn geometry_without_uvs_is_untextured() {
    let frame = textured_scene(textured(Color::splat(0.5), Color::ZERO), false, vec![], Color::ZERO).frame(0.0);
    let accel = Brute::build(&frame.mesh).unwrap();
    let albedo = render_aov(&frame, &accel, Aov::Albedo, &RenderOptions::default());
    for (x, y) in [(1, 1), (4, 1), (1, 4), (4, 4)] {
        assert_close(albedo.get(x, y).unwrap(), Color::splat(0.5), 0.0, "plain diffuse");
    }
}

fn model(rel: &str) -> Option<PathBuf> {
    let here = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes").join(rel);
    let found = [here, Path::new("/work/shared/scenes").join(rel)].into_iter().find(|p| p.is_file());
    if found.is_none() {
        eprintln!("skipped: {rel} not found under shared/scenes");
    }
    found
}

#[test]
fn the_duck_is_yellow_not_grey() {
    for rel in ["Duck/glTF/Duck.gltf", "Duck/glTF-Binary/Duck.glb"] {
        let Some(p) = model(rel) else { return };
        let mut scene = load_file(&p).unwrap();
        scene.settings.width = 32;
        scene.settings.height = 24;
        let frame = scene.frame(0.0);
        let accel = Brute::build(&frame.mesh).unwrap();
        let albedo = render_aov(&frame, &accel, Aov::Albedo, &RenderOptions::default());
        // The default camera frames the bounding box; its centre ray hits the body.
        let c = albedo.get(16, 12).unwrap();
        // Untextured, this was the white factor × 0.9: equal channels.
        assert!(c.x > 0.4 && c.y > 0.25 && c.z < 0.25 * c.x, "{rel}: albedo at the centre is {c}, not yellow");
        let (img, _) = render(&frame, &accel, &RenderOptions::default());
        let c = img.get(16, 12).unwrap();
        assert!(c.x > 2.0 * c.z && c.y > 1.5 * c.z, "{rel}: shaded colour at the centre is {c}, not yellow");
    }
}
