//! Shadow rays through transparent surfaces (`crates/render/src/shadow.rs`): a floor
//! point under a pane is lit by the light times the pane's filter, for clear, tinted
//! and stacked panes, and stays ambient-only under an opaque one.

mod common;

use common::*;
use dynray_render::shadow_filter;
use dynray_scene::shapes::cuboid;
use dynray_scene::{Color, Material};
use glam::Vec3;

/// The floor point under the panes (the centre pixel of an 81 × 61 image looking at the
/// origin), for a light straight above and panes of the given materials stacked at
/// heights 1, 2, 3 …
fn floor_under(panes: &[Material]) -> Color {
    let floor = Material { ambient: Color::splat(0.1), diffuse: Color::splat(0.5), ..black() };
    let mut actors = vec![(cuboid(Vec3::new(0.0, -0.5, 0.0), Vec3::new(20.0, 1.0, 20.0), Vec3::ZERO), floor)];
    for (i, m) in panes.iter().enumerate() {
        // Thin boxes: every pane is crossed twice (top and bottom face).
        let y = 1.0 + i as f32;
        actors.push((cuboid(Vec3::new(0.0, y, 0.0), Vec3::new(4.0, 0.05, 4.0), Vec3::ZERO), m.clone()));
    }
    let f = frame(
        actors,
        vec![point(Vec3::new(0.0, 10.0, 0.0), Color::ONE)],
        // Looks at the floor from the side, under the panes, so the camera ray itself
        // crosses no pane.
        look(Vec3::new(6.0, 0.5, 0.0), Vec3::ZERO, 30.0),
        (81, 61),
        env(Color::ZERO, Color::ONE),
    );
    let (film, stats) = render_brute(&f);
    assert!(stats.shadow_rays > 0);
    film.get(40, 30).unwrap()
}

fn glass(color: Color, transparency: f32) -> Material {
    Material { diffuse: color * 0.1, transparency: Color::splat(transparency), ior: 1.5, ..black() }
}

#[test]
fn no_pane_gives_ambient_plus_direct_light() {
    // ambient 0.1 × 1 + diffuse 0.5 × (N·L = 1).
    assert_close(floor_under(&[]), Color::splat(0.6), 1e-5, "unshadowed floor");
}

#[test]
fn opaque_pane_blocks_the_light() {
    let opaque = Material { diffuse: Color::splat(0.8), ..black() };
    assert_close(floor_under(&[opaque]), Color::splat(0.1), 1e-5, "under an opaque pane");
}

#[test]
fn clear_glass_dims_by_its_transparency_on_each_crossing() {
    let clear = Material { transparency: Color::splat(0.9), ior: 1.5, ..black() };
    assert_eq!(shadow_filter(&clear), Color::splat(0.9));
    // Two faces: 0.9².
    assert_close(floor_under(&[clear]), Color::splat(0.1 + 0.5 * 0.81), 1e-5, "under clear glass");
}

#[test]
fn tinted_glass_casts_a_tinted_shadow_and_panes_multiply() {
    let red = glass(Color::new(1.0, 0.5, 0.25), 0.8);
    let f = shadow_filter(&red);
    assert_close(f, Color::new(0.8, 0.4, 0.2), 1e-6, "filter");
    let one = floor_under(std::slice::from_ref(&red));
    assert_close(one, Color::splat(0.1) + 0.5 * f * f, 1e-5, "under one red pane");
    assert!(one.x > one.y && one.y > one.z, "the shadow is tinted: {one}");
    let two = floor_under(&[red.clone(), red]);
    assert_close(two, Color::splat(0.1) + 0.5 * f * f * f * f, 1e-5, "under two red panes");
}

#[test]
fn glass_over_opaque_still_blocks() {
    let clear = Material { transparency: Color::splat(0.9), ior: 1.5, ..black() };
    let opaque = Material { diffuse: Color::splat(0.8), ..black() };
    assert_close(floor_under(&[clear, opaque]), Color::splat(0.1), 1e-5, "glass above an opaque pane");
}
