//! Shared oracle machinery for the structure tests: real meshes, seeded ray sets, and
//! brute-force answers computed once and cached on disk under the test target directory,
//! so every test binary (one per structure) and every later run reuses them.
#![allow(dead_code)]

pub mod degenerate;

use dynray_accel::{Accel, BatchQuery, Brute};
use dynray_geom::{Hit, Ray, TriangleMesh, Vec3};
use rand::{rngs::SmallRng, Rng, SeedableRng};
use std::path::PathBuf;

/// `../shared/scenes` beside the checkout, or `$DYNRAY_SCENES`.
pub fn scenes_dir() -> PathBuf {
    if let Ok(d) = std::env::var("DYNRAY_SCENES") {
        return PathBuf::from(d);
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes")
}

/// Loads a model from the scenes directory; panics with a clear message if it is absent
/// (CI always has it: a missing model is a broken setup, not a reason to skip).
pub fn load(rel: &str) -> TriangleMesh {
    let p = scenes_dir().join(rel);
    dynray_scene::formats::ply::load(&p)
        .unwrap_or_else(|e| panic!("test model missing or unreadable ({e}); set DYNRAY_SCENES"))
}

pub fn bunny() -> TriangleMesh {
    load("bunny/bun_zipper.ply")
}

pub fn dragon_res2() -> TriangleMesh {
    load("dragon/dragon_vrip_res2.ply.gz")
}

fn rand_dir(rng: &mut SmallRng) -> Vec3 {
    loop {
        let v = Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
        let l = v.length_squared();
        if l > 1e-4 && l <= 1.0 {
            return v / l.sqrt();
        }
    }
}

fn rand_in(rng: &mut SmallRng, lo: Vec3, hi: Vec3) -> Vec3 {
    Vec3::new(rng.gen_range(lo.x..=hi.x), rng.gen_range(lo.y..=hi.y), rng.gen_range(lo.z..=hi.z))
}

/// A seeded mix: camera-like rays from outside aimed into the box (40 %), rays from
/// inside the box in random directions (25 %), axis-parallel rays (10 %), directions
/// with one or two zero components (10 %), and clipped `[tmin, tmax]` intervals (15 %).
pub fn random_rays(mesh: &TriangleMesh, n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = SmallRng::seed_from_u64(seed);
    let b = mesh.bounds();
    let (lo, hi, c) = (b.min, b.max, b.center());
    let diag = b.extent().length();
    (0..n)
        .map(|i| match i % 20 {
            0..=7 => {
                let o = c + rand_dir(&mut rng) * diag * 1.5;
                let target = rand_in(&mut rng, lo, hi);
                Ray::new(o, target - o)
            }
            8..=12 => Ray::new(rand_in(&mut rng, lo, hi), rand_dir(&mut rng)),
            13 | 14 => {
                let axis = rng.gen_range(0..3);
                let mut d = Vec3::ZERO;
                d[axis] = if rng.gen() { 1.0 } else { -1.0 };
                Ray::new(rand_in(&mut rng, lo, hi), d)
            }
            15 | 16 => {
                let mut d = rand_dir(&mut rng);
                d[rng.gen_range(0..3)] = 0.0;
                if rng.gen() {
                    d[rng.gen_range(0..3)] = 0.0;
                }
                let o = if rng.gen() { rand_in(&mut rng, lo, hi) } else { c - d * diag };
                Ray::new(o, d)
            }
            _ => {
                let o = c + rand_dir(&mut rng) * diag;
                let d = (rand_in(&mut rng, lo, hi) - o).normalize();
                let tmin = rng.gen_range(0.0..1.2 * diag);
                let tmax = tmin + rng.gen_range(0.0..0.8 * diag);
                Ray::with_interval(o, d, tmin, tmax)
            }
        })
        .collect()
}

/// Rays that stress the edges of every structure: aimed exactly at vertices and edge
/// midpoints, starting on a vertex, running along an edge (grazing), with huge and tiny
/// direction lengths, empty and zero-length intervals.
pub fn adversarial_rays(mesh: &TriangleMesh, n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = SmallRng::seed_from_u64(seed);
    let b = mesh.bounds();
    let c = b.center();
    let diag = b.extent().length();
    let nt = mesh.triangle_count();
    (0..n)
        .map(|i| {
            let tri = mesh.triangle(rng.gen_range(0..nt));
            let verts = [tri.p0, tri.p1, tri.p2];
            let v = verts[rng.gen_range(0..3)];
            let w = verts[rng.gen_range(0..3)];
            let far = c + rand_dir(&mut rng) * diag * 2.0;
            match i % 10 {
                0 => Ray::new(far, v - far),
                1 => Ray::new(far, (v + w) * 0.5 - far),
                2 => Ray::new(v, rand_dir(&mut rng)),
                3 => Ray::new(v, w - v),
                4 => Ray::new(v - (w - v), w - v),
                5 => Ray::new(far, (tri.centroid() - far) * 1e-18),
                6 => Ray::new(far, (tri.centroid() - far) * 1e18),
                7 => {
                    let d = tri.centroid() - far;
                    let t = rng.gen_range(0.5f32..1.0);
                    Ray::with_interval(far, d, t, t)
                }
                8 => Ray::with_interval(far, tri.centroid() - far, 2.0, 1.0),
                _ => Ray::with_interval(far, tri.centroid() - far, f32::NEG_INFINITY, f32::INFINITY),
            }
        })
        .collect()
}

fn fnv(h: &mut u64, bytes: &[u8]) {
    for &b in bytes {
        *h ^= b as u64;
        *h = h.wrapping_mul(0x100000001b3);
    }
}

fn key(mesh: &TriangleMesh, rays: &[Ray], probe: &[Hit]) -> u64 {
    let mut h = 0xcbf29ce484222325u64;
    fnv(&mut h, bytemuck::cast_slice(&mesh.positions));
    fnv(&mut h, bytemuck::cast_slice(&mesh.indices));
    for r in rays {
        for f in [r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax] {
            fnv(&mut h, &f.to_bits().to_le_bytes());
        }
    }
    // The triangle test's source and a live probe of it: a changed test changes the key.
    fnv(&mut h, include_str!("../../../geom/src/triangle.rs").as_bytes());
    fnv(&mut h, include_str!("../../../geom/src/ray.rs").as_bytes());
    for p in probe {
        fnv(&mut h, &p.t.to_bits().to_le_bytes());
        fnv(&mut h, &p.prim.to_le_bytes());
    }
    h
}

/// Brute-force closest hits of `rays`, read from the on-disk cache when an earlier test
/// (of any structure) already computed them for the same mesh, rays and triangle test.
pub fn brute_hits(mesh: &TriangleMesh, rays: &[Ray]) -> Vec<Hit> {
    // Tests of one binary run in parallel: let the first compute a set while the others
    // wait and then read it from the cache, instead of all computing it at once.
    static COMPUTING: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _guard = COMPUTING.lock().unwrap_or_else(|e| e.into_inner());
    let brute = Brute::build(mesh).expect("oracle mesh");
    let probe: Vec<Hit> = rays.iter().take(32).map(|r| brute.intersect(r)).collect();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("oracle-cache");
    let file = dir.join(format!("{:016x}.bin", key(mesh, rays, &probe)));
    if let Ok(bytes) = std::fs::read(&file) {
        if bytes.len() == rays.len() * 16 {
            return bytes
                .chunks_exact(16)
                .map(|c| {
                    let w = |i: usize| u32::from_le_bytes(c[i * 4..i * 4 + 4].try_into().unwrap());
                    Hit { t: f32::from_bits(w(0)), u: f32::from_bits(w(1)), v: f32::from_bits(w(2)), prim: w(3) }
                })
                .collect();
        }
    }
    let hits = brute.intersect_batch(rays);
    let mut bytes = Vec::with_capacity(hits.len() * 16);
    for h in &hits {
        for w in [h.t.to_bits(), h.u.to_bits(), h.v.to_bits(), h.prim] {
            bytes.extend_from_slice(&w.to_le_bytes());
        }
    }
    let _ = std::fs::create_dir_all(&dir);
    let tmp = file.with_extension(format!("tmp{}", std::process::id()));
    if std::fs::write(&tmp, &bytes).is_ok() {
        let _ = std::fs::rename(&tmp, &file);
    }
    hits
}

/// Asserts that `accel` returns exactly the oracle's hit (same `t` bits, same triangle,
/// same barycentrics) for every ray, and that `occluded` agrees with "has a closest hit".
pub fn assert_matches_oracle(accel: &dyn Accel, mesh: &TriangleMesh, rays: &[Ray], label: &str) {
    let want = brute_hits(mesh, rays);
    let got = accel.intersect_batch(rays);
    let mut bad = Vec::new();
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        let same = g.prim == w.prim
            && g.t.to_bits() == w.t.to_bits()
            && g.u.to_bits() == w.u.to_bits()
            && g.v.to_bits() == w.v.to_bits();
        if !same {
            bad.push(i);
        }
    }
    let occ = accel.occluded_batch(rays);
    let bad_occ: Vec<usize> = (0..rays.len()).filter(|&i| occ[i] != want[i].is_hit()).collect();
    let hits = want.iter().filter(|h| h.is_hit()).count();
    let show = |v: &[usize], what: &str| {
        v.iter()
            .take(5)
            .map(|&i| {
                format!(
                    "  ray {i} {:?}: {what} got {:?}, brute {:?}",
                    rays[i],
                    if what == "hit" { format!("{:?}", got[i]) } else { format!("{}", occ[i]) },
                    want[i]
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert!(
        bad.is_empty() && bad_occ.is_empty(),
        "{} on {label}: {} of {} rays differ from brute force in closest hit, {} in occluded ({} oracle hits)\n{}\n{}",
        accel.name(),
        bad.len(),
        rays.len(),
        bad_occ.len(),
        hits,
        show(&bad, "hit"),
        show(&bad_occ, "occluded"),
    );
}

/// The standard bunny set every structure is checked on: 100k random + 20k adversarial.
pub fn bunny_rays(mesh: &TriangleMesh) -> Vec<Ray> {
    let mut r = random_rays(mesh, 100_000, 1);
    r.extend(adversarial_rays(mesh, 20_000, 2));
    r
}

/// The standard set for the 202k-triangle dragon: 20k random + 5k adversarial + 2k far.
pub fn dragon_rays(mesh: &TriangleMesh) -> Vec<Ray> {
    let mut r = dragon_near_rays(mesh);
    r.extend(far_rays(mesh, 2_000, 5));
    r
}

/// The dragon set without its far rays: 20k random + 5k adversarial.
pub fn dragon_near_rays(mesh: &TriangleMesh) -> Vec<Ray> {
    let mut r = random_rays(mesh, 20_000, 3);
    r.extend(adversarial_rays(mesh, 5_000, 4));
    r
}

/// Rays from 10^5 to 10^10 units away (10^k × the model's size, k in 0..5, scaled by its
/// distance unit), aimed at vertices, edge midpoints and triangle centroids: the entry
/// point's arithmetic far from the model is where an exact walk can lose its way.
pub fn far_rays(mesh: &TriangleMesh, n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = SmallRng::seed_from_u64(seed);
    let c = mesh.bounds().center();
    let nt = mesh.triangle_count();
    (0..n)
        .map(|i| {
            let tri = mesh.triangle(rng.gen_range(0..nt));
            let target = match i % 3 {
                0 => tri.p0,
                1 => (tri.p1 + tri.p2) * 0.5,
                _ => tri.centroid(),
            };
            let distance = 10f32.powi(5 + (i % 6) as i32);
            let o = c + rand_dir(&mut rng) * distance;
            if i % 4 == 3 {
                // Normalised: t is then about the distance itself.
                Ray::new(o, (target - o).normalize())
            } else {
                Ray::new(o, target - o)
            }
        })
        .collect()
}

/// `mesh` with every vertex moved by a travelling wave of `amp` × the model's largest
/// extent (in y, varying over x and z with `phase`), as an animation frame would: same
/// triangles, same order, new positions.
pub fn wave(mesh: &TriangleMesh, amp: f32, phase: f32) -> TriangleMesh {
    let b = mesh.bounds();
    let k = std::f32::consts::TAU * 3.0 / b.extent().max_element();
    let a = amp * b.extent().max_element();
    let mut m = mesh.clone();
    for p in &mut m.positions {
        p[1] += a * (k * p[0] + phase).sin() * (k * p[2] - phase).cos();
    }
    m
}
