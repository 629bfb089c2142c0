//! The wide BVH against brute force beyond oracle.rs (which checks every preset at the
//! default width and kernel): both widths × every kernel this CPU runs on the standard bunny and dragon
//! sets, degenerate scenes, tiny meshes (one-leaf roots, padded blocks), refit.
//!
//! Each variant reuses the one brute-force answer of its ray set (support's on-disk
//! cache), so the cost is the variants' own traversal. CI also runs this file with
//! `DYNRAY_FORCE_SCALAR=1`, which sends even the `kernel=auto` builds to the scalar kernel.

mod support;

use dynray_accel::bvh::KernelRequest;
use dynray_accel::{Accel, AccelKind, AccelSpec, BatchQuery, Coherent, Wbvh, WbvhParams};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use support::degenerate::{coplanar_sheet, million_to_one_strip, rays_at};
use support::*;

/// Every width and every kernel this CPU runs, as `--accel` spells them.
fn variants() -> Vec<String> {
    let kernels = KernelRequest::runnable();
    assert!(kernels.contains(&KernelRequest::Scalar));
    [4, 8].iter().flat_map(|w| kernels.iter().map(move |k| format!("bvh:width={w},kernel={}", k.name()))).collect()
}

fn build(spec: &str, mesh: &TriangleMesh) -> Box<dyn Accel> {
    let spec: AccelSpec = spec.parse().unwrap();
    let a = spec.build(mesh, None).unwrap_or_else(|e| panic!("{spec}: {e}"));
    let s = a.validate(mesh).unwrap_or_else(|e| panic!("{spec}: {e}"));
    assert_eq!(s.primitive_refs, mesh.triangle_count(), "{spec}: {s:?}");
    a
}

fn check_variants(mesh: &TriangleMesh, rays: &[Ray], label: &str) {
    for v in variants() {
        let a = build(&v, mesh);
        assert_matches_oracle(a.as_ref(), mesh, rays, &format!("{label} ({v}, kernel {})", kernel_of(a.as_ref())));
    }
}

fn kernel_of(a: &dyn Accel) -> String {
    a.stats().extra.into_iter().find(|(k, _)| k == "kernel").map(|(_, v)| v).unwrap_or_default()
}

#[test]
fn every_width_and_kernel_matches_brute_on_the_bunny() {
    let mesh = bunny();
    check_variants(&mesh, &bunny_rays(&mesh), "bunny");
}

#[test]
fn every_width_and_kernel_matches_brute_on_the_dragon() {
    let mesh = dragon_res2();
    check_variants(&mesh, &dragon_rays(&mesh), "dragon_res2");
}

/// Batches traced with several rays in flight (stream.rs) and one ray at a time give
/// brute force's answers, whatever the kernel; batches smaller than the rays in flight
/// and rays that finish at different steps included.
#[test]
fn interleaved_and_one_at_a_time_batches_match_brute() {
    let mesh = bunny();
    let rays = bunny_rays(&mesh);
    for k in KernelRequest::runnable() {
        for il in ["on", "off"] {
            let v = format!("bvh:kernel={},interleave={il}", k.name());
            let a = build(&v, &mesh);
            assert_matches_oracle(a.as_ref(), &mesh, &rays, &v);
            for n in 0..=5 {
                let (got, occ) = (a.intersect_batch(&rays[..n]), a.occluded_batch(&rays[..n]));
                for (i, r) in rays[..n].iter().enumerate() {
                    let want = a.intersect(r);
                    assert_eq!(
                        (got[i].prim, got[i].t.to_bits()),
                        (want.prim, want.t.to_bits()),
                        "{v}: {n} rays, ray {i}"
                    );
                    assert_eq!(occ[i], a.occluded(r), "{v}: {n} rays, ray {i}");
                }
            }
        }
    }
}

/// Shadow rays of a camera's pixels in order, towards a light above and to the side of
/// the bunny (its ears and back shade its body): a coherent any-hit batch, as the
/// last-occluder cache (`occluder_cache`, stream.rs) expects, with runs of occluded rays
/// and the lit rays that follow them.
fn bunny_shadow_rays(mesh: &TriangleMesh, camera_hits: &dyn Accel) -> Vec<Ray> {
    let b = mesh.bounds();
    let (c, d) = (b.center(), (b.max - b.min).length());
    let eye = c + Vec3::new(0.2, 0.1, 1.0) * d;
    let light = c + Vec3::new(-0.6, 1.0, 0.3) * d;
    let (fwd, n) = ((c - eye).normalize(), 96);
    let right = fwd.cross(Vec3::Y).normalize();
    let up = right.cross(fwd);
    let mut rays = Vec::new();
    for y in 0..n {
        for x in 0..n {
            let (sx, sy) = ((x as f32 + 0.5) / n as f32 - 0.5, 0.5 - (y as f32 + 0.5) / n as f32);
            let primary = Ray::new(eye, fwd + (right * sx + up * sy) * 0.6);
            let h = camera_hits.intersect(&primary);
            if h.is_hit() {
                let p = primary.at(h.t) - primary.dir.normalize() * (d * 1e-4);
                let to = light - p;
                rays.push(Ray::with_interval(p, to, 0.0, 0.9999));
            }
        }
    }
    rays
}

/// The last-occluder cache changes only the work: every kernel, cache on and off, gives
/// brute force's answers on a coherent shadow batch in which occluded rays are followed
/// by lit ones (a cache that answered without its leaf test would fail there).
#[test]
fn occluder_cache_answers_as_brute_force() {
    let mesh = bunny();
    let rays = bunny_shadow_rays(&mesh, build("bvh", &mesh).as_ref());
    assert!(dynray_accel::bvh::looks_coherent(&rays), "the batch must take the cached path");
    let want: Vec<bool> = brute_hits(&mesh, &rays).iter().map(|h| h.is_hit()).collect();
    let lit_after_shadow = want.windows(2).filter(|w| w[0] && !w[1]).count();
    let shadowed = want.iter().filter(|o| **o).count();
    assert!(
        shadowed > 200 && lit_after_shadow > 20,
        "{} rays, {shadowed} occluded, {lit_after_shadow} lit after occluded",
        rays.len()
    );
    for k in KernelRequest::runnable() {
        for cache in ["on", "off"] {
            let v = format!("bvh:kernel={},occluder_cache={cache},interleave=off", k.name());
            let got = build(&v, &mesh).occluded_batch(&rays);
            let bad: Vec<usize> = (0..rays.len()).filter(|&i| got[i] != want[i]).collect();
            assert!(
                bad.is_empty(),
                "{v}: {} of {} rays differ from brute force, first {:?}",
                bad.len(),
                rays.len(),
                &bad[..bad.len().min(5)]
            );
        }
    }
}

/// Trees on huge pages (`huge_pages=on`, what `auto` does above 16 MiB) answer as brute
/// force, single rays and batches, and the stats say which layout a tree got.
#[test]
fn huge_page_trees_match_brute() {
    let mesh = bunny();
    let rays = bunny_rays(&mesh);
    let advice = |a: &dyn Accel| a.stats().extra.into_iter().find(|(k, _)| k == "huge_pages").map(|(_, v)| v);
    for (v, want) in [("bvh:huge_pages=on", "advised"), ("bvh:huge_pages=off", "off"), ("bvh", "off")] {
        let a = build(v, &mesh);
        // The bunny's 4 MiB tree is under `auto`'s threshold.
        assert_eq!(advice(a.as_ref()).as_deref(), Some(want), "{v}");
        assert_matches_oracle(a.as_ref(), &mesh, &rays, v);
        let (got, occ) = (a.intersect_batch(&rays), a.occluded_batch(&rays));
        for (i, r) in rays.iter().enumerate().step_by(7) {
            let one = a.intersect(r);
            assert_eq!((got[i].prim, got[i].t.to_bits()), (one.prim, one.t.to_bits()), "{v}: ray {i}");
            assert_eq!(occ[i], a.occluded(r), "{v}: ray {i}");
        }
    }
}

#[test]
fn each_kernel_is_what_kernel_asks_for() {
    let mesh = bunny();
    let scalar = build("bvh:kernel=scalar", &mesh);
    assert_eq!(kernel_of(scalar.as_ref()), "scalar");
    // Each named kernel is the one used; without the environment override, `auto` takes
    // the widest this CPU runs.
    let runnable = KernelRequest::runnable();
    for k in &runnable {
        assert_eq!(kernel_of(build(&format!("bvh:kernel={}", k.name()), &mesh).as_ref()), k.name());
    }
    if std::env::var_os(dynray_accel::bvh::FORCE_SCALAR_ENV).is_none() {
        assert_eq!(kernel_of(build("bvh", &mesh).as_ref()), runnable.last().unwrap().name());
    }
    // A kernel the CPU lacks is refused by name, not silently replaced.
    for k in [KernelRequest::Avx2, KernelRequest::Avx512].into_iter().filter(|k| !runnable.contains(k)) {
        let spec: AccelSpec = format!("bvh:kernel={}", k.name()).parse().unwrap();
        let e = spec.build(&mesh, None).err().expect("a kernel this CPU lacks must be refused").to_string();
        assert!(e.contains("kernel") && e.contains(k.name()), "{e}");
    }
}

#[test]
fn registry_builds_the_wide_bvh_by_name_with_sane_stats() {
    let mesh = bunny();
    let a = "bvh".parse::<AccelKind>().unwrap().build(&mesh).unwrap();
    assert_eq!(a.name(), "bvh");
    let s = a.stats();
    assert_eq!(s.leaf_sizes.iter().enumerate().map(|(k, c)| k * c).sum::<usize>(), mesh.triangle_count());
    assert!(s.sah_cost.is_some_and(|c| c > 1.0) && s.max_depth >= 3, "{s:?}");
    // 256-byte nodes and 160-byte blocks, at least ⌈n/4⌉ of them.
    assert!(s.memory_bytes >= mesh.triangle_count().div_ceil(4) * 160, "{s:?}");
    // The binary BVH is at least 2.5× deeper than its 8-wide collapse on the bunny (18 levels).
    let bvh = AccelKind::Bvh2.build(&mesh).unwrap().stats();
    assert!(s.max_depth * 2 <= bvh.max_depth, "wbvh depth {} vs bvh {}", s.max_depth, bvh.max_depth);
}

#[test]
fn tiny_meshes_with_one_leaf_roots_and_padded_blocks() {
    // 1..=9 triangles of a fan: a root with one leaf child, partly filled blocks, a
    // second level once the builder splits.
    for n in 1..=9u32 {
        let mut pos = vec![[0.0, 0.0, 0.0]];
        for k in 0..=n {
            let a = k as f32 * 0.6;
            pos.push([a.cos(), a.sin(), 0.1 * k as f32]);
        }
        let mesh = TriangleMesh::new(pos, (0..n).map(|k| [0, k + 1, k + 2]).collect());
        let mut rays = random_rays(&mesh, 1_000, 40 + n as u64);
        rays.extend(adversarial_rays(&mesh, 500, 60 + n as u64));
        check_variants(&mesh, &rays, &format!("fan of {n}"));
    }
}

#[test]
fn degenerate_scenes() {
    let sheet = coplanar_sheet();
    let b = sheet.bounds();
    let mut rays = rays_at(b.min, b.max, 4_000, 31);
    rays.extend(adversarial_rays(&sheet, 1_000, 32));
    check_variants(&sheet, &rays, "coplanar sheet");

    let strip = million_to_one_strip();
    let mut rays = random_rays(&strip, 3_000, 33);
    rays.extend(adversarial_rays(&strip, 1_000, 34));
    check_variants(&strip, &rays, "1e6:1 strip");

    // 20k triangles in one point: every centroid equal, median splits by index.
    let point = TriangleMesh::new(vec![[0.3, -0.2, 1.0]; 3], (0..20_000).map(|_| [0, 1, 2]).collect());
    let rays: Vec<Ray> = (0..100)
        .map(|i| {
            let o = Vec3::new(i as f32 * 0.02 - 1.0, 2.0, 0.5);
            Ray::new(o, Vec3::new(0.3, -0.2, 1.0) - o)
        })
        .collect();
    check_variants(&point, &rays, "one point");
}

#[test]
fn identical_triangles_tie_to_the_lowest_index() {
    // 10k copies of one triangle: every hit is at the same `t`, so the answer is triangle
    // 0 only if no leaf is culled at exactly the best `t`.
    let mesh = TriangleMesh::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        (0..10_000).map(|_| [0, 1, 2]).collect(),
    );
    let rays: Vec<Ray> = (0..16)
        .map(|i| Ray::new(Vec3::new(0.05 * i as f32, 0.2, 1.0 + i as f32), Vec3::new(0.01, 0.0, -1.0)))
        .collect();
    for v in variants() {
        let a = build(&v, &mesh);
        // The first rays hit (the later ones pass beside the triangle).
        assert!(rays[..8].iter().all(|r| a.intersect(r).prim == 0), "{v}");
        assert_matches_oracle(a.as_ref(), &mesh, &rays, &format!("10k copies ({v})"));
    }
}

/// Refits `a` to two waves of `mesh` (amplitudes 0.01 and 0.2), validating it and
/// holding it to brute force after each on `random` = (count, seed) random and
/// `adversarial` rays of the moved mesh (seeds + the wave's step).
fn follow_waves(a: &mut dyn Accel, mesh: &TriangleMesh, label: &str, random: (usize, u64), adversarial: (usize, u64)) {
    for (step, amp) in [(0u64, 0.01f32), (1, 0.2)] {
        let moved = wave(mesh, amp, step as f32);
        a.update(&moved).unwrap();
        a.validate(&moved).unwrap_or_else(|e| panic!("{label} after refit: {e}"));
        let mut rays = random_rays(&moved, random.0, random.1 + step);
        rays.extend(adversarial_rays(&moved, adversarial.0, adversarial.1 + step));
        assert_matches_oracle(a, &moved, &rays, &format!("{label} wave {amp}"));
    }
}

#[test]
fn refit_follows_a_wave_and_refitting_back_restores_the_tree() {
    let mesh = bunny();
    for v in ["bvh:width=4", "bvh:width=8"] {
        let mut a = build(v, &mesh);
        assert!(a.update_refits(), "{v}");
        let before = a.stats();
        let probe = random_rays(&mesh, 5_000, 90);
        let hits_before = a.as_ref().intersect_batch(&probe);
        // The waves and rays of oracle.rs's update test, so the brute-force answers are shared.
        follow_waves(a.as_mut(), &mesh, v, (4_000, 500), (1_000, 600));
        a.update(&mesh).unwrap();
        assert_eq!(a.stats(), before, "{v}: refitting back must give the built tree");
        assert!(a.as_ref().intersect_batch(&probe).iter().zip(&hits_before).all(|(x, y)| x.same_as(y)), "{v}");
    }
}

#[test]
fn block_cost_off_builds_a_valid_tree_too() {
    let mesh = dragon_res2();
    let p = WbvhParams { block_cost: false, ..WbvhParams::default() };
    let w = Wbvh::build(&mesh, &p).unwrap();
    w.validate(&mesh).unwrap();
    let on = Wbvh::build(&mesh, &WbvhParams::default()).unwrap().stats();
    // Block cost makes fewer, fuller leaves (the point of it).
    assert!(on.leaves < w.stats().leaves, "{} vs {}", on.leaves, w.stats().leaves);
    assert_matches_oracle(&w, &mesh, &dragon_rays(&mesh), "dragon_res2 block_cost=off");
}

/// Large slanted triangles among small ones (what pre-splitting cuts), seeded.
fn slanted_mesh(seed: u64, big: usize, small: usize) -> TriangleMesh {
    use rand::{rngs::SmallRng, Rng, SeedableRng};
    let mut rng = SmallRng::seed_from_u64(seed);
    let mut p = |r: f32| Vec3::new(rng.gen_range(-r..r), rng.gen_range(-r..r), rng.gen_range(-r..r));
    let mut positions = Vec::new();
    for _ in 0..big {
        positions.extend([p(10.0), p(10.0), p(10.0)].map(|v| v.to_array()));
    }
    for _ in 0..small {
        let c = p(9.0);
        positions.extend([c + p(0.3), c + p(0.3), c + p(0.3)].map(|v| v.to_array()));
    }
    let indices = (0..(big + small) as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    TriangleMesh::new(positions, indices)
}

/// Rays aimed at the points where the mesh's triangles cross the planes of the first
/// levels of a power-of-two grid over the mesh's box (where pre-splitting cuts), from
/// random points around the mesh: hits that land on the seam between two parts.
fn rays_at_grid_planes(mesh: &TriangleMesh, n: usize, seed: u64) -> Vec<Ray> {
    use rand::{rngs::SmallRng, Rng, SeedableRng};
    let mut rng = SmallRng::seed_from_u64(seed);
    let b = mesh.bounds();
    let diag = b.extent().length();
    let mut rays = Vec::with_capacity(n);
    while rays.len() < n {
        let t = mesh.triangle(rng.gen_range(0..mesh.triangle_count()));
        let axis = rng.gen_range(0..3);
        let level = rng.gen_range(1..6);
        let cells = (1u32 << level) as f32;
        let c = b.min[axis] + (b.extent()[axis] / cells) * rng.gen_range(1..(1u32 << level)) as f32;
        let v = [t.p0, t.p1, t.p2];
        for i in 0..3 {
            let (p, q) = (v[i], v[(i + 1) % 3]);
            if (p[axis] - c) * (q[axis] - c) < 0.0 {
                let s = (c - p[axis]) / (q[axis] - p[axis]);
                let at = p + (q - p) * s;
                let from =
                    at + Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)) * diag;
                rays.push(Ray::new(from, at - from));
            }
        }
    }
    rays.truncate(n);
    rays
}

/// The first frame of BART's kitchen: 110k triangles, walls, floor and table tops of a
/// few large triangles each (the scene pre-splitting was measured on).
fn kitchen() -> TriangleMesh {
    let scene = dynray_scene::load_file(&scenes_dir().join("bart/kitchen/aff/kitchen.aff"))
        .unwrap_or_else(|e| panic!("test scene missing or unreadable ({e}); set DYNRAY_SCENES"));
    scene.frame(scene.animation.timeline.time_of(0)).mesh
}

/// Pre-split trees (a triangle in several leaves, each leaf box over its parts) give brute
/// force's answers at both widths with every kernel, on the kitchen, a slanted synthetic
/// mesh and the Cornell box, including rays that hit exactly where the parts meet; they
/// validate, and they really split.
#[test]
fn presplit_trees_match_brute() {
    let cornell = dynray_scene::load_file(&scenes_dir().join("cornell-box/mcguire-obj/CornellBox-Original.obj"))
        .expect("Cornell box")
        .frame(0.0)
        .mesh;
    for (label, mesh, rays_n) in [
        ("kitchen", kitchen(), 6_000),
        ("slanted", slanted_mesh(21, 300, 20_000), 20_000),
        ("cornell", cornell, 20_000),
    ] {
        let mut rays = random_rays(&mesh, rays_n, 31);
        rays.extend(adversarial_rays(&mesh, rays_n / 4, 32));
        rays.extend(rays_at_grid_planes(&mesh, rays_n / 2, 33));
        for v in variants() {
            for budget in ["0.1", "1"] {
                let spec = format!("{v},presplit={budget}");
                let a = build_unchecked(&spec, &mesh);
                let s = a.validate(&mesh).unwrap_or_else(|e| panic!("{label} {spec}: {e}"));
                // (The Cornell box's 36 triangles get under one extra reference at 0.1.)
                let must_split = budget == "1" || label != "cornell";
                assert!(s.primitive_refs > mesh.triangle_count() || !must_split, "{label} {spec}: nothing split");
                assert_matches_oracle(a.as_ref(), &mesh, &rays, &format!("{label} ({spec})"));
                // Packets (groups of 8 rays from one origin) through the same tree.
                let packets = one_origin_groups(&rays);
                let want = brute_hits(&mesh, &packets);
                let got = Coherent(a.as_ref()).intersect_batch(&packets);
                let occ = Coherent(a.as_ref()).occluded_batch(&packets);
                let bad =
                    (0..packets.len()).filter(|&i| !got[i].same_as(&want[i]) || occ[i] != want[i].is_hit()).count();
                assert_eq!(bad, 0, "{label} ({spec}): {bad} of {} packet lanes differ from brute force", packets.len());
            }
        }
    }
}

/// A pre-split tree refits: its leaves then hold the moved triangles' whole boxes, and it
/// answers as brute force on the moved mesh.
#[test]
fn presplit_tree_refits() {
    let mesh = slanted_mesh(22, 200, 10_000);
    let mut a = build_unchecked("bvh:presplit=0.5", &mesh);
    follow_waves(a.as_mut(), &mesh, "presplit refit", (5_000, 700), (2_000, 800));
    assert!(a.update(&slanted_mesh(22, 200, 9_999)).is_err(), "a mesh of another triangle count refits");
}

/// `rays` regrouped into packets: each group of 8 consecutive rays restarted from the
/// first one's origin, aimed at the same points.
fn one_origin_groups(rays: &[Ray]) -> Vec<Ray> {
    rays.chunks(8)
        .flat_map(|g| {
            let o = g[0].origin;
            g.iter().map(move |r| Ray::new(o, r.origin + r.dir - o))
        })
        .collect()
}

fn build_unchecked(spec: &str, mesh: &TriangleMesh) -> Box<dyn Accel> {
    let spec: AccelSpec = spec.parse().unwrap();
    spec.build(mesh, None).unwrap_or_else(|e| panic!("{spec}: {e}"))
}
