//! The camera's near and far clip planes (Mitsuba's `near_clip`/`far_clip`): a camera ray
//! sees only what lies between them, for every integrator, while shadow rays still see
//! what the near plane hides.

mod common;

use common::*;
use dynray_accel::Brute;
use dynray_geom::{TriangleMesh, Vec3};
use dynray_render::{render, render_aov, Aov, IntegratorKind, RenderOptions};
use dynray_scene::{Clip, Color, Frame, Material};

/// A square facing +z at depth `z`, half size `h`.
fn square(z: f32, h: f32) -> TriangleMesh {
    TriangleMesh::new(vec![[-h, -h, z], [h, -h, z], [h, h, z], [-h, h, z]], vec![[0, 1, 2], [0, 2, 3]])
}

/// A surface of flat colour `c`: under a white ambient light for Whitted, emitted
/// towards the camera for the path tracer.
fn flat(c: Color) -> Material {
    Material { ambient: c, diffuse: Color::ZERO, emission: c, ..black() }
}

/// A red square 1 in front of the eye hiding a green one 5 in front, eye at z = 5.
fn scene(clip: Clip) -> Frame {
    let mut camera = look(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0);
    camera.clip = clip;
    frame(
        vec![(square(4.0, 0.5), flat(Color::new(1.0, 0.0, 0.0))), (square(0.0, 10.0), flat(Color::new(0.0, 1.0, 0.0)))],
        vec![],
        camera,
        (9, 9),
        env(Color::new(0.0, 0.0, 1.0), Color::ONE),
    )
}

fn centre(frame: &Frame) -> Color {
    let accel = Brute::build(&frame.mesh).unwrap();
    render(frame, &accel, &RenderOptions::default()).0.get(4, 4).unwrap()
}

#[test]
fn near_plane_hides_what_lies_in_front_of_it_and_far_plane_what_lies_behind() {
    assert_close(centre(&scene(Clip::NONE)), Color::new(1.0, 0.0, 0.0), 1e-6, "no clip: the near square");
    assert_close(centre(&scene(Clip { near: 2.0, far: 1e4 })), Color::new(0.0, 1.0, 0.0), 1e-6, "near plane at 2");
    assert_close(centre(&scene(Clip { near: 2.0, far: 4.0 })), Color::new(0.0, 0.0, 1.0), 1e-6, "far plane at 4");
    // The far square's corner pixel lies at distance 5 / cos θ > 5 along its ray: a far
    // plane at 5.01 along the axis still keeps it, as Mitsuba's planes do.
    let f = scene(Clip { near: 2.0, far: 5.01 });
    let accel = Brute::build(&f.mesh).unwrap();
    let corner = render(&f, &accel, &RenderOptions::default()).0.get(0, 0).unwrap();
    assert_close(corner, Color::new(0.0, 1.0, 0.0), 1e-6, "corner inside the far plane");
}

#[test]
fn every_integrator_starts_camera_rays_at_the_near_plane() {
    let f = scene(Clip { near: 2.0, far: 1e4 });
    let accel = Brute::build(&f.mesh).unwrap();
    for integrator in IntegratorKind::ALL.iter().copied() {
        let options = RenderOptions { integrator, spp: 1, ..Default::default() };
        let c = render(&f, &accel, &options).0.get(4, 4).unwrap();
        assert_close(c, Color::new(0.0, 1.0, 0.0), 1e-5, &format!("{integrator:?}"));
    }
    // The depth AOV measures from the eye, not from the plane: the green square at 5.
    let depth = render_aov(&f, &accel, Aov::Depth, &RenderOptions::default()).get(4, 4).unwrap();
    assert_close(depth, Color::splat(5.0), 1e-5, "depth");
}
