//! The example scenes round trip (issue 3): every `examples/*.scn` loads, renders with the
//! BVH at 160 × 120 and matches its golden image `tests/golden/<stem>_160x120.png`
//! within the render crate's tolerance; and each renders through the `dynray` binary.
//!
//! A file with no objects (`materials.scn`, definitions for `include`) is checked to
//! load and to provide what it promises, and is not rendered. `bunny.scn` reads
//! `../../shared/scenes/bunny/bun_zipper.ply` relative to `examples/`, i.e. the shared
//! models beside the checkout.
//!
//! After a deliberate change to the renderer, the parser or an example, look at the new
//! images and regenerate the goldens with
//!
//! ```text
//! DYNRAY_BLESS=1 cargo test --test examples
//! ```

mod support;

use dynray_accel::{Bvh, BvhParams};
use dynray_render::{render, RenderOptions, RenderStats};
use dynray_scene::{load_file, parse_scn_str, Scene};
use std::path::PathBuf;
use support::{check_golden, dynray, examples_dir, ok};

/// The golden size: small enough that each example renders in well under a second
/// optimised, large enough that a shading or geometry change moves many pixels.
const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// Examples that must exist (so the loop below cannot pass by finding nothing), with
/// whether each is a full scene (rendered) or an include-only file.
const KNOWN: &[(&str, bool)] = &[
    ("whitted", true),
    ("seed_examples", true),
    ("bunny", true),
    ("materials", false),
    ("textured", true),
    ("animated", true),
];

/// Every `examples/*.scn`, sorted by name.
fn example_files() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(examples_dir())
        .expect("read examples/")
        .map(|e| e.expect("list examples/").path())
        .filter(|p| p.extension().is_some_and(|e| e == "scn"))
        .collect();
    v.sort();
    v
}

fn stem(p: &std::path::Path) -> String {
    p.file_stem().unwrap().to_string_lossy().into_owned()
}

/// Loads an example, naming a missing shared model helpfully.
fn load(path: &std::path::Path) -> Scene {
    load_file(path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}\n(examples read models from ../shared/scenes beside the checkout; \
             in a worktree, link it there)",
            path.display()
        )
    })
}

/// Renders a loaded scene's first frame with the BVH at the golden size.
fn render_small(scene: &Scene) -> (dynray_render::Film, RenderStats) {
    let mut frame = scene.frame(0.0);
    frame.settings.width = WIDTH;
    frame.settings.height = HEIGHT;
    let bvh = Bvh::build(&frame.mesh, &BvhParams::default()).expect("example meshes are valid");
    render(&frame, &bvh, &RenderOptions::default())
}

#[test]
fn the_known_examples_are_present() {
    let stems: Vec<String> = example_files().iter().map(|p| stem(p)).collect();
    for (name, _) in KNOWN {
        assert!(stems.iter().any(|s| s == name), "examples/{name}.scn is missing; found {stems:?}");
    }
}

#[test]
fn every_full_example_matches_its_golden_image() {
    let mut failures = Vec::new();
    let mut rendered = 0;
    for path in example_files() {
        let name = stem(&path);
        let scene = load(&path);
        if scene.actors.is_empty() {
            // Include-only; `include_only_files_render_nothing_and_define_their_materials`
            // checks that this is what it is meant to be.
            assert!(
                KNOWN.contains(&(name.as_str(), false)),
                "{}: has no objects; a new include-only file must be listed in KNOWN",
                path.display()
            );
            continue;
        }
        let (film, stats) = render_small(&scene);
        // Every example is lit and has shadows somewhere; a scene whose lights or camera
        // were lost would still produce an image, so check the ray counts too.
        assert_eq!(stats.primary_rays, (WIDTH * HEIGHT) as u64, "{name}");
        assert!(stats.shadow_rays > 0, "{name}: no shadow rays: {stats:?}");
        if name == "whitted" {
            // The mirror and the glass sphere.
            assert!(stats.secondary_rays > 0, "{name}: no reflection or refraction: {stats:?}");
        }
        if name == "textured" {
            assert_eq!(scene.textures.len(), 1, "{name}: letter_f.png should load");
        }
        if let Err(e) = check_golden(&film, &format!("{name}_{WIDTH}x{HEIGHT}.png")) {
            failures.push(e);
        }
        rendered += 1;
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let full = KNOWN.iter().filter(|(_, full)| *full).count();
    assert!(rendered >= full, "rendered {rendered} examples, expected at least {full}");
}

#[test]
fn include_only_files_render_nothing_and_define_their_materials() {
    let path = examples_dir().join("materials.scn");
    let scene = load(&path);
    assert!(scene.actors.is_empty(), "materials.scn should only define things");
    // Rendered on its own it says what it is, not that a mesh has no triangles (issue 48).
    let out = tempfile::tempdir().unwrap();
    let o = dynray(&["render", path.to_str().unwrap(), "-o", out.path().join("m.png").to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("nothing to render: the scene has no objects") && err.contains("`include`"), "{err}");
    // Using every definition from a scene in the same folder evaluates them all.
    let text = r#"
        include "materials.scn"
        sphere { center <-3, 0, 0> radius 1 material matte_ivory }
        sphere { center <-1, 0, 0> radius 1 material glossy_brick }
        sphere { center <1, 0, 0> radius 1 material chrome }
        sphere { center <3, 0, 0> radius 1 material clear_glass }
        environment { background sky ambient white * 0.1 }
        light { position <0, 5, 5> color ivory }
    "#;
    let scene = parse_scn_str("uses-materials.scn", text, &examples_dir())
        .unwrap_or_else(|e| panic!("using materials.scn: {e}"));
    assert_eq!(scene.actors.len(), 4);
    let mut names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    names.sort();
    assert_eq!(names, ["chrome", "clear_glass", "glossy_brick", "matte_ivory"]);
    let glass = scene.materials.iter().find(|m| m.name == "clear_glass").unwrap();
    assert!(glass.transparency.min_element() > 0.0 && glass.ior == 1.5, "{glass:?}");
}

#[test]
fn every_full_example_renders_through_the_binary() {
    let dir = tempfile::tempdir().unwrap();
    for path in example_files() {
        let name = stem(&path);
        if KNOWN.contains(&(name.as_str(), false)) {
            continue;
        }
        let rel = format!("examples/{name}.scn");
        let out = dir.path().join(format!("{name}.png"));
        let o = ok(dynray(&["render", &rel, "-o", out.to_str().unwrap(), "--width", "64", "--height", "48"]));
        let img = image::open(&out).unwrap_or_else(|e| panic!("{name}: {}: {e}", out.display())).to_rgb8();
        assert_eq!(img.dimensions(), (64, 48), "{name}");
        let err = String::from_utf8_lossy(&o.stderr);
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!(lines.len(), 1, "{name}: expected a one-line summary on stderr, got:\n{err}");
        let line = lines[0];
        for needle in [format!("{rel}: "), " triangles, bvh build ".into(), "(64x48, ".into(), " Mrays/s) -> ".into()] {
            assert!(line.contains(&needle), "{name}: summary lacks {needle:?}: {line}");
        }
        assert!(line.ends_with(out.to_str().unwrap()), "{name}: summary should end with the output: {line}");
        assert!(o.stdout.is_empty(), "{name}: render should print nothing on stdout");
    }
}
