//! The uniform grid's own checks (the standard sets, every preset and update after a
//! deformation are in oracle.rs, shared by every structure): rays along cell faces,
//! edges and corners, bad parameters, a thread-independent build, degenerate scenes.

mod support;

use dynray_accel::StructureParams;
use dynray_accel::{Accel, BuildError, Grid, GridParams};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use rand::{rngs::SmallRng, Rng, SeedableRng};
use support::*;

fn build(mesh: &TriangleMesh, p: &GridParams) -> Grid {
    let g = Grid::build(mesh, p).expect("build");
    g.validate(mesh).expect("valid grid");
    g
}

#[test]
fn rays_along_cell_faces_edges_and_corners() {
    // Rays built from the grid's own planes: along faces, through edges and corners,
    // where the DDA's crossings tie; the tie handling must not skip a cell.
    let mesh = bunny();
    let g = build(&mesh, &GridParams::default());
    let s = *g.shape();
    let mut rng = SmallRng::seed_from_u64(9);
    let plane = |rng: &mut SmallRng, a: usize| s.plane(a, rng.gen_range(0..=s.res[a]));
    let mut rays = Vec::new();
    for i in 0..20_000 {
        let corner = Vec3::new(plane(&mut rng, 0), plane(&mut rng, 1), plane(&mut rng, 2));
        let other = Vec3::new(plane(&mut rng, 0), plane(&mut rng, 1), plane(&mut rng, 2));
        rays.push(match i % 4 {
            // Corner to corner: crosses many edges and corners exactly (up to rounding).
            0 => Ray::new(corner, other - corner),
            // Along a face: one direction component zero, origin on that face.
            1 => Ray::new(corner, Vec3::new(other.x - corner.x, other.y - corner.y, 0.0)),
            // Along an edge.
            2 => Ray::new(corner, Vec3::new(0.0, 0.0, if rng.gen() { 1.0 } else { -1.0 })),
            // Diagonal through a corner from outside.
            _ => {
                let d = Vec3::new(1.0, 1.0, 1.0) * (s.cell.max_element() + 1e-3);
                Ray::new(corner - d * 1000.0, d)
            }
        });
    }
    assert_matches_oracle(&g, &mesh, &rays, "bunny grid planes");
}

#[test]
fn bad_params_are_errors() {
    let mesh = bunny();
    for p in [
        GridParams { density: 0.0, ..GridParams::default() },
        GridParams { density: f32::INFINITY, ..GridParams::default() },
        GridParams { max_cells: 0, ..GridParams::default() },
        GridParams { max_refs_per_triangle: 0, ..GridParams::default() },
    ] {
        assert!(matches!(Grid::build(&mesh, &p), Err(BuildError::Param { .. })), "{p:?}");
    }
}

#[test]
fn build_is_identical_with_one_and_two_threads() {
    let mesh = bunny();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| Grid::build(&mesh, &GridParams::default()).unwrap())
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.shape(), b.shape());
    let cells = a.shape().cells();
    assert!((0..cells).all(|c| a.cell_refs(c) == b.cell_refs(c)));
}

// ---- degenerate scenes: bounded build, exact answers ----

fn check_degenerate(mesh: &TriangleMesh, rays: &[Ray], label: &str) -> Grid {
    for (name, p) in GridParams::presets() {
        let g = build(mesh, &p);
        assert_matches_oracle(&g, mesh, rays, &format!("{label} ({name})"));
    }
    build(mesh, &GridParams::default())
}

#[test]
fn coplanar_triangles() {
    let mesh = degenerate::coplanar_sheet();
    let mut rays = random_rays(&mesh, 20_000, 21);
    rays.extend(adversarial_rays(&mesh, 5_000, 22));
    let g = check_degenerate(&mesh, &rays, "coplanar sheet");
    assert_eq!(g.shape().res[1], 1, "a flat scene has one cell across");
}

#[test]
fn all_triangles_in_one_point() {
    let p = [1.5f32, -2.0, 3.25];
    let mesh = TriangleMesh::new(vec![p; 3], vec![[0, 1, 2]; 10_000]);
    let rays = degenerate::rays_at(Vec3::from(p), Vec3::from(p), 2_000, 31);
    let g = check_degenerate(&mesh, &rays, "point");
    assert_eq!(g.shape().cells(), 1);
}

#[test]
fn single_triangle() {
    let mesh = TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]);
    let mut rays = random_rays(&mesh, 5_000, 41);
    rays.extend(adversarial_rays(&mesh, 2_000, 42));
    check_degenerate(&mesh, &rays, "single triangle");
}

#[test]
fn hundred_thousand_identical_triangles() {
    // A fine grid would put every copy in thousands of cells: the reference budget
    // must coarsen it so memory stays bounded.
    let n = 100_000;
    let mesh = TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.2, 0.0], [0.3, 1.0, 0.4]], vec![[0, 1, 2]; n]);
    let rays = degenerate::rays_at(Vec3::ZERO, Vec3::ONE, 300, 51);
    let p = GridParams::default();
    let g = build(&mesh, &p);
    assert!(g.stats().primitive_refs <= p.max_refs_per_triangle as usize * n, "{:?}", g.stats());
    assert_matches_oracle(&g, &mesh, &rays, "100k identical triangles");
}

#[test]
fn million_to_one_aspect_ratio() {
    let mesh = degenerate::million_to_one_strip();
    let mut rays = random_rays(&mesh, 20_000, 62);
    rays.extend(adversarial_rays(&mesh, 5_000, 63));
    let g = check_degenerate(&mesh, &rays, "1e6:1 strip");
    assert!(g.shape().cells() <= GridParams::default().max_cells as usize);
}
