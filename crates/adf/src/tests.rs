//! The field's promises, checked on an analytic sphere (exact distances at any depth)
//! and a closed cube mesh.

use crate::*;
use dynray_render::Geometry;
use std::collections::HashSet;

/// A small fixed random stream for test points.
struct Rng(u64);

impl Rng {
    fn f(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((self.0 >> 40) as f32) / (1u64 << 24) as f32
    }
    fn v(&mut self) -> Vec3 {
        Vec3::new(self.f(), self.f(), self.f())
    }
}

fn sphere() -> SphereSource {
    SphereSource { centre: Vec3::new(0.1, -0.2, 0.05), radius: 1.0 }
}

/// The sphere in a box 4 times its size, so deep trees stay small.
fn sphere_adf(max_level: u32, epsilon: f32, rule: bool) -> Adf {
    let b = Aabb::new(Vec3::splat(-4.0), Vec3::splat(4.0));
    Adf::build_with(&sphere(), b, &BuildParams { max_level, epsilon }, &|_, _| {}, rule).unwrap()
}

/// Every internal cell's key, read back from H.
fn stored_keys(adf: &Adf) -> HashSet<[u32; 3]> {
    adf.hash.keys().into_iter().collect()
}

fn key(level: u32, q: [u32; 3], max_level: u32) -> [u32; 3] {
    q.map(|c| (1 << level) + (c >> (max_level - level)))
}

#[test]
fn deep_hashes_are_collision_free_and_find_every_internal_cell() {
    // Level 10: the seed's 4-byte identifiers; level 11: keys past 1024, H's second word.
    for level in [10, 11] {
        check_deep_hash(level);
    }
}

fn check_deep_hash(level: u32) {
    let adf = sphere_adf(level, 1e-3, true);
    let n = adf.internal_cells();
    let deepest = level as usize - 1;
    assert!(adf.info.internal_per_level[deepest] > 0, "cells at level {deepest}: {:?}", adf.info.internal_per_level);
    assert_eq!(adf.hash.high_ids().is_empty(), level <= 10, "second identifier words exactly past level 10");
    let keys = stored_keys(&adf);
    assert_eq!(keys.len() as u64, n, "H holds each internal cell once");
    let mut slots = HashSet::new();
    let mut blocks = HashSet::new();
    for &k in &keys {
        assert!(slots.insert(adf.hash.slot(k)), "collision at {k:?}");
        let b = adf.hash.find(k).expect("stored key found");
        assert!(blocks.insert(b) && (b as u64) < n);
    }
    // H is the smallest cube that holds every internal cell.
    let m = adf.hash.table_edge();
    assert!((m as u64).pow(3) >= n && ((m - 1) as u64).pow(3) < n);
    // The three searches find the deepest stored cell, and the file keeps every table.
    let mut rng = Rng(level as u64);
    let fine = 1u32 << level;
    for _ in 0..2000 {
        let q = rng.v().to_array().map(|c| ((c * fine as f32) as u32).min(fine - 1));
        let want = (1..level).take_while(|&lv| keys.contains(&key(lv, q, level))).last().unwrap_or(0);
        for s in [Search::Linear, Search::Binary, Search::CoherentLinear] {
            assert_eq!(adf.locate_fine(q, s, &mut 0).level, want, "level {level}, {s:?} at {q:?}");
        }
    }
    assert_eq!(Adf::from_bytes(&adf.to_bytes(), std::path::Path::new("deep.adf")).unwrap(), adf);
    eprintln!(
        "level {level}: {n} internal cells, H {m}^3, Φ {}^3, hash {:.0} ms in {} attempt(s), build {:.0} ms",
        adf.hash.offset_edge(),
        adf.info.hash_ms,
        adf.hash.attempts(),
        adf.info.build_ms
    );
}

#[test]
fn point_location_finds_the_deepest_existing_cell_at_every_level() {
    let adf = sphere_adf(9, 1e-3, true);
    let keys = stored_keys(&adf);
    let l = adf.max_level;
    let reference = |q: [u32; 3]| (1..l).take_while(|&lv| keys.contains(&key(lv, q, l))).last().unwrap_or(0);
    let mut rng = Rng(3);
    let mut points: Vec<[u32; 3]> = Vec::new();
    // Points inside stored cells of every level, and uniform ones.
    let mut by_level: Vec<Vec<[u32; 3]>> = vec![Vec::new(); l as usize];
    for k in &keys {
        by_level[(31 - k[0].leading_zeros()) as usize].push(*k);
    }
    for (lv, ks) in by_level.iter().enumerate() {
        assert!(!ks.is_empty(), "no internal cell at level {lv}");
        for k in ks.iter().step_by((ks.len() / 40).max(1)) {
            let span = 1u32 << (l - lv as u32);
            let q = k.map(|c| ((c - (1 << lv)) * span) + (rng.f() * span as f32) as u32 % span);
            assert!(reference(q) >= lv as u32);
            points.push(q);
        }
    }
    let n = 1u32 << l;
    points.extend((0..2000).map(|_| rng.v().to_array().map(|c| ((c * n as f32) as u32).min(n - 1))));
    let mut seen = HashSet::new();
    let mut hint = 0;
    for q in points {
        let want = reference(q);
        seen.insert(want);
        for s in [Search::Linear, Search::Binary] {
            let got = adf.locate_fine(q, s, &mut 0);
            assert_eq!(got.level, want, "{s:?} at {q:?}");
            assert_eq!(Some(got.block), adf.hash.find(key(want, q, l)));
        }
        // Coherent search from the previous point's level and from a random one.
        assert_eq!(adf.locate_fine(q, Search::CoherentLinear, &mut hint).level, want);
        let mut h = (rng.f() * l as f32) as u32;
        assert_eq!(adf.locate_fine(q, Search::CoherentLinear, &mut h).level, want);
    }
    assert!(seen.len() >= 3, "answers at levels {seen:?}");
}

#[test]
fn reconstruction_is_within_epsilon_where_the_build_promised_it() {
    let eps_rel = 2e-3;
    let adf = sphere_adf(7, eps_rel, true);
    let src = sphere();
    let keys = stored_keys(&adf);
    let size = adf.cube.size;
    let eps = adf.epsilon;
    assert!((eps - eps_rel * size).abs() < 1e-6);
    let (mut checked, mut skipped) = (0, 0);
    for &k in &keys {
        let level = 31 - k[0].leading_zeros();
        if level + 1 >= adf.max_level {
            continue; // children at the maximum level: no ε promise
        }
        for o in 0..8u32 {
            let child = [0, 1, 2].map(|c| 2 * k[c] + ((o >> c) & 1));
            if keys.contains(&child) {
                continue;
            }
            // A leaf that passed the ε test: its 27 grid points, in world space.
            let cl = level + 1;
            let idx = child.map(|c| c - (1 << cl));
            let at = |g: [u32; 3]| adf.cube.world([0, 1, 2].map(|c| 2 * idx[c] + g[c]), cl + 1);
            let corners_exact = (0..8u32).all(|c| {
                let p = at([0, 1, 2].map(|a| 2 * ((c >> a) & 1)));
                (adf.distance(p, Search::Linear).unwrap() - src.signed_distance(p)).abs() < 1e-5 * size
            });
            if !corners_exact {
                skipped += 1; // a corner moved by the T-junction rule
                continue;
            }
            for g in 0..27u32 {
                let p = at([g % 3, (g / 3) % 3, g / 9]);
                let err = (adf.distance(p, Search::Binary).unwrap() - src.signed_distance(p)).abs();
                assert!(err <= eps + 1e-5 * size, "leaf {child:?} point {g}: error {err} > ε {eps}");
            }
            checked += 1;
        }
    }
    assert!(checked > 100, "only {checked} promised leaves ({skipped} constrained)");
}

/// The largest `|f(b) − f(a)| / (L |b − a|)` over consecutive samples of random
/// segments through the cube: at most 1 for a continuous field of Lipschitz bound L.
fn worst_lipschitz_ratio(adf: &Adf, segments: usize, steps: usize) -> f32 {
    let mut rng = Rng(11);
    let c = adf.cube;
    let mut worst = 0.0f32;
    for _ in 0..segments {
        let (a, b) = (c.origin + rng.v() * c.size, c.origin + rng.v() * c.size);
        let mut prev = (a, adf.distance(a, Search::Linear).unwrap());
        for i in 1..=steps {
            let p = a + (b - a) * (i as f32 / steps as f32);
            let d = adf.distance(p, Search::CoherentLinear).unwrap();
            let gap = (p - prev.0).length();
            let ratio = ((d - prev.1).abs() - 1e-6 * c.size).max(0.0) / (adf.lipschitz * gap);
            worst = worst.max(ratio);
            prev = (p, d);
        }
    }
    worst
}

#[test]
fn the_field_is_continuous_across_level_changes() {
    let adf = sphere_adf(7, 2e-3, true);
    assert!(adf.info.constrained_samples > 0, "the tree must have T-junctions to test");
    let r = worst_lipschitz_ratio(&adf, 300, 4000);
    assert!(r <= 1.001, "a jump along a segment: {r} × the Lipschitz bound {}", adf.lipschitz);
    // Without the rule the same check sees the cracks, so it can fail.
    let cracked = sphere_adf(7, 2e-3, false);
    let r = worst_lipschitz_ratio(&cracked, 300, 4000);
    assert!(r > 1.5, "expected cracks without the T-junction rule, worst ratio {r}");
}

#[test]
fn sphere_tracing_hits_the_sphere_with_radial_normals() {
    let adf = sphere_adf(8, 1e-3, true);
    let src = sphere();
    let geo = AdfGeometry::new(&adf, dynray_scene::Material::default());
    let mut rng = Rng(5);
    let finest = adf.cube.size / 256.0;
    for _ in 0..300 {
        let target = src.centre + (rng.v() - 0.5) * 1.2;
        let origin = src.centre + (rng.v() - 0.5).normalize() * 3.5;
        let ray = dynray_geom::Ray::new(origin, target - origin);
        let hit = geo.intersect(&ray);
        // The exact sphere's hit.
        let (oc, d) = (origin - src.centre, ray.dir);
        let (a, b, c) = (d.dot(d), oc.dot(d), oc.dot(oc) - 1.0);
        let disc = b * b - a * c;
        if disc < 0.05 * a {
            continue; // grazing or missing: the field's surface is within ε, not exact
        }
        let t = (-b - disc.sqrt()) / a;
        assert!(hit.is_hit(), "missed the sphere along {ray:?}");
        let dl = ray.dir.length();
        assert!((hit.t - t).abs() * dl < 0.5 * finest, "t {} vs {t}", hit.t);
        let s = geo.surface(&ray, &hit, 0).unwrap();
        assert!(s.ng.dot((s.p - src.centre).normalize()) > 0.99, "normal {}", s.ng);
        // A shadow ray leaving the surface outwards is not blocked by it.
        let away = dynray_geom::Ray::new(s.p + s.ng * 1e-5, s.ng);
        assert!(!geo.occluded(&away));
    }
}

#[test]
fn files_round_trip_and_damage_is_an_error() {
    let mut adf = sphere_adf(5, 1e-3, true);
    adf.set_view(Some(View {
        position: Vec3::new(1.0, 2.0, 3.0),
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        projection: ViewProjection::Perspective(45.0),
    }));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.adf");
    adf.save(&path).unwrap();
    assert_eq!(Adf::load(&path).unwrap(), adf);
    let bytes = std::fs::read(&path).unwrap();
    let p = std::path::Path::new("x.adf");
    assert!(matches!(Adf::from_bytes(&bytes[..bytes.len() - 1], p), Err(FileError::Length { .. })));
    assert!(matches!(Adf::from_bytes(&bytes[..100], p), Err(FileError::Length { .. })));
    assert!(matches!(Adf::from_bytes(&bytes[..5], p), Err(FileError::NotAdf { .. })));
    assert!(matches!(Adf::from_bytes(b"not an adf at all", p), Err(FileError::NotAdf { .. })));
    // Version 1 (the 10-level format before this one) and an unknown future version.
    for v in [1u8, 3] {
        let mut other = bytes.clone();
        other[8] = v;
        assert!(matches!(Adf::from_bytes(&other, p), Err(FileError::Version { found, .. }) if found == v as u32));
    }
    // A flipped bit anywhere in the body fails the checksum.
    for at in [200, bytes.len() / 2, bytes.len() - 9] {
        let mut bad = bytes.clone();
        bad[at] ^= 0x10;
        assert!(matches!(Adf::from_bytes(&bad, p), Err(FileError::Corrupt { .. })), "byte {at}");
    }
    // A header claiming huge tables: a length error, nothing allocated.
    let mut huge = bytes.clone();
    huge[24..28].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(matches!(Adf::from_bytes(&huge, p), Err(FileError::Length { .. })));
    // Regression (issue 43): sizes whose product passes 2^64 — block dimensions of
    // 2^31 × 2^31 × 4, a cell table of (2^22)^3 — overflowed the u64 size arithmetic
    // (a panic with overflow checks, a wrapped size without): a length error now.
    let mut wraps = bytes.clone();
    for (i, d) in [1u32 << 31, 1 << 31, 4].into_iter().enumerate() {
        wraps[24 + 4 * i..28 + 4 * i].copy_from_slice(&d.to_le_bytes());
    }
    assert!(matches!(Adf::from_bytes(&wraps, p), Err(FileError::Length { .. })));
    let mut cube = bytes.clone();
    cube[36..40].copy_from_slice(&(1u32 << 22).to_le_bytes());
    assert!(matches!(Adf::from_bytes(&cube, p), Err(FileError::Length { expected: u64::MAX, .. })));
    let msg = Adf::from_bytes(&bytes[..bytes.len() - 1], p).unwrap_err().to_string();
    assert!(msg.starts_with("x.adf: "), "{msg}");
}

#[test]
fn bad_parameters_are_errors() {
    let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
    let build = |max_level, epsilon| Adf::build(&sphere(), b, &BuildParams { max_level, epsilon }, &|_, _| {});
    assert!(matches!(build(17, 1e-3), Err(AdfError::LevelOutOfRange { level: 17, max: 16 })));
    assert!(matches!(build(0, 1e-3), Err(AdfError::LevelOutOfRange { .. })));
    assert!(matches!(build(5, 0.0), Err(AdfError::BadEpsilon(_))));
    assert!(matches!(build(5, f32::NAN), Err(AdfError::BadEpsilon(_))));
    let empty = dynray_geom::TriangleMesh::new(vec![], vec![]);
    assert!(matches!(Adf::from_mesh(&empty, &BuildParams::default(), &|_, _| {}), Err(AdfError::EmptyMesh)));
}

#[test]
fn a_mesh_field_is_signed_and_the_same_for_any_thread_count() {
    let p = (0..8).map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32]).collect();
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let idx = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    let mesh = dynray_geom::TriangleMesh::new(p, idx);
    let params = BuildParams { max_level: 6, epsilon: 1e-3 };
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let (a, topo) = one.install(|| Adf::from_mesh(&mesh, &params, &|_, _| {})).unwrap();
    let (b, _) = Adf::from_mesh(&mesh, &params, &|_, _| {}).unwrap();
    assert!(topo.is_closed());
    let (ab, bb) = (a.to_bytes(), b.to_bytes());
    // Past the header (its build times differ), up to the checksum (which covers them).
    assert_eq!(ab[372..ab.len() - 8], bb[372..bb.len() - 8], "tables differ with the thread count");
    assert!((a.distance(Vec3::splat(0.5), Search::Linear).unwrap() + 0.5).abs() < 1e-3);
    assert!((a.distance(Vec3::new(1.05, 0.5, 0.5), Search::Linear).unwrap() - 0.05).abs() < 2e-3);
}

#[test]
fn local_steps_find_the_crossings_a_dense_march_finds_in_fewer_samples() {
    let adf = sphere_adf(7, 1e-3, true);
    let finest = adf.cube.size / 128.0;
    let mut rng = Rng(17);
    let (mut ours, mut dense_samples) = (0u64, 0u64);
    for _ in 0..400 {
        let origin = adf.cube.origin + rng.v() * adf.cube.size;
        let dir = (rng.v() - 0.5).normalize();
        let ray = dynray_geom::Ray::new(origin, dir);
        let (hit, n) = adf.march_counted(&ray);
        ours += n as u64;
        // Reference: fixed steps of a twentieth of a finest cell, no bound trusted.
        let (t0, t1) = adf.cube.bounds().clip(&dynray_geom::PreparedRay::new(&ray), 0.0, f32::INFINITY).unwrap();
        let f = |t: f32| adf.distance(ray.at(t), Search::Linear).unwrap_or(1.0);
        let (s0, step) = (f(t0), finest / 20.0);
        let mut t = t0;
        let mut want = None;
        while t < t1 {
            let tn = (t + step).min(t1);
            dense_samples += 1;
            if (f(tn) <= 0.0) != (s0 <= 0.0) {
                want = Some(tn);
                break;
            }
            t = tn;
        }
        match (hit, want) {
            (Some(a), Some(b)) => assert!((a - b).abs() <= 2.0 * step, "hit at {a}, dense march at {b}"),
            (None, None) => {}
            (a, b) => panic!("march {a:?} vs dense march {b:?} along {ray:?}"),
        }
    }
    assert!(ours * 10 < dense_samples, "{ours} samples vs {dense_samples} of the dense march");
    // The root's bound is the global one, and every cell's is within it.
    assert_eq!(adf.cell_lipschitz[0], adf.lipschitz);
    assert!(adf.cell_lipschitz.iter().all(|&l| l <= adf.lipschitz));
}
