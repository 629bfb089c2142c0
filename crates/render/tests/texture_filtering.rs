//! Texture filtering (issue 48): a checker-textured floor receding to the horizon,
//! rendered at one sample per pixel with mipmaps and ray cones, is much closer to a
//! supersampled reference than the same render without mipmaps, while the foreground,
//! where a pixel covers less than a texel, is untouched; the footprint survives a mirror
//! bounce; and every integrator filters.

mod common;

use common::*;
use dynray_accel::Brute;
use dynray_geom::{TriangleMesh, Vec3};
use dynray_render::{render, Film, IntegratorKind, RenderOptions};
use dynray_scene::{Color, Frame, Material, Texture, TextureRef};
use std::sync::Arc;

/// `n × n` texels of black and white squares `square` texels wide.
fn checker(n: u32, square: u32) -> Texture {
    let texels = (0..n * n).map(|i| Color::splat((((i % n) / square + (i / n) / square) % 2) as f32)).collect();
    Texture::from_linear("checker", n, n, texels).unwrap()
}

/// A material that shows its texture as it is under an ambient light of 1 (Whitted).
fn shows_texture() -> Material {
    Material { ambient: Color::ONE, diffuse_texture: Some(TextureRef::new(0)), ..black() }
}

/// A quad through `corners` (counter-clockwise seen from the side it faces) with uvs
/// `uvs` at them.
fn quad(corners: [Vec3; 4], uvs: [[f32; 2]; 4]) -> TriangleMesh {
    let mut m = TriangleMesh::new(corners.map(|c| c.to_array()).to_vec(), vec![[0, 1, 2], [0, 2, 3]]);
    m.uvs = Some(uvs.to_vec());
    m
}

/// The floor `y = 0`, 800 wide and 400 deep in front of a camera 1 above it, looking
/// slightly down: the horizon is near the top of the 96 × 64 image, the bottom row sees
/// the floor 2 units away. The texture is 512 × 512 with 8-texel squares, one image per
/// 64 × 64 units (a texel is 1/8 unit, a square 1 unit), repeated.
fn floor(texture: Texture) -> Frame {
    let s = 64.0;
    let (x, z) = (400.0, 400.0);
    let mesh = quad(
        [Vec3::new(-x, 0.0, 2.0), Vec3::new(x, 0.0, 2.0), Vec3::new(x, 0.0, -z), Vec3::new(-x, 0.0, -z)],
        [[-x / s, 2.0 / s], [x / s, 2.0 / s], [x / s, -z / s], [-x / s, -z / s]],
    );
    let camera = look(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, -6.0), 40.0);
    let mut f = frame(vec![(mesh, shows_texture())], vec![], camera, (96, 64), env(Color::ZERO, Color::ONE));
    f.settings.max_recursion_level = 1;
    f.textures = vec![Arc::new(texture)];
    f
}

fn render_with(frame: &Frame, integrator: IntegratorKind, spp: u32, threads: usize) -> Film {
    let accel = Brute::build(&frame.mesh).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| render(frame, &accel, &RenderOptions { spp, integrator, ..Default::default() }).0)
}

/// Root-mean-square difference over the rows `rows` (all channels).
fn rms(a: &Film, b: &Film, rows: std::ops::Range<u32>) -> f64 {
    let w = a.width();
    let (mut sum, mut n) = (0.0f64, 0usize);
    for y in rows {
        for x in 0..w {
            let d = a.get(x, y).unwrap() - b.get(x, y).unwrap();
            sum += d.length_squared() as f64 / 3.0;
            n += 1;
        }
    }
    (sum / n as f64).sqrt()
}

fn bits(f: &Film, rows: std::ops::Range<u32>) -> Vec<u32> {
    rows.flat_map(|y| (0..f.width()).flat_map(move |x| f.get(x, y).unwrap().to_array().map(f32::to_bits))).collect()
}

#[test]
fn a_receding_checker_floor_is_filtered_towards_the_supersampled_image() {
    let mipmapped = floor(checker(512, 8));
    let plain = floor(checker(512, 8).without_mipmaps());
    // The reference: 256 jittered samples per pixel of the unfiltered texture.
    let reference = render_with(&plain, IntegratorKind::Whitted, 256, 2);
    let filtered = render_with(&mipmapped, IntegratorKind::Whitted, 1, 2);
    let aliased = render_with(&plain, IntegratorKind::Whitted, 1, 2);
    let h = filtered.height();
    let (e_filtered, e_aliased) = (rms(&filtered, &reference, 0..h), rms(&aliased, &reference, 0..h));
    // The far floor: the 16 rows below the horizon (row 17).
    let far = 17..33;
    let (far_filtered, far_aliased) = (rms(&filtered, &reference, far.clone()), rms(&aliased, &reference, far));
    eprintln!(
        "RMS error against 256 spp: filtered 1 spp {e_filtered:.4}, unfiltered 1 spp {e_aliased:.4} \
         (far floor: {far_filtered:.4} vs {far_aliased:.4})"
    );
    assert!(e_filtered < 0.5 * e_aliased, "filtered {e_filtered:.4} vs unfiltered {e_aliased:.4}");
    assert!(far_filtered < 0.4 * far_aliased, "far floor: filtered {far_filtered:.4} vs unfiltered {far_aliased:.4}");
    // The foreground (the bottom 12 rows: a pixel covers under a texel there) reads
    // level 0: bit for bit the unfiltered image, as sharp as it was.
    assert!(bits(&filtered, h - 12..h) == bits(&aliased, h - 12..h), "the foreground was blurred");
    let fg = (0..filtered.width()).map(|x| filtered.get(x, h - 1).unwrap().x);
    let (lo, hi) = fg.fold((f32::MAX, f32::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    assert!(lo < 0.05 && hi > 0.95, "the nearest row keeps black and white squares: {lo} .. {hi}");
    // Deterministic: the filtered image does not depend on the thread count.
    let one = render_with(&mipmapped, IntegratorKind::Whitted, 1, 1);
    assert!(bits(&one, 0..h) == bits(&filtered, 0..h), "1 and 2 threads differ");
    // The cumulative integrator filters the same camera rays the same way.
    let cumulative = render_with(&mipmapped, IntegratorKind::Cumulative, 1, 2);
    assert!(rms(&cumulative, &filtered, 0..h) < 1e-6);
}

/// A `n × n` checker of 1-texel squares on a 2 × 2 quad facing the +x direction at
/// x = 3, seen by a parallel camera 2 units high looking down −z, either straight
/// (`mirror: false`, the quad turned to face the camera) or in a 45° mirror that turns
/// the rays towards +x. A pixel is 2/15 units: `64 · 2/15 / 2 ≈ 4.3` texels.
fn checker_seen(mirror: bool, texture: Texture) -> Frame {
    let uvs = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let camera = parallel(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 2.0);
    let mut actors = Vec::new();
    if mirror {
        let m = 1.5;
        let glass =
            quad([Vec3::new(-m, -m, m), Vec3::new(m, -m, -m), Vec3::new(m, m, -m), Vec3::new(-m, m, m)], [[0.0; 2]; 4]);
        actors.push((TriangleMesh { uvs: None, ..glass }, Material { specular: Color::ONE, ..black() }));
        let target = quad(
            [
                Vec3::new(3.0, -1.0, 1.0),
                Vec3::new(3.0, -1.0, -1.0),
                Vec3::new(3.0, 1.0, -1.0),
                Vec3::new(3.0, 1.0, 1.0),
            ],
            uvs,
        );
        actors.push((target, shows_texture()));
    } else {
        let target = quad(
            [
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
            ],
            uvs,
        );
        actors.push((target, shows_texture()));
    }
    let mut f = frame(actors, vec![], camera, (15, 15), env(Color::ZERO, Color::ONE));
    f.settings.max_recursion_level = 2;
    f.textures = vec![Arc::new(texture)];
    f
}

/// Largest distance of any pixel from grey 0.5.
fn off_grey(f: &Film) -> f32 {
    f.pixels().iter().map(|c| (*c - Color::splat(0.5)).abs().max_element()).fold(0.0, f32::max)
}

#[test]
fn the_footprint_goes_through_a_mirror() {
    for mirror in [false, true] {
        for kind in [IntegratorKind::Whitted, IntegratorKind::Cumulative] {
            // Every level from 1 down of a 1-texel checker is grey: a pixel of 4.3 texels
            // reads levels 2 and 3.
            let filtered = render_with(&checker_seen(mirror, checker(64, 1)), kind, 1, 2);
            assert!(off_grey(&filtered) < 1e-5, "mirror {mirror}, {kind}: {}", off_grey(&filtered));
            // Without mipmaps the same pixels hit black and white texels: the test sees
            // the difference.
            let aliased = render_with(&checker_seen(mirror, checker(64, 1).without_mipmaps()), kind, 1, 2);
            assert!(off_grey(&aliased) > 0.2, "mirror {mirror}, {kind}: {}", off_grey(&aliased));
        }
    }
}

#[test]
fn the_path_tracer_filters_too() {
    // The face-on checker lit along the view direction: direct light only (one
    // segment after the camera's), so the image is deterministic.
    let mut f = checker_seen(false, checker(64, 1));
    f.materials[0] = Material { diffuse: Color::ONE, diffuse_texture: Some(TextureRef::new(0)), ..black() };
    f.lights = vec![directional(Vec3::NEG_Z, Color::ONE)];
    f.settings.max_recursion_level = 1;
    // Every pixel sees the same grey (relative spread of its values), unfiltered not.
    let spread = |f: &Film| {
        let v: Vec<f32> = f.pixels().iter().map(|c| c.x).collect();
        let (lo, hi) = v.iter().fold((f32::MAX, f32::MIN), |(lo, hi), x| (lo.min(*x), hi.max(*x)));
        (hi - lo) / hi
    };
    let filtered = render_with(&f, IntegratorKind::Path, 1, 2);
    assert!(filtered.pixels()[0].x > 0.0 && spread(&filtered) < 1e-4, "{}", spread(&filtered));
    f.textures = vec![Arc::new(checker(64, 1).without_mipmaps())];
    let aliased = render_with(&f, IntegratorKind::Path, 1, 2);
    assert!(spread(&aliased) > 0.3, "{}", spread(&aliased));
}
