//! The octree (seed 002) against brute force: both traversals (neighbour walk and top-down
//! descent), balanced and unbalanced, on the standard bunny and dragon sets, on every
//! preset, and on degenerate scenes; plus the 2:1 balance invariant.

mod support;

use dynray_accel::octree::{Octree, OctreeDescent, OctreeParams};
use dynray_accel::StructureParams;
use dynray_accel::{Accel, AccelKind};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use support::*;

fn both(mesh: &TriangleMesh, params: &OctreeParams) -> (Octree, OctreeDescent) {
    let walk = Octree::build(mesh, params).expect("build");
    walk.validate(mesh).expect("valid octree");
    let descent = OctreeDescent::build(mesh, params).expect("build");
    (walk, descent)
}

fn check_both(mesh: &TriangleMesh, params: &OctreeParams, rays: &[Ray], label: &str) {
    let (walk, descent) = both(mesh, params);
    assert_matches_oracle(&walk, mesh, rays, label);
    assert_matches_oracle(&descent, mesh, rays, label);
}

#[test]
fn bunny_unbalanced_matches_brute() {
    let mesh = bunny();
    let (walk, _) = both(&mesh, &OctreeParams::unbalanced());
    // The unbalanced tree must really exercise the point-location crossing.
    let locate = walk.stats().extra.iter().find(|(k, _)| k == "faces crossed by point location").unwrap().1.clone();
    assert!(locate.parse::<usize>().unwrap() > 0, "no LOCATE faces in the unbalanced bunny");
    // Its oracle check on the standard set is oracle.rs's `unbalanced` preset; here a
    // sample through both traversals.
    check_both(&mesh, &OctreeParams::unbalanced(), &random_rays(&mesh, 6_000, 24), "bunny unbalanced");
}

#[test]
fn a_deep_tree_with_tiny_leaves_matches_brute_on_bunny_sample() {
    // The presets are checked in oracle.rs.
    let mesh = bunny();
    let mut rays = random_rays(&mesh, 6_000, 21);
    rays.extend(adversarial_rays(&mesh, 2_000, 22));
    // Small leaves and deep trees stress the walk hardest.
    let deep = OctreeParams { max_depth: 10, leaf_threshold: 2, balance: true };
    check_both(&mesh, &deep, &rays, "depth 10, 2 per leaf");
}

#[test]
fn balance_gives_zero_one_or_four_neighbours_per_face() {
    let mesh = bunny();
    let oct = Octree::build(&mesh, &OctreeParams::default()).unwrap();
    oct.validate(&mesh).unwrap();
    let unbalanced = Octree::build(&mesh, &OctreeParams::unbalanced()).unwrap();
    assert!(oct.leaves_added_by_balance() > 0);
    assert_eq!(unbalanced.leaves_added_by_balance(), 0);
    assert!(oct.leaf_count() > unbalanced.leaf_count());
    // Independent of validate(): read every face's count from the records.
    let rec = oct.records();
    let mut a = 0;
    let mut counts = [0usize; 16];
    while a < rec.len() {
        let nc = rec[a + 3];
        let mut links = 0;
        for f in 0..6 {
            let n = (nc >> (4 * f)) & 0xF;
            counts[n as usize] += 1;
            links += n as usize;
        }
        a += 4 + links;
    }
    assert_eq!(a, rec.len());
    for (n, &c) in counts.iter().enumerate() {
        assert!(c == 0 || matches!(n, 0 | 1 | 4), "{c} faces with {n} neighbours");
    }
    assert!(counts[4] > 0 && counts[1] > 0 && counts[0] > 0, "{counts:?}");
}

#[test]
fn registry_builds_both_names() {
    let mesh = bunny();
    for name in ["octree", "octree-descent"] {
        let kind: AccelKind = name.parse().unwrap();
        let accel = kind.build(&mesh).unwrap();
        assert_eq!(accel.name(), name);
        let s = accel.stats();
        assert!(s.memory_bytes == accel.memory_bytes() && s.leaves > 1000 && s.primitive_refs >= mesh.triangle_count());
    }
}

#[test]
fn update_rebuilds_moved_geometry() {
    let mut mesh = bunny();
    let mut oct = Octree::build(&mesh, &OctreeParams::default()).unwrap();
    for p in &mut mesh.positions {
        p[1] += 0.05;
        p[0] *= 1.5;
    }
    oct.update(&mesh).unwrap();
    oct.validate(&mesh).unwrap();
    assert_matches_oracle(&oct, &mesh, &random_rays(&mesh, 3_000, 31), "moved bunny");
    let mut fewer = mesh.clone();
    fewer.indices.pop();
    assert!(oct.update(&fewer).is_err());
}

fn grid_mesh(n: usize, f: impl Fn(f32, f32) -> [f32; 3]) -> TriangleMesh {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push(f(i as f32 / n as f32, j as f32 / n as f32));
        }
    }
    let w = (n + 1) as u32;
    for j in 0..n as u32 {
        for i in 0..n as u32 {
            let a = j * w + i;
            indices.push([a, a + 1, a + w + 1]);
            indices.push([a, a + w + 1, a + w]);
        }
    }
    TriangleMesh::new(positions, indices)
}

fn degenerate_check(mesh: &TriangleMesh, label: &str, max_refs: usize) {
    let mut rays = random_rays(mesh, 4_000, 41);
    rays.extend(adversarial_rays(mesh, 1_000, 42));
    degenerate_check_with(mesh, label, max_refs, &rays);
}

fn degenerate_check_with(mesh: &TriangleMesh, label: &str, max_refs: usize, rays: &[Ray]) {
    for (name, p) in [("balanced", OctreeParams::default()), ("unbalanced", OctreeParams::unbalanced())] {
        let (walk, descent) = both(mesh, &p);
        let s = walk.stats();
        assert!(s.primitive_refs <= max_refs, "{label} {name}: {} refs", s.primitive_refs);
        assert_matches_oracle(&walk, mesh, rays, &format!("{label} {name}"));
        assert_matches_oracle(&descent, mesh, rays, &format!("{label} {name}"));
    }
}

#[test]
fn coplanar_scene() {
    // A 60×60 grid in the plane z = 0.25, plus one in a plane that is a cell boundary.
    let mut mesh = grid_mesh(60, |u, v| [u, v, 0.25]);
    let other = grid_mesh(20, |u, v| [u, 0.5, v]);
    let base = mesh.positions.len() as u32;
    mesh.positions.extend(other.positions);
    mesh.indices.extend(other.indices.iter().map(|t| t.map(|i| i + base)));
    let n = mesh.triangle_count();
    degenerate_check(&mesh, "coplanar", 40 * n);
}

#[test]
fn all_triangles_in_one_point() {
    // The shared ray generators need a box with volume; aim rays at and through the point.
    let point_rays = |p: Vec3| -> Vec<Ray> {
        (0..2_000)
            .map(|i| {
                let a = i as f32 * 0.7;
                let d = Vec3::new(a.cos(), (a * 1.3).sin(), (a * 0.4).cos() - 0.3);
                match i % 4 {
                    0 => Ray::new(p - d, d),
                    1 => Ray::new(p, d),
                    2 => Ray::new(p + d * 1e-3 * (i as f32), -d),
                    _ => Ray::new(p + Vec3::new(0.0, 1e-3, 0.0), d),
                }
            })
            .collect()
    };
    let mesh = TriangleMesh::new(vec![[0.3, -2.0, 7.0]], vec![[0, 0, 0]; 1000]);
    degenerate_check_with(&mesh, "one point", 1000, &point_rays(Vec3::new(0.3, -2.0, 7.0)));
    let origin = TriangleMesh::new(vec![[0.0; 3]], vec![[0, 0, 0]; 10]);
    degenerate_check_with(&origin, "one point at the origin", 10, &point_rays(Vec3::ZERO));
}

#[test]
fn single_triangle() {
    let mesh = TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]], vec![[0, 1, 2]]);
    let oct = Octree::build(&mesh, &OctreeParams::default()).unwrap();
    assert_eq!(oct.leaf_count(), 1);
    degenerate_check(&mesh, "single triangle", 1);
}

#[test]
fn many_identical_triangles() {
    // 100k copies of one triangle: no split can separate them, so none is made.
    // Few rays: every one of them tests all 100k copies (brute force and octree alike).
    let mesh = TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.2, 0.0], [0.3, 1.0, 0.7]], vec![[0, 1, 2]; 100_000]);
    let mut rays = random_rays(&mesh, 150, 43);
    rays.extend(adversarial_rays(&mesh, 50, 44));
    degenerate_check_with(&mesh, "100k identical", 800_000, &rays);
}

#[test]
fn extreme_aspect_ratio_scene() {
    // A 1e6 × 1 × 1 strip of 4000 triangles: cells are cubes, so almost all are empty.
    let mesh = grid_mesh(40, |u, v| [u * 1.0e6, v, (u * 977.0).sin() * 0.5]);
    let mut m = mesh.clone();
    // And a thin sliver triangle spanning the whole length.
    let base = m.positions.len() as u32;
    m.positions.extend([[0.0, 0.5, 0.0], [1.0e6, 0.5, 0.0], [1.0e6, 0.5 + 1e-3, 0.0]]);
    m.indices.push([base, base + 1, base + 2]);
    let n = m.triangle_count();
    degenerate_check(&m, "1e6:1 strip", 200 * n);
}

#[test]
fn rays_along_leaf_planes_and_through_corners() {
    // A regular 8×8×8 lattice of small triangles whose corners lie on cell planes; rays
    // run exactly along the planes and through lattice corners (Plücker zeros).
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for z in 0..8 {
        for y in 0..8 {
            for x in 0..8 {
                let p = Vec3::new(x as f32, y as f32, z as f32) * 0.125;
                let b = positions.len() as u32;
                positions.extend([
                    p.to_array(),
                    (p + Vec3::new(0.125, 0.0, 0.0)).to_array(),
                    (p + Vec3::new(0.0, 0.125, 0.06)).to_array(),
                ]);
                indices.push([b, b + 1, b + 2]);
            }
        }
    }
    let mesh = TriangleMesh::new(positions, indices);
    let mut rays = Vec::new();
    for i in 0..=16 {
        for j in 0..=16 {
            let (a, b) = (i as f32 / 16.0, j as f32 / 16.0);
            rays.push(Ray::new(Vec3::new(-1.0, a, b), Vec3::X));
            rays.push(Ray::new(Vec3::new(a, 2.0, b), -Vec3::Y));
            rays.push(Ray::new(Vec3::new(a, b, -0.5), Vec3::Z));
            rays.push(Ray::new(Vec3::new(a, b, 0.0), Vec3::new(1.0, 1.0, 1.0)));
            rays.push(Ray::new(Vec3::new(-a, -b, -1.0), Vec3::new(1.0, 1.0, 1.0)));
            rays.push(Ray::new(Vec3::new(a, b, 0.5), Vec3::new(1.0, -1.0, 0.0)));
        }
    }
    for p in OctreeParams::presets().into_iter().map(|(_, p)| p) {
        let (walk, descent) = both(&mesh, &OctreeParams { leaf_threshold: 1, ..p });
        assert_matches_oracle(&walk, &mesh, &rays, "lattice");
        assert_matches_oracle(&descent, &mesh, &rays, "lattice");
    }
}

#[test]
fn bad_parameters_are_errors() {
    let mesh = bunny();
    assert!(Octree::build(&mesh, &OctreeParams { max_depth: 40, ..Default::default() }).is_err());
    assert!(Octree::build(&mesh, &OctreeParams { leaf_threshold: 0, ..Default::default() }).is_err());
}

#[test]
fn malformed_rays_never_panic_or_hit() {
    let mesh = bunny();
    let (walk, descent) = both(&mesh, &OctreeParams::default());
    let c = mesh.bounds().center();
    let bad = [
        Ray::new(c, Vec3::ZERO),
        Ray::new(c, Vec3::new(f32::NAN, 1.0, 0.0)),
        Ray::with_interval(c, Vec3::X, 2.0, 1.0),
        Ray::with_interval(c, Vec3::X, f32::NAN, f32::NAN),
    ];
    for r in &bad {
        for a in [&walk as &dyn Accel, &descent] {
            assert!(!a.intersect(r).is_hit() && !a.occluded(r), "{} hit on {r:?}", a.name());
        }
    }
    // Infinite components and far-away origins: any answer, but no panic or endless walk.
    for r in [
        Ray::new(c, Vec3::new(f32::INFINITY, 0.0, 0.0)),
        Ray::new(c, Vec3::new(f32::INFINITY, -f32::INFINITY, 1.0)),
        Ray::new(Vec3::splat(1e30), -Vec3::ONE),
        Ray::new(Vec3::splat(-3e38), Vec3::new(1.0, 1e-30, 1.0)),
    ] {
        let _ = (walk.intersect(&r), descent.intersect(&r), walk.occluded(&r), descent.occluded(&r));
    }
}

#[test]
fn rays_through_leaf_corners_and_edges() {
    // Aimed at the built tree's own leaf corners and edge midpoints, where the Plücker
    // signs are zero or within rounding of it, and started on them (secondary rays).
    use rand::{rngs::SmallRng, Rng, SeedableRng};
    let mesh = bunny();
    for p in [OctreeParams::default(), OctreeParams::unbalanced()] {
        let (walk, descent) = both(&mesh, &p);
        let boxes = walk.boxes();
        let mut rng = SmallRng::seed_from_u64(51);
        let b = mesh.bounds();
        let diag = b.extent().length();
        let mut rays = Vec::new();
        for i in 0..6_000 {
            let lb = boxes[rng.gen_range(0..boxes.len())];
            let pick = |rng: &mut SmallRng| {
                Vec3::new(
                    if rng.gen() { lb.min.x } else { lb.max.x },
                    if rng.gen() { lb.min.y } else { lb.max.y },
                    if rng.gen() { lb.min.z } else { lb.max.z },
                )
            };
            let corner = pick(&mut rng);
            let target = if i % 2 == 0 { corner } else { (corner + pick(&mut rng)) * 0.5 };
            let far = b.center()
                + Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)) * diag;
            match i % 3 {
                0 => rays.push(Ray::new(far, target - far)),
                1 => rays.push(Ray::new(target, far - target)),
                _ => {
                    // Axis-parallel and diagonal directions through the point.
                    let dirs = [Vec3::X, -Vec3::Y, Vec3::Z, Vec3::new(1.0, 1.0, 0.0), Vec3::new(-1.0, 1.0, -1.0)];
                    let d = dirs[rng.gen_range(0..dirs.len())];
                    rays.push(Ray::new(target - d * diag, d));
                }
            }
        }
        let label = if p.balance { "leaf corners balanced" } else { "leaf corners unbalanced" };
        assert_matches_oracle(&walk, &mesh, &rays, label);
        assert_matches_oracle(&descent, &mesh, &rays, label);
    }
}
