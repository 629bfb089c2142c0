//! The path tracer on scenes whose answer is known: the furnace (a closed emitting and
//! reflecting sphere around the camera), the three light-gathering strategies converging
//! to one image, and images that do not depend on the thread count.
//!
//! Every render has fixed seeds, so each test is deterministic; tolerances are set from
//! the renders' own noise (the spread of independent pixels), at several standard errors,
//! so that they hold for any seed yet fail on a wrong factor of a few per cent.

mod common;

use common::{env, frame, look};
use dynray_accel::AccelSpec;
use dynray_geom::TriangleMesh;
use dynray_render::{render_with, Film, IntegratorKind, PathStrategy, PathTracer, RenderOptions, SceneIntersector};
use dynray_scene::shapes::{cuboid, icosphere};
use dynray_scene::{Bsdf, BsdfKind, Color, Frame, Light, LightKind, Material, Microfacet, Roughness};
use glam::Vec3;

fn diffuse(rho: f32) -> Material {
    Material { bsdf: Some(Bsdf::diffuse(Color::splat(rho))), ..common::black() }
}

fn render_path(frame: &Frame, spp: u32, seed: u64, strategy: PathStrategy) -> Film {
    let accel = "bvh".parse::<AccelSpec>().unwrap().build(&frame.mesh, None).unwrap();
    let scene = SceneIntersector::triangles(frame, accel.as_ref());
    let tracer = PathTracer::new(frame, &scene).with_strategy(strategy);
    render_with(frame, &tracer, &RenderOptions { spp, seed, integrator: IntegratorKind::Path, ..Default::default() }).0
}

/// Mean of the green channel over all pixels and its standard error (pixels are
/// independent estimates).
fn mean_and_error(f: &Film) -> (f64, f64) {
    let px: Vec<f64> = f.pixels().iter().map(|c| c.y as f64).collect();
    let n = px.len() as f64;
    let mean = px.iter().sum::<f64>() / n;
    let var = px.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// A sphere with its faces turned inwards, so that its inside is the front side.
fn inward_sphere(radius: f32) -> TriangleMesh {
    let mut m = icosphere(Vec3::ZERO, radius, 3);
    for t in &mut m.indices {
        t.swap(1, 2);
    }
    if let Some(ns) = &mut m.normals {
        for n in ns {
            *n = n.map(|c| -c);
        }
    }
    m
}

fn furnace(rho: f32, emission: f32, max_depth: u32) -> Frame {
    let wall = Material { emission: Color::splat(emission), ..diffuse(rho) };
    let mut f = frame(
        vec![(inward_sphere(3.0), wall)],
        vec![],
        look(Vec3::ZERO, Vec3::Z, 60.0),
        (16, 16),
        env(Color::ZERO, Color::ZERO),
    );
    f.settings.max_recursion_level = max_depth - 1;
    f
}

/// Inside a closed sphere that emits `Le` and reflects `ρ` everywhere, every path of
/// `D` segments sees `Le Σ_{k<D} ρᵏ` (`Le / (1 − ρ)` unbounded), whatever the sphere's
/// shape or tessellation: the integrator's emission, light sampling, MIS, BSDF
/// sampling, depth count and Russian roulette must all be right to get it.
#[test]
fn furnace_converges_to_the_emitted_radiance() {
    let (rho, le) = (0.6f32, 0.5f32);
    for depth in [1u32, 2, 3, 6, 40] {
        let f = render_path(&furnace(rho, le, depth), 64, 7, PathStrategy::Mis);
        let (mean, err) = mean_and_error(&f);
        let want: f64 = (0..depth).map(|k| le as f64 * (rho as f64).powi(k as i32)).sum();
        let tol = 4.0 * err + 1e-6;
        assert!((mean - want).abs() <= tol, "depth {depth}: mean {mean}, want {want} ± {tol}");
        assert!((mean - want).abs() <= 0.01 * want, "depth {depth}: mean {mean}, want {want} within 1 %");
    }
}

/// The same furnace with every path ending by Russian roulette only (no depth limit
/// reached): `Le / (1 − ρ)`.
#[test]
fn furnace_unbounded_is_le_over_one_minus_rho() {
    let (rho, le) = (0.8f32, 0.25f32);
    let f = render_path(&furnace(rho, le, 1024), 64, 3, PathStrategy::Mis);
    let (mean, err) = mean_and_error(&f);
    let want = le as f64 / (1.0 - rho as f64);
    assert!((mean - want).abs() <= 4.0 * err && (mean - want).abs() < 0.015 * want, "mean {mean} ± {err}, want {want}");
}

/// A lamp (an emitting quad facing down) over a diffuse floor, a rough metal box and a
/// glass-like Phong sphere: light sampling only, BSDF sampling only and their MIS
/// combination estimate the same image.
fn lamp_scene(max_depth: u32) -> Frame {
    let floor = cuboid(Vec3::new(0.0, -0.5, 0.0), Vec3::new(8.0, 1.0, 8.0), Vec3::ZERO);
    let metal = Material {
        bsdf: Some(Bsdf {
            kind: BsdfKind::Conductor {
                eta: Color::new(0.2, 0.92, 1.1),
                k: Color::new(3.9, 2.45, 2.14),
                specular_reflectance: Color::ONE,
                roughness: Some(Roughness { distribution: Microfacet::Ggx, alpha_u: 0.3, alpha_v: 0.3 }),
            },
            two_sided: false,
        }),
        ..common::black()
    };
    let plastic =
        Material { diffuse: Color::new(0.6, 0.2, 0.2), spot: Color::splat(0.3), shine: 20.0, ..common::black() };
    let lamp_mesh = TriangleMesh {
        positions: vec![[-0.5, 2.0, -0.5], [0.5, 2.0, -0.5], [0.5, 2.0, 0.5], [-0.5, 2.0, 0.5]],
        // Wound so that the normal points down (-y), towards the scene.
        indices: vec![[0, 1, 2], [0, 2, 3]],
        normals: None,
        uvs: None,
    };
    let lamp = Material { emission: Color::splat(4.0), ..diffuse(0.5) };
    let mut f = frame(
        vec![
            (floor, diffuse(0.7)),
            (cuboid(Vec3::new(-0.6, 0.3, 0.0), Vec3::splat(0.6), Vec3::new(0.0, 30.0, 0.0)), metal),
            (icosphere(Vec3::new(0.6, 0.35, 0.2), 0.35, 3), plastic),
            (lamp_mesh, lamp),
        ],
        vec![],
        look(Vec3::new(0.0, 1.2, 3.5), Vec3::new(0.0, 0.4, 0.0), 45.0),
        (24, 18),
        env(Color::ZERO, Color::ZERO),
    );
    f.settings.max_recursion_level = max_depth - 1;
    f
}

#[test]
fn light_sampling_bsdf_sampling_and_mis_agree() {
    for depth in [2u32, 4] {
        let scene = lamp_scene(depth);
        let runs: Vec<(PathStrategy, f64, f64)> = [PathStrategy::Mis, PathStrategy::Light, PathStrategy::Bsdf]
            .into_iter()
            .map(|s| {
                let spp = if s == PathStrategy::Bsdf { 1024 } else { 256 };
                let (m, e) = mean_and_error(&render_path(&scene, spp, 11, s));
                (s, m, e)
            })
            .collect();
        let (_, mis, mis_err) = runs[0];
        assert!(mis > 0.01, "depth {depth}: the lamp lights the scene ({mis})");
        for &(s, m, e) in &runs[1..] {
            let tol = 4.0 * (e * e + mis_err * mis_err).sqrt();
            assert!((m - mis).abs() <= tol, "depth {depth}: {s:?} mean {m} ± {e} vs MIS {mis} ± {mis_err}");
        }
        // MIS is the least noisy of the three.
        assert!(runs[0].2 <= runs[2].2, "depth {depth}: MIS error {} vs BSDF-only {}", runs[0].2, runs[2].2);
    }
}

/// A point light on a diffuse floor: direct light only, the closed form `ρ/π · I cos/d²`
/// (the light's colour is `I / π`, so `ρ · colour · cos / d²`) at every pixel centre.
#[test]
fn point_light_direct_lighting_is_exact() {
    let floor = cuboid(Vec3::new(0.0, -0.5, 0.0), Vec3::new(20.0, 1.0, 20.0), Vec3::ZERO);
    let light = Light {
        kind: LightKind::Point { position: Vec3::new(0.0, 2.0, 0.0), falloff: 2 },
        color: Color::splat(3.0),
        emitter_stand_in: false,
    };
    let mut f = frame(
        vec![(floor, diffuse(0.5))],
        vec![light],
        common::parallel(Vec3::new(0.0, 5.0, 0.0), Vec3::ZERO, 4.0),
        (9, 9),
        env(Color::ZERO, Color::ZERO),
    );
    f.camera.up = Vec3::Z;
    f.settings.max_recursion_level = 1;
    let film = render_path(&f, 1, 0, PathStrategy::Mis);
    for (y, x) in [(4u32, 4u32), (0, 0), (2, 7)] {
        let px = Vec3::new((x as f32 + 0.5) / 9.0 * 4.0 - 2.0, 0.0, (y as f32 + 0.5) / 9.0 * 4.0 - 2.0);
        let to = Vec3::new(0.0, 2.0, 0.0) - px;
        let want = 0.5 * 3.0 * (to.y / to.length()) / to.length_squared();
        let got = film.get(x, y).unwrap().y;
        assert!((got - want).abs() <= 1e-4 * want, "pixel ({x}, {y}): {got} vs {want}");
    }
}

/// Rayon pools of one and two threads give the same image, bit for bit.
#[test]
fn path_traced_image_is_identical_with_one_and_two_threads() {
    let scene = lamp_scene(6);
    let accel = "bvh".parse::<AccelSpec>().unwrap().build(&scene.mesh, None).unwrap();
    let bits = |threads: usize| -> Vec<u32> {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let film = pool.install(|| {
            dynray_render::render(
                &scene,
                accel.as_ref(),
                &RenderOptions {
                    spp: 8,
                    seed: 5,
                    integrator: IntegratorKind::Path,
                    tile_size: 5,
                    ..Default::default()
                },
            )
            .0
        });
        film.pixels().iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect()
    };
    let one = bits(1);
    assert!(one.iter().any(|&b| b != 0));
    assert!(one == bits(2), "1-thread and 2-thread path-traced films differ");
}
