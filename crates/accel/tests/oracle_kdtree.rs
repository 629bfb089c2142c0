//! The kd-tree (standard stack traversal and stackless Ropes++) against brute force: real
//! models, every preset, degenerate inputs, and rays lying exactly in split planes.

mod support;

use dynray_accel::StructureParams;
use dynray_accel::{Accel, AccelKind, BuildError, KdTree, KdTreeParams, KdTreeRopes};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use rand::{rngs::SmallRng, Rng, SeedableRng};
use support::*;

/// Builds both variants and validates them.
fn build_both(mesh: &TriangleMesh, params: &KdTreeParams, label: &str) -> (KdTree, KdTreeRopes) {
    let std_tree = KdTree::build_with(mesh, params).unwrap();
    let ropes = KdTreeRopes::build_with(mesh, params).unwrap();
    std_tree.validate(mesh).unwrap_or_else(|e| panic!("{label}: kdtree invalid: {e}"));
    ropes.validate(mesh).unwrap_or_else(|e| panic!("{label}: kdtree-ropes invalid: {e}"));
    (std_tree, ropes)
}

/// Builds both variants, validates them, and checks them against the oracle.
fn check_both(mesh: &TriangleMesh, params: &KdTreeParams, rays: &[Ray], label: &str) -> (KdTree, KdTreeRopes) {
    let (std_tree, ropes) = build_both(mesh, params, label);
    assert_matches_oracle(&std_tree, mesh, rays, label);
    assert_matches_oracle(&ropes, mesh, rays, label);
    (std_tree, ropes)
}

/// Random and adversarial rays over a (small or degenerate) mesh.
fn mixed_rays(mesh: &TriangleMesh, n: usize, seed: u64) -> Vec<Ray> {
    let mut r = random_rays(mesh, n, seed);
    r.extend(adversarial_rays(mesh, n / 4, seed + 1));
    r
}

/// Asserts the structure stayed small: references per triangle within the cap, and
/// nodes no more than a few per reference.
fn assert_bounded(t: &dyn Accel, tris: usize, params: &KdTreeParams, label: &str) {
    let s = t.stats();
    assert!(
        s.primitive_refs as f64 <= params.max_refs_per_triangle as f64 * tris as f64 + 1.0,
        "{label}: {} references for {tris} triangles",
        s.primitive_refs
    );
    assert!(s.nodes <= 4 * s.primitive_refs + 1, "{label}: {} nodes for {} references", s.nodes, s.primitive_refs);
    assert!(s.max_depth <= params.depth_limit(tris), "{label}: depth {}", s.max_depth);
}

#[test]
fn bunny_tree_is_deep_with_bounded_duplication() {
    // The oracle check of the bunny is in oracle.rs; this is the shape of the tree.
    let mesh = bunny();
    let (t, r) = build_both(&mesh, &KdTreeParams::default(), "bunny");
    let s = t.stats();
    // A real SAH kd-tree on the bunny: deep, many leaves, and duplication from straddling
    // triangles that the depth limit keeps in check (≈5.5 with the defaults).
    assert!(s.leaves > 10_000 && s.max_depth >= 15, "{s:?}");
    let refs = s.primitive_refs as f64 / mesh.triangle_count() as f64;
    assert!((1.5..8.0).contains(&refs), "{refs} references per triangle");
    // Ropes cost memory on top of the same tree (seed 000: "more than twice").
    assert!(r.memory_bytes() > t.memory_bytes() + 40 * s.leaves, "{} vs {}", r.memory_bytes(), t.memory_bytes());
}

#[test]
fn presets_differ_and_respect_their_bounds_on_bunny() {
    // Every preset's oracle check is in oracle.rs; here what distinguishes them.
    let mesh = bunny();
    let mut nodes = Vec::new();
    for (name, params) in KdTreeParams::presets() {
        let (t, _) = build_both(&mesh, &params, &format!("bunny/{name}"));
        assert_bounded(&t, mesh.triangle_count(), &params, name);
        nodes.push(t.stats().nodes);
    }
    // The presets really differ: fast is the smallest tree, high quality the largest.
    assert!(nodes[0] < nodes[1] && nodes[1] < nodes[2], "nodes per preset {nodes:?}");
}

#[test]
fn ropes_walk_is_stackless_on_almost_every_random_ray() {
    let mesh = bunny();
    let t = KdTreeRopes::build(&mesh).unwrap();
    let rays = random_rays(&mesh, 20_000, 11);
    let stackless = rays.iter().filter(|r| t.walk_is_stackless(r)).count();
    // Hand-overs to the stack happen only at edges and corners met within rounding.
    assert!(stackless as f64 >= 0.995 * rays.len() as f64, "{stackless} of {} stackless", rays.len());
}

#[test]
fn counted_traversal_returns_the_same_hits() {
    let mesh = bunny();
    let rays = random_rays(&mesh, 2_000, 5);
    let accels: [Box<dyn Accel>; 2] =
        [Box::new(KdTree::build(&mesh).unwrap()), Box::new(KdTreeRopes::build(&mesh).unwrap())];
    for a in &accels {
        let mut c = dynray_accel::TraversalCounts::default();
        for r in &rays {
            assert!(a.intersect_counted(r, &mut c).same_as(&a.intersect(r)), "{}: {r:?}", a.name());
        }
        assert!(c.nodes > rays.len() as u64 && c.triangles > 0, "{}: {c:?}", a.name());
    }
}

/// An `n`×`n` grid of unit quads lying exactly in the plane z = `z`, x and y from `x0`.
fn flat_grid(n: u32, x0: f32, z: f32) -> TriangleMesh {
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            pos.push([x0 + i as f32, x0 + j as f32, z]);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let v = j * (n + 1) + i;
            idx.push([v, v + 1, v + n + 2]);
            idx.push([v, v + n + 2, v + n + 1]);
        }
    }
    TriangleMesh::new(pos, idx)
}

#[test]
fn coplanar_axis_aligned_grid_matches_brute_force() {
    let mesh = flat_grid(40, -20.0, 0.75);
    for (name, params) in KdTreeParams::presets() {
        let (t, _) = check_both(&mesh, &params, &mixed_rays(&mesh, 8_000, 21), &format!("flat grid/{name}"));
        assert_bounded(&t, mesh.triangle_count(), &params, name);
    }
}

#[test]
fn stacked_and_crossing_grids_match_brute_force() {
    // Grids in z = 0.75 and z = 3, plus a vertical grid in x = 0.5 crossing both: the SAH
    // puts planes exactly on the geometry, and planar triangles must land on one side.
    let mut mesh = flat_grid(20, -10.0, 0.75);
    mesh.append(&flat_grid(20, -10.0, 3.0));
    let mut wall = flat_grid(12, -6.0, 0.0);
    wall.positions.iter_mut().for_each(|p| *p = [0.5, p[0], p[1] + 4.0]);
    mesh.append(&wall);
    let params = KdTreeParams::default();
    let (t, _) = check_both(&mesh, &params, &mixed_rays(&mesh, 12_000, 23), "crossing grids");
    assert_bounded(&t, mesh.triangle_count(), &params, "crossing grids");
    let planes = t.nodes().iter().filter(|n| !n.is_leaf()).filter(|n| [0.75, 3.0, 0.5].contains(&n.split())).count();
    assert!(planes > 0, "no split lies on the geometry; the test would prove little");
}

#[test]
fn all_triangles_in_one_point_stay_one_leaf() {
    let mesh = TriangleMesh::new(vec![[1.0, 2.0, 3.0]; 3], vec![[0, 1, 2]; 5_000]);
    // The shared ray sets need a box with volume; aim at and start from the point instead.
    let mut rng = SmallRng::seed_from_u64(31);
    let p = Vec3::new(1.0, 2.0, 3.0);
    let rays: Vec<Ray> = (0..400)
        .map(|i| {
            let mut d = Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
            if i % 4 == 3 {
                d.x = 0.0;
            }
            if i % 2 == 0 {
                Ray::new(p - d * 3.0, d)
            } else {
                Ray::new(p, d)
            }
        })
        .collect();
    let (t, r) = check_both(&mesh, &KdTreeParams::high_quality(), &rays, "one point");
    assert_eq!((t.stats().nodes, t.stats().primitive_refs), (1, 5_000));
    assert_eq!(r.stats().leaves, 1);
}

#[test]
fn single_triangle_matches_brute_force() {
    let mesh = TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.2, 0.0], [0.3, 1.0, 0.5]], vec![[0, 1, 2]]);
    for (name, params) in KdTreeParams::presets() {
        check_both(&mesh, &params, &mixed_rays(&mesh, 4_000, 41), &format!("single/{name}"));
    }
}

#[test]
fn many_identical_triangles_keep_the_lowest_index() {
    let mesh = TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.2], [0.0, 1.0, 0.4]], vec![[0, 1, 2]; 100_000]);
    let params = KdTreeParams::default();
    let rays = mixed_rays(&mesh, 400, 51);
    let (t, _) = check_both(&mesh, &params, &rays, "100k identical");
    // No plane separates identical triangles: one leaf, no duplication.
    assert_eq!(t.stats().primitive_refs, 100_000);
    assert!(rays.iter().map(|r| t.intersect(r)).any(|h| h.prim == 0), "no ray hit the stack");
}

#[test]
fn extreme_aspect_ratio_scene_matches_brute_force() {
    // A 1e6 : 1 : 1 slab of small triangles, one in ten stretched 100 : 1 along the slab.
    // (Needles as long as the slab are left out on purpose: at 1e6 with f32 their
    // triangle test itself reports hits thousands of units away from the needle, which
    // no spatial structure can reproduce; that is the triangle test's conditioning, not a
    // property of the kd-tree.)
    let mut rng = SmallRng::seed_from_u64(61);
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for i in 0..8_000u32 {
        let c = Vec3::new(rng.gen_range(0.0..1.0e6), rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0));
        let s = if i % 10 == 0 { Vec3::new(50.0, 0.5, 0.5) } else { Vec3::new(0.5, 0.5, 0.5) };
        for _ in 0..3 {
            let d = Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)) * s;
            pos.push((c + d).to_array());
        }
        idx.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let mesh = TriangleMesh::new(pos, idx);
    let params = KdTreeParams::default();
    // Compared with brute force run in this binary, not with the on-disk oracle cache:
    // the cache is shared by every build in the target directory, and a binary linked
    // against another version of the triangle test (f32 vs f64 shear) gave `t` 2 ulps
    // apart here (ray 53: 0x45c41e99 against 0x45c41e9b) while the cache key's 32-ray
    // probe did not notice the change.
    let rays = mixed_rays(&mesh, 12_000, 63);
    let brute = dynray_accel::Brute::build(&mesh).unwrap();
    let t = KdTree::build_with(&mesh, &params).unwrap();
    let r = KdTreeRopes::build_with(&mesh, &params).unwrap();
    t.validate(&mesh).unwrap();
    r.validate(&mesh).unwrap();
    for (i, ray) in rays.iter().enumerate() {
        let want = brute.intersect(ray);
        for a in [&t as &dyn Accel, &r] {
            let got = a.intersect(ray);
            let same = got.same_as(&want) && got.u.to_bits() == want.u.to_bits() && got.v.to_bits() == want.v.to_bits();
            assert!(same, "{} ray {i} {ray:?}: got {got:?}, brute {want:?}", a.name());
            assert_eq!(a.occluded(ray), want.is_hit(), "{} ray {i} {ray:?} occluded", a.name());
        }
    }
    assert_bounded(&t, mesh.triangle_count(), &params, "aspect 1e6");
}

#[test]
fn coordinates_near_f32_max_build_and_match() {
    // Areas and extents overflow to infinity here; the build must neither panic nor spin,
    // and the traversals must still agree with brute force.
    let mut rng = SmallRng::seed_from_u64(91);
    let mut mesh = flat_grid(10, -5.0, 0.0);
    mesh.positions.iter_mut().for_each(|p| *p = [p[0] * 2.0e37, p[1] * 2.0e37, rng.gen_range(-1.0e38..1.0e38)]);
    let rays: Vec<Ray> = (0..4_000)
        .map(|i| {
            let o = Vec3::new(rng.gen_range(-1.0e38..1.0e38), rng.gen_range(-1.0e38..1.0e38), 3.0e38);
            let target = Vec3::new(rng.gen_range(-1.0e38..1.0e38), rng.gen_range(-1.0e38..1.0e38), 0.0);
            let mut d = target * 0.5 - o * 0.5;
            if i % 5 == 0 {
                d.x = 0.0;
            }
            Ray::new(o, d)
        })
        .collect();
    for (name, params) in KdTreeParams::presets() {
        check_both(&mesh, &params, &rays, &format!("huge/{name}"));
    }
}

#[test]
fn rays_in_split_planes_match_brute_force() {
    let mesh = bunny();
    let t = KdTree::build(&mesh).unwrap();
    let b = mesh.bounds();
    let mut rng = SmallRng::seed_from_u64(71);
    let splits: Vec<(usize, f32)> = t.nodes().iter().filter(|n| !n.is_leaf()).map(|n| (n.axis(), n.split())).collect();
    let mut rays = Vec::new();
    for k in 0..20_000 {
        let (a, p) = splits[rng.gen_range(0..splits.len())];
        let mut o = Vec3::new(
            rng.gen_range(b.min.x..=b.max.x),
            rng.gen_range(b.min.y..=b.max.y),
            rng.gen_range(b.min.z..=b.max.z),
        );
        o[a] = p;
        let mut d = Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
        match k % 4 {
            // Lying in the plane, from inside or from outside the model's box.
            0 => d[a] = 0.0,
            1 => {
                d[a] = 0.0;
                o -= d * 2.0 * b.extent().length();
            }
            // Along one axis inside the plane (two zero components).
            2 => {
                d = Vec3::ZERO;
                d[(a + 1 + k % 2) % 3] = if rng.gen() { 1.0 } else { -1.0 };
            }
            // Starting on the plane and crossing it.
            _ => {}
        }
        rays.push(Ray::new(o, d));
    }
    let ropes = KdTreeRopes::build(&mesh).unwrap();
    assert_matches_oracle(&t, &mesh, &rays, "bunny split planes");
    assert_matches_oracle(&ropes, &mesh, &rays, "bunny split planes");
}

#[test]
fn update_rebuilds_moved_geometry_and_rejects_new_topology() {
    let mut mesh = flat_grid(10, 0.0, 0.0);
    let mut t = KdTree::build(&mesh).unwrap();
    let mut r = KdTreeRopes::build(&mesh).unwrap();
    mesh.positions.iter_mut().for_each(|p| p[2] = (p[0] * 0.7).sin() + p[1] * 0.1);
    t.update(&mesh).unwrap();
    r.update(&mesh).unwrap();
    let rays = mixed_rays(&mesh, 4_000, 81);
    assert_matches_oracle(&t, &mesh, &rays, "updated grid");
    assert_matches_oracle(&r, &mesh, &rays, "updated grid");
    let other = flat_grid(3, 0.0, 0.0);
    assert!(matches!(t.update(&other), Err(BuildError::TopologyChanged { built: 200, given: 18 })));
    assert!(matches!(r.update(&other), Err(BuildError::TopologyChanged { .. })));
}

#[test]
fn bad_parameters_are_typed_errors() {
    let mesh = flat_grid(2, 0.0, 0.0);
    let cases = [
        KdTreeParams { intersection_cost: 0.0, ..Default::default() },
        KdTreeParams { traversal_cost: f32::NAN, ..Default::default() },
        KdTreeParams { empty_bonus: 1.5, ..Default::default() },
        KdTreeParams { max_depth: Some(1_000), ..Default::default() },
        KdTreeParams { max_refs_per_triangle: 0.5, ..Default::default() },
    ];
    for p in cases {
        assert!(matches!(KdTree::build_with(&mesh, &p), Err(BuildError::Param { .. })), "{p:?}");
    }
    assert!(matches!(KdTree::build(&TriangleMesh::default()), Err(BuildError::Mesh(_))));
}

#[test]
fn registry_names_both_traversals() {
    let mesh = flat_grid(4, 0.0, 0.0);
    for name in ["kdtree", "kdtree-ropes"] {
        let kind: AccelKind = name.parse().unwrap();
        assert_eq!(kind.build(&mesh).unwrap().name(), name);
    }
}
