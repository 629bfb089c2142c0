//! Bring your own triangles, build a BVH, trace rays: the smallest complete use of
//! dynray-accel. Structures see only a `TriangleMesh` (flat position and index arrays):
//! loading files is the scene crate's job, so this example makes its arrays itself — a
//! bumpy sphere — or reads them from a Wavefront OBJ with the `tobj` crate.
//!
//! `cargo run --release -p dynray-accel --example trace_mesh [MESH.obj]` builds a BVH,
//! traces a 256×256 grid of rays at the mesh in one batch, checks a few against brute
//! force and prints what it found. `cargo test` runs it too.

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

/// A sphere of radius about 1 with a bumpy surface, `n` × `2n` quads: arrays as a
/// program that generates or simulates its geometry would have them.
fn bumpy_sphere(n: u32) -> TriangleMesh {
    let mut positions = Vec::new();
    for i in 0..=n {
        let theta = std::f32::consts::PI * i as f32 / n as f32;
        for j in 0..2 * n {
            let phi = std::f32::consts::PI * j as f32 / n as f32;
            let r = 1.0 + 0.05 * (5.0 * theta).sin() * (7.0 * phi).cos();
            positions.push([r * theta.sin() * phi.cos(), r * theta.cos(), r * theta.sin() * phi.sin()]);
        }
    }
    let at = |i: u32, j: u32| i * 2 * n + j % (2 * n);
    let mut indices = Vec::new();
    for i in 0..n {
        for j in 0..2 * n {
            indices.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            indices.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    TriangleMesh::new(positions, indices)
}

/// The triangles of every object of an OBJ file, in file order.
fn read_obj(path: &Path) -> Result<TriangleMesh, Box<dyn std::error::Error>> {
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    let (models, _) = tobj::load_obj(path, &options)?;
    let (mut positions, mut indices) = (Vec::new(), Vec::new());
    for m in models {
        let base = positions.len() as u32;
        positions.extend(m.mesh.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        indices.extend(m.mesh.indices.chunks_exact(3).map(|t| [base + t[0], base + t[1], base + t[2]]));
    }
    Ok(TriangleMesh::new(positions, indices))
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
    let (name, mesh) = match path {
        Some(p) => (p.display().to_string(), read_obj(p)?),
        None => ("bumpy sphere".to_string(), bumpy_sphere(200)),
    };
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
fn traces_the_generated_mesh() {
    let s = run(None).expect("example runs");
    // A grid over a sphere's box hits π/4 of it, and misses the corners.
    let rate = s.hits as f64 / s.rays as f64;
    assert!(s.triangles == 160_000 && (0.74..0.82).contains(&rate), "{} of {} rays hit", s.hits, s.rays);
}

#[test]
fn traces_an_obj_file() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/scenes/cornell-box/mcguire-obj/CornellBox-Original.obj");
    if !path.exists() {
        eprintln!("{} is missing: the OBJ case is skipped", path.display());
        return;
    }
    let s = run(Some(&path)).expect("example runs");
    // The box's back wall fills the view along -z (its outer edges aside).
    assert!(s.triangles > 30 && s.hits * 100 > s.rays * 99, "{} of {} rays hit", s.hits, s.rays);
}
