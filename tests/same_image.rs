//! `dynray render --accel NAME` produces the same image for every NAME.
//!
//! Every structure returns brute force's closest hit bit for bit (same triangle, same
//! `t`, same u/v), and the renderer's shading depends only on those hits, so the films
//! of all structures must be identical down to the `f32` bits: not merely close. A
//! difference means a structure returned a different hit somewhere (or an occlusion
//! answer that disagrees), which the oracle tests' ray sets missed.

mod support;

use dynray_accel::AccelKind;
use dynray_render::{render, Film, RenderOptions, RenderStats};
use dynray_scene::demo::demo_scene_with;
use support::{dynray, ok};

/// Renders the demo scene (sphere detail 8, 96 × 72) with `kind`.
fn demo_film(kind: AccelKind) -> (Film, RenderStats) {
    let mut frame = demo_scene_with(8).frame(0.0);
    frame.settings.width = 96;
    frame.settings.height = 72;
    let accel = kind.build(&frame.mesh).unwrap_or_else(|e| panic!("{kind}: {e}"));
    render(&frame, accel.as_ref(), &RenderOptions::default())
}

/// The first pixel whose channels differ in their bits, as `(x, y, got, want)`.
fn first_difference(got: &Film, want: &Film) -> Option<(u32, u32, [f32; 3], [f32; 3])> {
    let w = want.width() as usize;
    got.pixels().iter().zip(want.pixels()).enumerate().find_map(|(i, (g, r))| {
        let (g, r) = (g.to_array(), r.to_array());
        (g.map(f32::to_bits) != r.map(f32::to_bits)).then_some(((i % w) as u32, (i / w) as u32, g, r))
    })
}

#[test]
fn every_structure_renders_the_demo_scene_bit_identically_to_the_bvh() {
    let (reference, ref_stats) = demo_film(AccelKind::Bvh2);
    assert!(ref_stats.secondary_rays > 0 && ref_stats.shadow_rays > 0, "{ref_stats:?}");
    // The scene must have something on screen, or equality would prove nothing.
    let first = reference.pixels()[0];
    assert!(reference.pixels().iter().any(|p| *p != first), "the demo renders as one colour");
    let mut failures = Vec::new();
    // Brute force is included: at this size and detail it takes well under a second.
    for &kind in AccelKind::ALL.iter().filter(|&&k| k != AccelKind::Bvh2) {
        let (film, stats) = demo_film(kind);
        assert_eq!((film.width(), film.height()), (96, 72), "{kind}");
        if let Some((x, y, got, want)) = first_difference(&film, &reference) {
            failures.push(format!("{kind}: first differing pixel ({x}, {y}): {got:?}, bvh {want:?}"));
        } else if stats != ref_stats {
            failures.push(format!("{kind}: same image but different ray counts: {stats:?}, bvh {ref_stats:?}"));
        }
    }
    assert!(failures.is_empty(), "films differ from the BVH's:\n{}", failures.join("\n"));
}

#[test]
fn the_binary_writes_the_same_png_for_every_accel_it_is_given() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str| {
        let out = dir.path().join(format!("{name}.png"));
        ok(dynray(&[
            "render",
            "examples/seed_examples.scn",
            "-o",
            out.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "48",
            "--accel",
            name,
        ]));
        std::fs::read(&out).unwrap_or_else(|e| panic!("{name}: {}: {e}", out.display()))
    };
    let reference = run("bvh");
    let img = image::load_from_memory(&reference).expect("bvh wrote a PNG").to_rgb8();
    assert_eq!(img.dimensions(), (64, 48));
    // One structure from each family: the oracle, a kd-tree without a stack, A-buffers.
    for name in ["brute", "kdtree-ropes", "apit"] {
        let got = run(name);
        if got != reference {
            let got = image::load_from_memory(&got).expect("a PNG").to_rgb8();
            let at = got.pixels().zip(img.pixels()).position(|(a, b)| a != b);
            let (x, y) = at.map_or((0, 0), |i| (i as u32 % 64, i as u32 / 64));
            panic!(
                "--accel {name} wrote a different PNG than --accel bvh; first differing pixel ({x}, {y}): {:?} vs {:?}",
                got.get_pixel(x, y),
                img.get_pixel(x, y)
            );
        }
    }
}

#[test]
fn first_difference_finds_one_changed_bit() {
    let (a, _) = demo_film(AccelKind::Bvh2);
    assert!(first_difference(&a, &a).is_none());
    let mut b = a.clone();
    let c = a.get(17, 5).unwrap();
    b.set(17, 5, dynray_scene::Color::new(f32::from_bits(c.x.to_bits() ^ 1), c.y, c.z));
    let (x, y, _, _) = first_difference(&b, &a).expect("one bit differs");
    assert_eq!((x, y), (17, 5));
}
