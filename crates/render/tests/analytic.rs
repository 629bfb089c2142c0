//! Renders whose pixels are known in closed form: a head-on lit sphere, a shadow, a
//! mirror, an invisible ior-1 slab, and total internal reflection.

mod common;

use common::*;
use dynray_render::linear_to_srgb8;
use dynray_scene::shapes::{cuboid, uv_sphere};
use dynray_scene::{Color, Environment, Material};
use glam::Vec3;

#[test]
fn diffuse_sphere_lit_from_the_eye_is_brightest_at_the_centre() {
    // 32 stacks × 64 slices put a vertex (normal +z) exactly at the sphere's front.
    let m = Material { ambient: Color::splat(0.1), diffuse: Color::splat(0.8), ..black() };
    let eye = Vec3::new(0.0, 0.0, 4.0);
    let bg = Color::new(0.0, 0.0, 0.3);
    let f = frame(
        vec![(uv_sphere(Vec3::ZERO, 1.0, 32, 64), m)],
        vec![point(eye, Color::ONE)],
        look(eye, Vec3::ZERO, 40.0),
        (41, 41),
        env(bg, Color::splat(0.2)),
    );
    let (film, stats) = render_brute(&f);
    let lum = |c: Color| c.x + c.y + c.z;
    let centre = film.get(20, 20).unwrap();
    let brightest = film.pixels().iter().map(|&c| lum(c)).fold(f32::MIN, f32::max);
    assert_eq!(lum(centre), brightest, "centre {centre} is not the brightest pixel");
    // ambient 0.1 × 0.2 + diffuse 0.8 × (N·L = 1).
    assert_close(centre, Color::splat(0.82), 1e-4, "centre radiance");
    // Lambert falls off towards the silhouette; the corner sees the background.
    let near_rim = film.get(20, 20 - 12).unwrap();
    assert!(lum(near_rim) < 0.8 * lum(centre), "rim {near_rim} vs centre {centre}");
    assert_eq!(film.get(0, 0).unwrap(), bg);
    assert_eq!(stats.primary_rays, 41 * 41);
    assert!(stats.shadow_rays > 0 && stats.secondary_rays == 0, "{stats:?}");
}

#[test]
fn point_in_shadow_gets_only_ambient() {
    let floor_m = Material { ambient: Color::new(0.3, 0.4, 0.5), diffuse: Color::splat(0.7), ..black() };
    let ambient = Color::splat(0.5);
    let lights = [point(Vec3::new(0.0, 5.0, 0.0), Color::ONE), directional(Vec3::NEG_Y, Color::ONE)];
    for light in lights {
        let f = frame(
            vec![
                (cuboid(Vec3::new(0.0, -0.5, 0.0), Vec3::new(20.0, 1.0, 20.0), Vec3::ZERO), floor_m.clone()),
                (uv_sphere(Vec3::new(0.0, 1.5, 0.0), 0.5, 16, 32), Material { diffuse: Color::ONE, ..black() }),
            ],
            vec![light],
            // The odd image size puts pixel (40, 30)'s centre ray exactly on the look-at
            // point, the floor point straight under the sphere.
            look(Vec3::new(0.0, 3.0, 6.0), Vec3::ZERO, 50.0),
            (81, 61),
            env(Color::ZERO, ambient),
        );
        let (film, _) = render_brute(&f);
        let shadow = film.get(40, 30).unwrap();
        let want = floor_m.ambient * ambient;
        assert_close(shadow, want, 1e-6, &format!("{light:?}: shadowed floor"));
        assert_eq!(shadow.to_array().map(linear_to_srgb8), want.to_array().map(linear_to_srgb8));
        // The floor in front of the shadow is lit.
        let lit = film.get(40, 55).unwrap();
        assert!(lit.x > want.x + 0.3, "{light:?}: lit floor {lit} not brighter than ambient {want}");
    }
}

#[test]
fn mirror_sphere_shows_the_wall_at_its_centre_and_the_background_at_its_rim() {
    let bg = Color::new(0.2, 0.3, 0.9);
    let green = Color::new(0.0, 1.0, 0.0);
    let mirror = Material { specular: Color::ONE, ..black() };
    let wall = Material { ambient: green, ..black() };
    // Parallel camera at z = 3 looking down −z; the wall behind it faces the sphere.
    let (w, height) = (61u32, 2.5f32);
    let f = frame(
        vec![
            (uv_sphere(Vec3::ZERO, 1.0, 48, 96), mirror),
            (cuboid(Vec3::new(0.0, 0.0, 8.0), Vec3::new(40.0, 40.0, 1.0), Vec3::ZERO), wall),
        ],
        vec![],
        parallel(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, height),
        (w, w),
        env(bg, Color::ONE),
    );
    let (film, stats) = render_brute(&f);
    assert_close(film.get(30, 30).unwrap(), green, 1e-5, "sphere centre reflects the wall");
    // The pixel whose centre lies at 0.9–0.97 of the radius: the reflected ray leaves
    // backwards (z < 0) and escapes to the background.
    let x_of = |px: u32| ((px as f32 + 0.5) / w as f32 * 2.0 - 1.0) * height * 0.5;
    let rim = (31..w).find(|&px| (0.9..0.97).contains(&x_of(px))).unwrap();
    assert_close(film.get(rim, 30).unwrap(), bg, 1e-5, &format!("rim pixel {rim}"));
    assert_close(film.get(30, rim).unwrap(), bg, 1e-5, &format!("rim pixel (30, {rim})"));
    assert_eq!(film.get(0, 0).unwrap(), bg, "off the sphere");
    assert!(stats.secondary_rays > 0);
}

/// Red sphere, optionally behind a glass slab of `slab_ior` that transmits everything.
fn sphere_behind_slab(slab: bool, slab_ior: f32) -> dynray_render::Film {
    let red = Material {
        ambient: Color::new(0.3, 0.0, 0.0),
        diffuse: Color::new(0.8, 0.1, 0.1),
        spot: Color::splat(0.5),
        shine: 30.0,
        ..black()
    };
    let glass = Material { transparency: Color::ONE, ior: slab_ior, ..black() };
    let mut actors = vec![(uv_sphere(Vec3::ZERO, 1.0, 24, 48), red)];
    if slab {
        // Thick vertical slab (z from 2 to 4) between camera and sphere, larger than the view. Both lights
        // reach the sphere without crossing it (shadow rays treat glass as opaque).
        actors.push((cuboid(Vec3::new(0.0, 0.0, 3.0), Vec3::new(30.0, 30.0, 2.0), Vec3::ZERO), glass));
    }
    let f = frame(
        actors,
        vec![directional(Vec3::new(0.0, -1.0, 0.0), Color::splat(0.6)), point(Vec3::new(3.0, 2.0, 0.5), Color::ONE)],
        look(Vec3::new(0.0, 0.5, 6.0), Vec3::ZERO, 35.0),
        (64, 48),
        env(Color::new(0.1, 0.2, 0.3), Color::splat(0.3)),
    );
    render_brute(&f).0
}

#[test]
fn glass_of_ior_one_is_invisible() {
    let without = sphere_behind_slab(false, 1.0);
    let with = sphere_behind_slab(true, 1.0);
    let (a, b) = (without.to_srgb8(), with.to_srgb8());
    let differing = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    let max = a.iter().zip(&b).map(|(x, y)| x.abs_diff(*y)).max().unwrap();
    // The slab moves each ray's origin by two offsets (≈1e-5 of the scene), which can
    // flip an 8-bit rounding, nothing more.
    assert!(max <= 1 && differing * 100 <= a.len(), "{differing} bytes differ, by up to {max}");
    // And a slab of ior 1.5 does bend the rays: the image changes.
    let bent = sphere_behind_slab(true, 1.5).to_srgb8();
    let changed = a.iter().zip(&bent).filter(|(x, y)| x.abs_diff(**y) > 8).count();
    assert!(changed > a.len() / 50, "ior 1.5 changed only {changed} bytes");
}

/// Fresnel reflectance for unpolarised light, written out independently of the renderer:
/// `n1` the side the ray comes from, angle of incidence `theta_i`.
fn fresnel_reflectance(n1: f64, n2: f64, theta_i: f64) -> f64 {
    let sin_t = n1 / n2 * theta_i.sin();
    if sin_t >= 1.0 {
        return 1.0;
    }
    let (ci, ct) = (theta_i.cos(), sin_t.asin().cos());
    let rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
    let rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct);
    0.5 * (rs * rs + rp * rp)
}

#[test]
fn total_internal_reflection_sends_transmitted_energy_to_the_mirror_direction() {
    // The camera sits in a medium of ior 1.5 looking down at a block of "air" (ior 1):
    // beyond asin(1/1.5) ≈ 41.8° incidence the block reflects totally. A red floor under
    // the block shows when light gets through; the sky (background) shows otherwise.
    // Below the critical angle, Fresnel splits each crossing: with R at the top face (and
    // the same R at the bottom one, by reciprocity) and T = 1 − R, the light entering
    // goes down to the floor or bounces between the faces, A = (T·red + R·T·bg) / (1 − R²),
    // and the pixel is R·bg + T·A (less what the weight threshold cuts, < 1e-3).
    let bg = Color::new(0.1, 0.2, 0.9);
    let red = Color::new(1.0, 0.0, 0.0);
    for deg in [20.0f32, 40.0, 44.0, 60.0] {
        let r = fresnel_reflectance(1.5, 1.0, (deg as f64).to_radians()) as f32;
        let t = 1.0 - r;
        let want = if r == 1.0 { bg } else { r * bg + t * (t * red + r * t * bg) / (1.0 - r * r) };
        let dir = Vec3::new(0.0, -deg.to_radians().cos(), -deg.to_radians().sin());
        let f = frame(
            vec![
                (
                    cuboid(Vec3::new(0.0, -1.0, 0.0), Vec3::new(400.0, 2.0, 400.0), Vec3::ZERO),
                    Material { transparency: Color::ONE, ior: 1.0, ..black() },
                ),
                (
                    cuboid(Vec3::new(0.0, -3.5, 0.0), Vec3::new(400.0, 1.0, 400.0), Vec3::ZERO),
                    Material { ambient: red, ..black() },
                ),
            ],
            vec![],
            parallel(-dir * 10.0, Vec3::ZERO, 1.0),
            (11, 11),
            Environment { background: bg, ambient: Color::ONE, ior: 1.5 },
        );
        let (film, _) = render_brute(&f);
        let what = if r == 1.0 { format!("{deg}°: TIR") } else { format!("{deg}°: refracts, R = {r}") };
        assert_close(film.get(5, 5).unwrap(), want, if r == 1.0 { 1e-6 } else { 1e-3 }, &what);
        if r < 1.0 {
            assert!(want.x > 0.5 * (1.0 - r), "{what}: the floor shows");
        }
    }
}
