//! The BIH's own checks (the standard sets, every preset and update after a deformation
//! are in oracle.rs, shared by every structure): seed 000's leaf-size sweep, refit of
//! both node layouts (with and without one-child nodes), bad parameters, a build
//! independent of the thread count, degenerate scenes.

mod support;

use dynray_accel::StructureParams;
use dynray_accel::{Accel, Bih, BihParams, BuildError};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use support::*;

fn build(mesh: &TriangleMesh, p: &BihParams) -> Bih {
    let bih = Bih::build(mesh, p).expect("build");
    bih.validate(mesh).expect("valid tree");
    bih
}

#[test]
fn bunny_leaf_size_sweep_of_the_seed() {
    // Seed 000 swept MaxPrims over 1, 5, 10, 20, 30; each must stay exact.
    let mesh = bunny();
    let rays = random_rays(&mesh, 20_000, 11);
    for (max_prims, empty_cut) in [1, 5, 10, 20, 30].into_iter().flat_map(|m| [(m, None), (m, Some(0.25))]) {
        let bih = build(&mesh, &BihParams { max_prims, empty_cut, ..BihParams::default() });
        let s = bih.stats();
        assert_eq!(s.primitive_refs, mesh.triangle_count());
        // Only nodes whose triangles' centres cannot be separated may exceed max_prims.
        let big: usize = s.leaf_sizes.iter().skip(max_prims as usize + 1).sum();
        assert!(big * 1000 <= s.leaves, "max_prims {max_prims}: {big} oversized leaves {:?}", s.leaf_sizes);
        assert_matches_oracle(&bih, &mesh, &rays, &format!("bunny max_prims={max_prims} empty_cut={empty_cut:?}"));
    }
}

#[test]
fn refit_after_wave_matches_brute_on_the_deformed_mesh() {
    let mesh = bunny();
    // Default has one-child (empty-cut) nodes, seed_000 has only two-child nodes.
    for (name, p) in [("default", BihParams::default()), ("seed_000", BihParams::seed_000())] {
        let mut bih = build(&mesh, &p);
        let nodes_before = bih.stats().nodes;
        for (step, amp) in [(0, 0.01f32), (1, 0.05), (2, 0.2)] {
            let moved = wave(&mesh, amp, step as f32);
            bih.update(&moved).expect("refit");
            bih.validate(&moved).expect("refitted tree is valid");
            assert_eq!(bih.stats().nodes, nodes_before, "refit keeps the topology");
            let mut rays = random_rays(&moved, 4_000, 100 + step);
            rays.extend(adversarial_rays(&moved, 1_000, 200 + step));
            assert_matches_oracle(&bih, &moved, &rays, &format!("bunny {name} refit wave {amp}"));
        }
    }
}

#[test]
fn bad_params_are_errors() {
    let mesh = bunny();
    for p in [
        BihParams { max_prims: 0, ..BihParams::default() },
        BihParams { max_depth: 0, ..BihParams::default() },
        BihParams { max_depth: 65, ..BihParams::default() },
        BihParams { shrink: Some(1.0), ..BihParams::default() },
        BihParams { shrink: Some(f32::NAN), ..BihParams::default() },
        BihParams { empty_cut: Some(0.0), ..BihParams::default() },
        BihParams { empty_cut: Some(1.0), ..BihParams::default() },
    ] {
        assert!(matches!(Bih::build(&mesh, &p), Err(BuildError::Param { .. })), "{p:?}");
    }
}

#[test]
fn build_is_identical_with_one_and_two_threads() {
    let mesh = dragon_res2();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| Bih::build(&mesh, &BihParams::default()).unwrap())
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(bytemuck::cast_slice::<_, u8>(a.nodes()), bytemuck::cast_slice::<_, u8>(b.nodes()));
    assert_eq!(a.prim_ids(), b.prim_ids());
}

// ---- degenerate scenes: bounded build, exact answers ----

fn check_degenerate(mesh: &TriangleMesh, rays: &[Ray], label: &str) -> Bih {
    for (name, p) in BihParams::presets() {
        let bih = build(mesh, &p);
        assert_matches_oracle(&bih, mesh, rays, &format!("{label} ({name})"));
    }
    build(mesh, &BihParams::default())
}

#[test]
fn coplanar_triangles() {
    let mesh = degenerate::coplanar_sheet();
    let mut rays = random_rays(&mesh, 20_000, 21);
    rays.extend(adversarial_rays(&mesh, 5_000, 22));
    check_degenerate(&mesh, &rays, "coplanar sheet");
}

#[test]
fn all_triangles_in_one_point() {
    let p = [1.5f32, -2.0, 3.25];
    let mesh = TriangleMesh::new(vec![p; 3], vec![[0, 1, 2]; 10_000]);
    let rays = degenerate::rays_at(Vec3::from(p), Vec3::from(p), 2_000, 31);
    let bih = check_degenerate(&mesh, &rays, "point");
    assert_eq!(bih.stats().nodes, 1, "no split can separate equal centres");
}

#[test]
fn single_triangle() {
    let mesh = TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]);
    let mut rays = random_rays(&mesh, 5_000, 41);
    rays.extend(adversarial_rays(&mesh, 2_000, 42));
    let bih = check_degenerate(&mesh, &rays, "single triangle");
    assert_eq!(bih.stats().nodes, 1);
}

#[test]
fn hundred_thousand_identical_triangles() {
    // Every hit ties on `t`: the lowest index (0) must win, in one bounded leaf.
    let mesh = TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.2, 0.0], [0.3, 1.0, 0.4]], vec![[0, 1, 2]; 100_000]);
    let rays = degenerate::rays_at(Vec3::ZERO, Vec3::ONE, 300, 51);
    let bih = build(&mesh, &BihParams::default());
    assert_eq!(bih.stats().nodes, 1, "identical triangles stay in one leaf");
    assert_eq!(bih.memory_bytes(), 16 + 100_000 * (36 + 4));
    assert_matches_oracle(&bih, &mesh, &rays, "100k identical triangles");
}

#[test]
fn million_to_one_aspect_ratio() {
    let mesh = degenerate::million_to_one_strip();
    let mut rays = random_rays(&mesh, 20_000, 62);
    rays.extend(adversarial_rays(&mesh, 5_000, 63));
    let bih = check_degenerate(&mesh, &rays, "1e6:1 strip");
    let s = bih.stats();
    assert!(s.nodes < 4 * mesh.triangle_count(), "{} nodes", s.nodes);
}
