//! Smooth shading by default, through the library and the binary: generated normals
//! never change a hit, `render --flat-shading` drops every vertex normal, and `info`
//! says where the normals come from.

mod support;

use dynray_accel::{BatchQuery, Brute};
use dynray_geom::{Ray, Vec3};
use dynray_render::{render, RenderOptions};
use std::path::{Path, PathBuf};
use support::{dynray, ok, scenes_dir};

/// The shared model, or `None` (with a note) when this checkout has none.
fn model(rel: &str) -> Option<PathBuf> {
    let p = scenes_dir().join(rel);
    if !p.is_file() {
        eprintln!("skipped: {} not found", p.display());
        return None;
    }
    Some(p)
}

/// Rays from a sphere around `mesh`'s box towards points inside it, on a fixed pattern.
fn rays_at(bounds: dynray_geom::Aabb, n: usize) -> Vec<Ray> {
    let (c, r) = (bounds.center(), bounds.extent().length());
    // A low-discrepancy pattern: golden-ratio spirals for origins and targets.
    let phi = 0.618_034_f32;
    (0..n)
        .map(|i| {
            let (a, b) = ((i as f32 * phi).fract(), (i as f32 + 0.5) / n as f32);
            let (theta, z) = (a * std::f32::consts::TAU, 2.0 * b - 1.0);
            let s = (1.0 - z * z).sqrt();
            let origin = c + Vec3::new(s * theta.cos(), z, s * theta.sin()) * r;
            let t = Vec3::new((i as f32 * 0.754_877).fract(), (i as f32 * 0.569_840).fract(), b) - 0.5;
            Ray::new(origin, c + t * bounds.extent() - origin)
        })
        .collect()
}

/// Regression guard for the rule that generated normals only add vertices: brute force
/// on the shaded bunny returns the file's hits, bit for bit.
#[test]
fn generated_normals_leave_every_hit_as_it_was() {
    let Some(p) = model("bunny/bun_zipper.ply") else { return };
    let raw = dynray_scene::load_mesh(&p).unwrap();
    let shaded = dynray_scene::load_file(&p).unwrap().frame(0.0).mesh;
    assert!(shaded.normals.is_some() && raw.normals.is_none());
    assert!(shaded.vertex_count() > raw.vertex_count(), "the bunny splits some vertices");
    let rays = rays_at(raw.bounds(), 1500);
    let before = Brute::build(&raw).unwrap().intersect_batch(&rays);
    let after = Brute::build(&shaded).unwrap().intersect_batch(&rays);
    let hits = before.iter().filter(|h| h.is_hit()).count();
    assert!(hits * 4 > rays.len(), "only {hits} of {} rays hit: the test would prove little", rays.len());
    for (i, (a, b)) in before.iter().zip(&after).enumerate() {
        assert_eq!(
            (a.t.to_bits(), a.prim, a.u.to_bits(), a.v.to_bits()),
            (b.t.to_bits(), b.prim, b.u.to_bits(), b.v.to_bits()),
            "ray {i}"
        );
    }
}

fn render_png(args: &[&str], out: &Path) -> Vec<u8> {
    let mut all = vec!["render", "-o", out.to_str().unwrap(), "--width", "96", "--height", "72", "--spp", "1"];
    all.extend_from_slice(args);
    ok(dynray(&all));
    image::open(out).unwrap().to_rgb8().into_raw()
}

#[test]
fn flat_shading_drops_vertex_normals_and_changes_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let Some(p) = model("bunny/bun_zipper.ply") else { return };
    let bunny = p.to_str().unwrap();
    let smooth = render_png(&[bunny], &dir.path().join("smooth.png"));
    let flat = render_png(&[bunny, "--flat-shading"], &dir.path().join("flat.png"));
    let differ = smooth.chunks(3).zip(flat.chunks(3)).filter(|(a, b)| a != b).count();
    assert!(differ > 200, "only {differ} pixels differ between smooth and flat shading");

    // The flat image is the library's render of the file's own triangles, no normals.
    let mut frame = dynray_scene::load_file_unshaded(&p).unwrap().scene.frame(0.0);
    assert!(frame.mesh.normals.is_none());
    frame.settings.width = 96;
    frame.settings.height = 72;
    let accel = dynray_accel::Bvh::build(&frame.mesh, &Default::default()).unwrap();
    let (film, _) = render(&frame, &accel, &RenderOptions::default());
    assert_eq!(flat, film.to_srgb8(), "--flat-shading is the geometric-normal render");

    // Normals a file or a scene gives are dropped too: the demo's spheres turn faceted.
    let demo = render_png(&[], &dir.path().join("demo.png"));
    let demo_flat = render_png(&["--flat-shading"], &dir.path().join("demo-flat.png"));
    assert_ne!(demo, demo_flat);
}

fn info_normals(file: &str) -> String {
    let o = ok(dynray(&["info", file]));
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    let line = out.lines().find(|l| l.starts_with("normals ")).unwrap_or_else(|| panic!("no normals line:\n{out}"));
    line["normals ".len()..].trim().to_string()
}

#[test]
fn info_says_where_the_normals_come_from() {
    if let Some(p) = model("bunny/bun_zipper.ply") {
        let n = info_normals(p.to_str().unwrap());
        assert!(n.starts_with("generated (crease 60°), ") && n.contains(" vertices split, in "), "{n}");
    }
    if let Some(p) = model("Duck/glTF-Binary/Duck.glb") {
        assert_eq!(info_normals(p.to_str().unwrap()), "from file");
    }
    let dir = tempfile::tempdir().unwrap();
    let scn = dir.path().join("two.scn");
    let tri = "vertices { 3 <0,0,0> <1,0,0> <0,1,0> } triangles { 1 <0,1,2> }";
    std::fs::write(&scn, format!("mesh {{ {tri} }}")).unwrap();
    assert_eq!(info_normals(scn.to_str().unwrap()), "geometric");
    std::fs::write(&scn, format!("mesh {{ {tri} }} mesh {{ {tri} shading smooth 30 }} mesh {{ {tri} }}")).unwrap();
    let n = info_normals(scn.to_str().unwrap());
    assert!(n.starts_with("geometric for 2 actors; generated (crease 30°) for 1 actor, 0 vertices split, in "), "{n}");
}
