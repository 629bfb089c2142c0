//! Load a mesh, build a BVH, trace rays: the smallest complete use of dynray-accel.
//!
//! `cargo run --release -p dynray-accel --example trace_mesh [MESH]` loads MESH (any
//! format dynray reads; default
//! `../shared/scenes/bunny/bun_zipper.ply` beside the checkout; an icosphere when that is
//! absent), builds a BVH, traces a 256×256 grid of rays at it in one batch, checks a few
//! against brute force and prints what it found. `cargo test` runs it too.

use dynray_accel::{Accel, BatchQuery, Brute, Bvh, BvhParams};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What one run found.
struct Summary {
    triangles: usize,
    rays: usize,
    hits: usize,
}

/// The model beside the checkout, or a generated icosphere (so the example always runs).
fn load(path: Option<&Path>) -> (String, TriangleMesh) {
    let default = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes/bunny/bun_zipper.ply");
    let path = path.map(Path::to_path_buf).unwrap_or(default);
    // Any file dynray reads (.ply, .obj, .gltf, .npz, .scn …) as one world-space mesh.
    match dynray_scene::load_mesh(&path) {
        Ok(mesh) => (path.display().to_string(), mesh),
        Err(e) => {
            eprintln!("{}: {e}; using an icosphere", path.display());
            ("icosphere".into(), dynray_scene::shapes::icosphere(Vec3::ZERO, 1.0, 4))
        }
    }
}

/// A `side`×`side` grid of parallel rays aimed at the mesh's box along −z.
fn grid_rays(mesh: &TriangleMesh, side: usize) -> Vec<Ray> {
    let b = mesh.bounds();
    let (lo, ext) = (b.min, b.extent());
    let z = b.max.z + ext.z;
    (0..side * side)
        .map(|i| {
            let (x, y) = ((i % side) as f32 + 0.5, (i / side) as f32 + 0.5);
            let o = Vec3::new(lo.x + ext.x * x / side as f32, lo.y + ext.y * y / side as f32, z);
            Ray::new(o, Vec3::new(0.0, 0.0, -1.0))
        })
        .collect()
}

fn run(path: Option<&Path>) -> Result<Summary, Box<dyn std::error::Error>> {
    let (name, mesh) = load(path);
    let t = Instant::now();
    let bvh = Bvh::build(&mesh, &BvhParams::default())?;
    let build_ms = t.elapsed().as_secs_f64() * 1e3;
    let rays = grid_rays(&mesh, 256);
    let t = Instant::now();
    let hits = bvh.intersect_batch(&rays);
    let trace_ms = t.elapsed().as_secs_f64() * 1e3;
    let n_hit = hits.iter().filter(|h| h.is_hit()).count();
    // Every structure answers exactly as brute force does; check a sample.
    let brute = Brute::build(&mesh)?;
    for i in (0..rays.len()).step_by(997) {
        let want = brute.intersect(&rays[i]);
        if !hits[i].same_as(&want) {
            return Err(format!("ray {i}: bvh {:?}, brute force {want:?}", hits[i]).into());
        }
    }
    println!(
        "{name}: {} triangles, BVH of {} nodes in {build_ms:.1} ms; {} rays, {n_hit} hits in {trace_ms:.1} ms",
        mesh.triangle_count(),
        bvh.stats().nodes,
        rays.len()
    );
    Ok(Summary { triangles: mesh.triangle_count(), rays: rays.len(), hits: n_hit })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = std::env::args_os().nth(1).map(PathBuf::from);
    let s = run(arg.as_deref())?;
    println!("hit rate {:.1} % over {} triangles", 100.0 * s.hits as f64 / s.rays as f64, s.triangles);
    Ok(())
}

#[test]
fn traces_the_default_mesh() {
    let s = run(None).expect("example runs");
    // A grid over the model's box hits a good part of it and misses around it.
    assert!(s.triangles > 0 && s.hits > s.rays / 10 && s.hits < s.rays, "{} of {} rays hit", s.hits, s.rays);
}
