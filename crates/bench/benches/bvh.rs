//! BVH build time and ray throughput on the bunny and the full dragon (871k triangles):
//! 1024×1024 pinhole rays from `Camera::framing`, traced on all cores. Two groups per
//! model: `bvh2/…`, the binary tree (`bvh2`) per preset, and `bvh/…`, the wide tree that
//! `bvh` names (build; primary rays one at a time and in packets of 8; any-hit on the same
//! rays, one at a time and in packets of 8; random rays from inside the box, the
//! incoherent case).
//!
//! Run: `cargo bench -p dynray-bench --bench bvh` (Mrays/s = rays / time per trace;
//! criterion prints elements per second). Set `DYNRAY_SCENES` when the scenes are not at
//! `../shared/scenes`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use dynray_accel::{Accel, BatchQuery, Bvh, BvhParams, Coherent, Wbvh, WbvhParams};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use dynray_scene::{Camera, Projection};
use rand::{rngs::SmallRng, Rng, SeedableRng};
use std::path::PathBuf;
use std::time::Duration;

const SIZE: u32 = 1024;

fn scene(rel: &str) -> TriangleMesh {
    let dir = std::env::var("DYNRAY_SCENES")
        .map(PathBuf::from)
        .unwrap_or_else(|_| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes"));
    let p = dir.join(rel);
    dynray_scene::formats::ply::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// One ray per pixel centre through a pinhole camera framing the mesh.
fn primary_rays(mesh: &TriangleMesh) -> Vec<Ray> {
    let cam = Camera::framing(&mesh.bounds());
    let fov_y = match cam.projection {
        Projection::Perspective { fov_y_deg } => fov_y_deg.to_radians(),
        Projection::Parallel { .. } => unreachable!("framing() gives a perspective camera"),
    };
    let fwd = (cam.look_at - cam.position).normalize();
    let right = fwd.cross(cam.up).normalize();
    let up = right.cross(fwd);
    let half = (fov_y * 0.5).tan();
    let mut rays = Vec::with_capacity((SIZE * SIZE) as usize);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let sx = ((x as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0) * half;
            let sy = (1.0 - (y as f32 + 0.5) / SIZE as f32 * 2.0) * half;
            let dir: Vec3 = fwd + right * sx + up * sy;
            rays.push(Ray::new(cam.position, dir));
        }
    }
    rays
}

fn bench_model(c: &mut Criterion, name: &str, rel: &str) {
    let mesh = scene(rel);
    let rays = primary_rays(&mesh);
    let presets = match std::env::var("BVH_BENCH_PRESETS") {
        // e.g. BVH_BENCH_PRESETS=default to bench one preset only.
        Ok(only) => vec![only],
        Err(_) => vec!["fast".to_string(), "default".to_string(), "hq".to_string()],
    };
    let mut g = c.benchmark_group(format!("bvh2/{name}"));
    g.sample_size(10).warm_up_time(Duration::from_secs(1));
    for preset in &presets {
        let p = match preset.as_str() {
            "fast" => BvhParams::fast(),
            "hq" => BvhParams::high_quality(),
            _ => BvhParams::default(),
        };
        g.throughput(Throughput::Elements(mesh.triangle_count() as u64));
        g.bench_function(format!("build/{preset}"), |b| b.iter(|| Bvh::build(&mesh, &p).unwrap()));
        let bvh = Bvh::build(&mesh, &p).unwrap();
        let s = bvh.stats();
        let hits = bvh.intersect_batch(&rays).iter().filter(|h| h.is_hit()).count();
        eprintln!(
            "{name}/{preset}: {} tris, {} nodes, depth {}, SAH {:.2}, {:.1} MB, {hits} of {} primary rays hit",
            mesh.triangle_count(),
            s.nodes,
            s.max_depth,
            s.sah_cost.unwrap_or(f64::NAN),
            s.memory_bytes as f64 / 1e6,
            rays.len()
        );
        g.throughput(Throughput::Elements(rays.len() as u64));
        g.bench_function(format!("primary/{preset}"), |b| b.iter(|| bvh.intersect_batch(&rays)));
        if preset == "default" {
            g.bench_function("occluded/default", |b| b.iter(|| bvh.occluded_batch(&rays)));
        }
    }
    g.finish();
}

/// As many rays as `n`, each from a random point of the mesh's box in a random direction
/// (seeded: the same set every run).
fn random_rays(mesh: &TriangleMesh, n: usize) -> Vec<Ray> {
    let b = mesh.bounds();
    let mut rng = SmallRng::seed_from_u64(5);
    (0..n)
        .map(|_| {
            let o = b.min + (b.max - b.min) * Vec3::new(rng.gen(), rng.gen(), rng.gen());
            let d = Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
            Ray::new(o, if d == Vec3::ZERO { Vec3::Y } else { d })
        })
        .collect()
}

/// The wide BVH (what `bvh` names) with its default parameters.
fn bench_wide(c: &mut Criterion, name: &str, rel: &str) {
    let mesh = scene(rel);
    let rays = primary_rays(&mesh);
    let random = random_rays(&mesh, rays.len());
    let p = WbvhParams::default();
    let mut g = c.benchmark_group(format!("bvh/{name}"));
    g.sample_size(10).warm_up_time(Duration::from_secs(1));
    g.throughput(Throughput::Elements(mesh.triangle_count() as u64));
    g.bench_function("build", |b| b.iter(|| Wbvh::build(&mesh, &p).unwrap()));
    let w = Wbvh::build(&mesh, &p).unwrap();
    eprintln!("{name}/wbvh: {} kernel, {:.1} MB", w.kernel(), w.stats().memory_bytes as f64 / 1e6);
    g.throughput(Throughput::Elements(rays.len() as u64));
    g.bench_function("primary", |b| b.iter(|| w.intersect_batch(&rays)));
    g.bench_function("primary-packets", |b| b.iter(|| Coherent(&w).intersect_batch(&rays)));
    g.bench_function("occluded", |b| b.iter(|| w.occluded_batch(&rays)));
    g.bench_function("occluded-packets", |b| b.iter(|| Coherent(&w).occluded_batch(&rays)));
    g.bench_function("random", |b| b.iter(|| w.intersect_batch(&random)));
    g.finish();
}

fn benches(c: &mut Criterion) {
    bench_model(c, "bunny", "bunny/bun_zipper.ply");
    bench_model(c, "dragon", "dragon/dragon_vrip.ply.gz");
    bench_wide(c, "bunny", "bunny/bun_zipper.ply");
    bench_wide(c, "dragon", "dragon/dragon_vrip.ply.gz");
}

criterion_group!(bvh, benches);
criterion_main!(bvh);
