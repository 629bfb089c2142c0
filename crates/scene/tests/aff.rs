//! BART's AFF (and NFF): the three BART scenes load, animate and keep their triangle
//! order; a hand-written file interpolates to hand-computed positions; every error path
//! is a clear error naming the file and line.

mod support;

use dynray_scene::{load_file, load_file_report, load_file_unshaded, Motion, Scene};
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use support::{model, write};

/// A BART scene loaded once for every test of this binary (they run in parallel).
fn bart(which: &'static str) -> Option<&'static Scene> {
    static KITCHEN: OnceLock<Option<Scene>> = OnceLock::new();
    static ROBOTS: OnceLock<Option<Scene>> = OnceLock::new();
    static MUSEUM: OnceLock<Option<Scene>> = OnceLock::new();
    let (cell, rel) = match which {
        "kitchen" => (&KITCHEN, "bart/kitchen/aff/kitchen.aff"),
        "robots" => (&ROBOTS, "bart/robot/aff/Robot.aff"),
        _ => (&MUSEUM, "bart/museum/aff/museum5.aff"),
    };
    cell.get_or_init(|| {
        let path = model(rel)?;
        let start = std::time::Instant::now();
        let report = load_file_report(&path).unwrap_or_else(|e| panic!("{e}"));
        eprintln!("{which}: loaded in {} ms ({} warnings)", start.elapsed().as_millis(), report.warnings.len());
        for w in report.warnings.iter().take(5) {
            eprintln!("  {w}");
        }
        Some(report.scene)
    })
    .as_ref()
}

const SCENES: [(&str, u32, usize); 3] = [
    // name, frames of the `a` line, triangles: SOURCE.md's counts, plus for the museum
    // its 10 textured `tt` triangles, 8 cones (64 triangles each) and 1,024 `tpa` ones.
    ("kitchen", 800, 110_561),
    ("robots", 800, 71_708),
    ("museum", 300, 10_274 + 10 + 8 * 64 + 1024),
];

#[test]
fn bart_scenes_have_their_frames_and_triangles() {
    for (name, frames, triangles) in SCENES {
        let Some(s) = bart(name) else { continue };
        assert_eq!(s.animation.timeline.frames, frames, "{name}");
        assert_eq!(s.triangle_count(), triangles, "{name}");
        assert!(s.is_animated(), "{name}");
        assert!(s.animation.camera_node.is_some(), "{name}: BART animates the camera");
        assert!(!s.lights.is_empty(), "{name}");
    }
}

/// Start, middle and end frames: same triangle count, finite non-empty boxes of the same
/// order of magnitude.
#[test]
fn bart_frames_are_stable_and_sane() {
    for (name, frames, triangles) in SCENES {
        let Some(s) = bart(name) else { continue };
        let tl = s.animation.timeline;
        let f0 = s.frame(tl.time_of(0));
        let d0 = f0.mesh.bounds().extent().length();
        for k in [frames / 2, frames - 1] {
            let f = s.frame(tl.time_of(k));
            assert_eq!(f.mesh.triangle_count(), triangles, "{name} frame {k}");
            assert_eq!(f.actor_ranges, f0.actor_ranges, "{name} frame {k}");
            let b = f.mesh.bounds();
            assert!(!b.is_empty() && b.min.is_finite() && b.max.is_finite(), "{name} frame {k}: {b:?}");
            let d = b.extent().length();
            assert!(d > d0 / 10.0 && d < d0 * 10.0, "{name} frame {k}: diagonal {d} vs {d0} at frame 0");
        }
    }
}

/// Between frame 0 and the middle frame dynamic actors move and static ones keep their
/// bits.
#[test]
fn bart_dynamic_actors_move_and_static_ones_do_not() {
    for (name, frames, _) in SCENES {
        let Some(s) = bart(name) else { continue };
        let tl = s.animation.timeline;
        let (a, b) = (s.frame(tl.time_of(0)), s.frame(tl.time_of(frames / 2)));
        let (mut moved, mut dynamic, mut still) = (0, 0, 0);
        let mut v0 = 0;
        for actor in &s.actors {
            let n = actor.mesh.vertex_count();
            let (pa, pb) = (&a.mesh.positions[v0..v0 + n], &b.mesh.positions[v0..v0 + n]);
            v0 += n;
            let bits = |p: &[[f32; 3]]| p.iter().map(|v| v.map(f32::to_bits)).collect::<Vec<_>>();
            if actor.motion == Motion::Static {
                assert_eq!(bits(pa), bits(pb), "{name}: static actor {:?} changed", actor.name);
                still += 1;
            } else {
                dynamic += 1;
                moved += (pa != pb) as usize;
            }
        }
        assert!(dynamic > 0 && moved > 0 && still > 0, "{name}: {dynamic} dynamic ({moved} moved), {still} static");
    }
}

#[test]
fn bart_cameras_follow_their_keys() {
    // Kitchen: `k camera` translation key at 5.0 is (3.50, 0.2, 0.1); a spline passes
    // through its keys.
    if let Some(s) = bart("kitchen") {
        let c = s.frame(5.0).camera;
        assert!((c.position - Vec3::new(3.5, 0.2, 0.1)).length() < 1e-4, "{:?}", c.position);
        assert!((s.frame(0.0).camera.position - Vec3::new(3.75, 2.3, 3.6)).length() < 1e-4);
    }
    // Museum: at 0.5 the eye is (3, 2.4, -1) turned 90° about y: looking down -x.
    if let Some(s) = bart("museum") {
        let c = s.frame(0.5).camera;
        assert!((c.position - Vec3::new(3.0, 2.4, -1.0)).length() < 1e-4, "{:?}", c.position);
        let dir = (c.look_at - c.position).normalize();
        assert!((dir - Vec3::NEG_X).length() < 1e-4, "{dir:?}");
        assert!((c.up - Vec3::Y).length() < 1e-4, "{:?}", c.up);
    }
}

/// One triangle under `x obj`. Translation keys (x): 5 at −1, 0 at 0, 1 at 1, 0 at 2, 7
/// at 3; rotation keys about y: 0° at −1 and 0, 90° at 2 and 3 (zero tension,
/// continuity, bias). BART's rules (crates/scene/src/animation/bart_track.rs): the first
/// and last keys only give the end tangents, the value holds at key 1 before it and at
/// key n−2 after it.
const KEYED: &str = "\
a 0 2 3
x obj
{
  p 3  1 0 0  0 1 0  0 0 1
}
k obj
{
  transl 5
  -1  5 0 0  0 0 0
  0   0 0 0  0 0 0
  1   1 0 0  0 0 0
  2   0 0 0  0 0 0
  3   7 0 0  0 0 0
  rot 4
  -1  0 1 0  0   0 0 0
  0   0 1 0  0   0 0 0
  2   0 1 0  90  0 0 0
  3   0 1 0  90  0 0 0
}
";

#[test]
fn keyed_transforms_interpolate_to_hand_computed_positions() {
    let dir = tempfile::tempdir().unwrap();
    let s = load_file_unshaded(&write(dir.path(), "keyed.aff", KEYED.as_bytes())).unwrap().scene;
    assert_eq!(s.animation.timeline.frames, 3);
    assert_eq!(s.animation.timeline.time_of(1), 1.0);
    assert_eq!(s.actors[0].motion, Motion::Dynamic);
    let p0 = |t: f32| Vec3::from_array(s.frame(t).mesh.positions[0]);
    let turned = |x: f32, deg: f32| Vec3::new(x + deg.to_radians().cos(), 0.0, -deg.to_radians().sin());
    // Rotation, one segment 0 → 2 s (0° → 90°, outer keys 0° and 90°): in half-angles
    // (log of the key quaternions) Δ = 45°, a0 = a1 = 2·2/3, Tout = Tin = a/2·(0 + 45) = 30°,
    // squad's controls φa = 0 + (30 − 45)/2 = −7.5°, φb = 45 + (45 − 30)/2 = 52.5°, and
    // with one axis squad is lerp(lerp(0, 45, u), lerp(−7.5, 52.5, u), 2u(1 − u)).
    let half_angle = |u: f32| {
        let lerp = |a: f32, b: f32, s: f32| a + s * (b - a);
        lerp(lerp(0.0, 45.0, u), lerp(-7.5, 52.5, u), 2.0 * u * (1.0 - u))
    };
    // t = 1: translation is key 2's (1, 0, 0); rotation halfway, 2·22.5° = 45°.
    assert!((p0(1.0) - turned(1.0, 45.0)).length() < 1e-5, "{}", p0(1.0));
    // t = 0.5: translation from 0 (Tout = ½((0 − 5) + (1 − 0)) = −2) to 1 (Tin =
    // ½((1 − 0) + (0 − 1)) = 0): h10(½)·(−2) + h01(½)·1 = −0.25 + 0.5 = 0.25 — the outer
    // key at −1 pulls the start. Rotation at u = ¼: half-angle 11.25 + ⅜·(7.5 − 11.25)
    // = 9.84375°, so 19.6875°.
    assert_eq!(half_angle(0.25), 9.84375);
    let want = turned(0.25, 19.6875);
    assert!((p0(0.5) - want).length() < 1e-5, "{} vs {want}", p0(0.5));
    // t = 1.5: from 1 (Tout = ½((1 − 0) + (0 − 1)) = 0) to 0 (Tin = ½((0 − 1) + (7 − 0))
    // = 3): h00(½)·1 + h11(½)·3 = 0.5 − 0.375 = 0.125.
    let want = turned(0.125, 2.0 * half_angle(0.75));
    assert!((p0(1.5) - want).length() < 1e-5, "{} vs {want}", p0(1.5));
    // Held outside keys 1 and n−2: never towards the outer keys' 5 and 7.
    assert!((p0(-0.5) - turned(0.0, 0.0)).length() < 1e-6, "{}", p0(-0.5));
    assert!((p0(5.0) - turned(0.0, 90.0)).length() < 1e-5, "{}", p0(5.0));
}

#[test]
fn nff_primitives_materials_and_views() {
    let dir = tempfile::tempdir().unwrap();
    let text = "\
v
from 0 0 5
at 0 0 0
up 0 1 0
angle 30
hither 0.1
resolution 320 200
b 0.1 0.2 0.3
l 1 2 3
l 0 5 0 0.5 0.5 0.5
f 1 0 0 0.8 0.2 10 0 1
p 4  0 0 0  1 0 0  1 1 0  0 1 0
fm 0.1 0.1 0.1  0.5 0.5 0.5  0.3 0.3 0.3  20 0 1.5
pp 3  0 0 1 0 0 1  1 0 1 0 0 1  0 1 1 0 0 1
s 0 0 -2 0.5
c 0 0 0 0.25  0 1 0 0.25
tt missing.ppm  0 0 0 0 0  1 0 0 1 0  0 1 0 0 1
";
    let r = load_file_report(&write(dir.path(), "prims.nff", text.as_bytes())).unwrap();
    let s = &r.scene;
    assert_eq!(s.triangle_count(), 2 + 1 + 960 + 64 + 1);
    assert_eq!((s.settings.width, s.settings.height), (320, 200));
    assert_eq!(s.environment.background, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(s.lights.len(), 2);
    assert_eq!(s.lights[1].color, Vec3::splat(0.5));
    let c = s.camera.unwrap();
    assert_eq!(c.position, Vec3::new(0.0, 0.0, 5.0));
    assert_eq!(s.materials[0].diffuse, Vec3::new(0.8, 0.0, 0.0));
    assert_eq!(s.materials[1].ior, 1.5);
    assert!(!s.is_animated());
    assert!(s.actors.iter().all(|a| a.motion == Motion::Static));
    assert!(r.warnings.iter().any(|w| w.message.contains("missing.ppm")), "{:?}", r.warnings);
    assert!(s.materials.iter().all(|m| m.diffuse_texture.is_none()), "an unreadable texture leaves it untextured");
}

#[test]
fn meshes_textures_and_animated_triangles() {
    let dir = tempfile::tempdir().unwrap();
    // A 1×1 PPM texture in BART's layout: aff/ beside TextureFiles/.
    std::fs::create_dir_all(dir.path().join("TextureFiles")).unwrap();
    std::fs::create_dir_all(dir.path().join("aff")).unwrap();
    write(&dir.path().join("TextureFiles"), "t.ppm", b"P3 1 1 255 255 0 0");
    let text = "\
a 0 1 2
m
vertices 4
0 0 0  1 0 0  1 1 0  0 1 0
normals 1
0 0 1
texturecoords 2 t.ppm
0 0  1 1
triangles 2
0 1 2  0 0 0  0 1 1
0 2 3  0 0 0  0 0 0
tpa 2
0  0 0 0 0 0 1  1 0 0 0 0 1  0 1 0 0 0 1
1  0 0 1 0 0 1  1 0 1 0 0 1  0 1 1 0 0 1
";
    let r = load_file_unshaded(&write(&dir.path().join("aff"), "m.aff", text.as_bytes())).unwrap();
    let s = &r.scene;
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    assert_eq!(s.textures.len(), 1);
    assert_eq!(s.actors.len(), 2, "the mesh and the animated triangle");
    let mesh = &s.actors[0].mesh;
    assert_eq!(mesh.vertex_count(), 5, "(vertex, normal, uv) triples de-duplicated");
    assert_eq!(mesh.uvs.as_ref().unwrap()[0], [0.0, 1.0], "v flipped to dynray's convention");
    assert!(s.materials[s.actors[0].materials[0] as usize].diffuse_texture.is_some());
    assert_eq!(s.actors[1].motion, Motion::Dynamic);
    assert_eq!(s.actors[0].motion, Motion::Static);
    let z = |t: f32| s.frame(t).mesh.positions[5][2];
    assert_eq!((z(0.0), z(0.25), z(1.0)), (0.0, 0.25, 1.0), "keyed vertices, linear between keys");
}

/// Writes `files` into a temp dir and returns the error of loading the first.
fn fails(files: &[(&str, &str)]) -> (String, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let paths: Vec<PathBuf> = files.iter().map(|(n, t)| write(dir.path(), n, t.as_bytes())).collect();
    match load_file(&paths[0]) {
        Ok(s) => panic!("{} loaded ({} triangles) but should fail", paths[0].display(), s.triangle_count()),
        Err(e) => (e.to_string(), dir),
    }
}

fn at(dir: &Path, file: &str, line: usize) -> String {
    format!("{}:{line}:", dir.join(file).display())
}

#[test]
fn unknown_commands_are_errors() {
    let (e, d) = fails(&[("u.aff", "b 0 0 0\nq 1 2 3\n")]);
    assert!(e.starts_with(&at(d.path(), "u.aff", 2)) && e.contains("unknown command `q`"), "{e}");
}

#[test]
fn numbers_that_do_not_parse_are_errors() {
    let (e, d) = fails(&[("n.aff", "p 3\n0 0 0\n1 0 zero\n0 1 0\n")]);
    assert!(e.starts_with(&at(d.path(), "n.aff", 3)) && e.contains("found `zero`"), "{e}");
    let (e, _d) = fails(&[("n.aff", "s 0 0 0 NaN\n")]);
    assert!(e.contains("not a finite number"), "{e}");
}

#[test]
fn keys_outside_the_animation_range_are_errors() {
    // The track moves from key 1 (t = 3) to key n−2 (t = 4), all after the range 0..1:
    // the error names key 1's line.
    let text = "a 0 1 10\nx o { p 3 0 0 0 1 0 0 0 1 0 }\nk o {\n transl 4\n 0.5 0 0 0 0 0 0\n 3 1 0 0 0 0 0\n \
                4 2 0 0 0 0 0\n 5 3 0 0 0 0 0\n}\n";
    let (e, d) = fails(&[("r.aff", text)]);
    assert!(e.starts_with(&at(d.path(), "r.aff", 6)) && e.contains("outside the animation range"), "{e}");
    // Outer keys beyond the ends (they only shape the ends) load.
    let ok = text.replace(" 3 1 0 0 0 0 0", " 0.75 1 0 0 0 0 0");
    let dir = tempfile::tempdir().unwrap();
    load_file_unshaded(&write(dir.path(), "ok.aff", ok.as_bytes())).unwrap();
    // A key earlier than the one before it is kept, as BART's reference code keeps it,
    // with a warning (BART's robots have one).
    let back =
        "x o { p 3 0 0 0 1 0 0 0 1 0 }\nk o { transl 4\n 0 0 0 0 0 0 0\n 1 0 0 0 0 0 0\n 0.5 0 0 0 0 0 0\n 2 0 0 0 0 0 0 }\n";
    let r = load_file_report(&write(dir.path(), "back.aff", back.as_bytes())).unwrap();
    assert!(
        r.warnings.iter().any(|w| w.line == Some(5) && w.message.contains("comes after") && w.message.contains("kept")),
        "{:?}",
        r.warnings
    );
    // Fewer than 4 keys: refused at the `rot` line, as BART's parse.c refuses them.
    let short = "x o { p 3 0 0 0 1 0 0 0 1 0 }\nk o {\n rot 2\n 0 0 1 0 0 0 0 0\n 1 0 1 0 90 0 0 0\n}\n";
    let (e, d) = fails(&[("s.aff", short)]);
    assert!(e.starts_with(&at(d.path(), "s.aff", 3)) && e.contains("at least 4"), "{e}");
}

#[test]
fn missing_includes_name_the_including_line() {
    let (e, d) = fails(&[("top.aff", "p 3 0 0 0 1 0 0 0 1 0\n\ni 0 nowhere.aff\n")]);
    assert!(e.starts_with(&at(d.path(), "top.aff", 3)) && e.contains("nowhere.aff"), "{e}");
}

/// Issue 43: a view whose `from` is its `at` (or whose `up` lies along the view) rendered
/// silently; it names the `v` block now.
#[test]
fn views_that_look_nowhere_are_errors() {
    let tri = "p 3 0 0 0 1 0 0 0 1 0\n";
    let same = format!("{tri}v\nfrom 1 2 3\nat 1 2 3\nup 0 1 0\nangle 45\n");
    let (e, d) = fails(&[("v.aff", same.as_str())]);
    assert!(e.starts_with(&at(d.path(), "v.aff", 3)) && e.contains("the camera looks nowhere"), "{e}");
    let along = format!("{tri}v\nfrom 0 0 5\nat 0 0 0\nup 0 0 1\nangle 45\n");
    let (e, _d) = fails(&[("u.aff", along.as_str())]);
    assert!(e.contains("parallel to the view direction"), "{e}");
}

#[test]
fn include_cycles_are_errors() {
    let (e, d) = fails(&[("a.aff", "i 0 b.aff\n"), ("b.aff", "p 3 0 0 0 1 0 0 0 1 0\ni 0 a.aff\n")]);
    assert!(e.contains("include cycle: a.aff → b.aff → a.aff"), "{e}");
    assert!(e.contains(&at(d.path(), "b.aff", 2)), "{e}");
}

#[test]
fn counts_that_lie_are_errors_without_huge_allocations() {
    let (e, d) = fails(&[("m.aff", "m\nvertices 1000000000\n0 0 0\n1 0 0\ntriangles 1\n0 1 2\n")]);
    assert!(e.starts_with(&at(d.path(), "m.aff", 5)) && e.contains("mesh vertex 3 of 1000000000"), "{e}");
    let (e, _d) = fails(&[("i.aff", "m\nvertices 3\n0 0 0 1 0 0 0 1 0\ntriangles 1\n0 1 7\n")]);
    assert!(e.contains("vertex index 7 out of range"), "{e}");
    let (e, _d) = fails(&[("p.aff", "p 4000000000\n0 0 0\n")]);
    assert!(e.contains("p.aff:2:") && e.contains("`p` vertex 2 of 4000000000"), "{e}");
    let (e, _d) = fails(&[("t.aff", "tpa 99999999\n0 0 0 0 0 0 1\n")]);
    assert!(e.contains("t.aff:2:") && e.contains("`tpa` key 1 of 99999999"), "{e}");
}

#[test]
fn unbalanced_blocks_are_errors() {
    let (e, _d) = fails(&[("b.aff", "xs 1 1 1 0 1 0 0 0 0 0 {\np 3 0 0 0 1 0 0 0 1 0\n")]);
    assert!(e.contains("missing `}`"), "{e}");
    let (e, _d) = fails(&[("c.aff", "p 3 0 0 0 1 0 0 0 1 0\n}\n")]);
    assert!(e.contains("c.aff:2: `}` without a matching `{`"), "{e}");
    let deep = "xs 1 1 1 0 1 0 0 0 0 0 {\n".repeat(1000);
    let (e, _d) = fails(&[("d.aff", &deep)]);
    assert!(e.contains("nested deeper"), "{e}");
}
