//! The seed's stopping rules: a ray's level (primary = 1) must be below
//! `max_recursion_level` to spawn children, and a child is traced only when its weight
//! (parent weight × largest coefficient component) exceeds `min_weight`.

mod common;

use common::*;
use dynray_render::RenderStats;
use dynray_scene::shapes::cuboid;
use dynray_scene::{Color, Material};
use glam::Vec3;

/// A half-silvered plane facing a parallel camera at z = 3; a green wall behind the
/// camera is what the mirror shows. Returns the centre pixel and the stats.
fn mirror_plane(specular: Color, max_level: u32, min_weight: f32) -> (Color, RenderStats) {
    let mirror = Material { ambient: Color::new(0.5, 0.0, 0.0), specular, ..black() };
    let wall = Material { ambient: Color::new(0.0, 1.0, 0.0), ..black() };
    let mut f = frame(
        vec![
            (cuboid(Vec3::new(0.0, 0.0, -0.5), Vec3::new(20.0, 20.0, 1.0), Vec3::ZERO), mirror),
            (cuboid(Vec3::new(0.0, 0.0, 8.0), Vec3::new(20.0, 20.0, 1.0), Vec3::ZERO), wall),
        ],
        vec![],
        parallel(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 1.0),
        (3, 3),
        env(Color::ZERO, Color::ONE),
    );
    f.settings.max_recursion_level = max_level;
    f.settings.min_weight = min_weight;
    let (film, stats) = render_brute(&f);
    (film.get(1, 1).unwrap(), stats)
}

#[test]
fn level_one_traces_primary_rays_only() {
    let (c, stats) = mirror_plane(Color::splat(0.5), 1, 0.0);
    assert_eq!(stats.secondary_rays, 0);
    assert_close(c, Color::new(0.5, 0.0, 0.0), 1e-6, "ambient only");
    let (c, stats) = mirror_plane(Color::splat(0.5), 2, 0.0);
    assert_eq!(stats.secondary_rays, 9);
    assert_close(c, Color::new(0.5, 0.5, 0.0), 1e-6, "ambient + 0.5 × green wall");
}

#[test]
fn weight_is_the_largest_coefficient_component_and_must_exceed_min_weight() {
    // Largest component 0.5: a threshold of exactly 0.5 stops the ray, 0.49 lets it go.
    let spec = Color::new(0.1, 0.5, 0.2);
    let (_, stopped) = mirror_plane(spec, 10, 0.5);
    assert_eq!(stopped.secondary_rays, 0);
    let (c, traced) = mirror_plane(spec, 10, 0.49);
    assert_eq!(traced.secondary_rays, 9);
    assert_close(c, Color::new(0.5, 0.5, 0.0), 1e-6, "coefficient applied per channel");
}
