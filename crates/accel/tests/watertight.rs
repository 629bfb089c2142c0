//! Watertightness: from inside a closed mesh every ray must hit it, including rays aimed
//! exactly at shared vertices and edges. Checked for every registered structure.

use dynray_accel::AccelKind;
use dynray_geom::{Ray, TriangleMesh, Vec3};
use dynray_scene::shapes::icosphere;

/// Seed 003's unit cube: 8 shared vertices, 12 triangles.
fn unit_cube() -> TriangleMesh {
    let p = (0..8).map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32]).collect();
    let idx = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    TriangleMesh::new(p, idx)
}

/// Rays from `origins` to every vertex and every edge midpoint of `mesh`.
fn rays_at_vertices_and_edges(mesh: &TriangleMesh, origins: &[Vec3]) -> Vec<Ray> {
    let mut targets: Vec<Vec3> = mesh.positions.iter().map(|p| Vec3::from_array(*p)).collect();
    for t in &mesh.indices {
        for k in 0..3 {
            targets.push((mesh.position(t[k]) + mesh.position(t[(k + 1) % 3])) * 0.5);
        }
    }
    origins.iter().flat_map(|&o| targets.iter().map(move |&t| Ray::new(o, t - o))).collect()
}

fn assert_no_leaks(label: &str, mesh: &TriangleMesh, origins: &[Vec3]) {
    let rays = rays_at_vertices_and_edges(mesh, origins);
    for &kind in AccelKind::ALL {
        let accel = kind.build(mesh).unwrap();
        let leaks: Vec<&Ray> = rays.iter().filter(|r| !accel.intersect(r).is_hit()).collect();
        assert!(
            leaks.is_empty(),
            "{kind} on {label}: {} of {} rays leak, e.g. {:?}",
            leaks.len(),
            rays.len(),
            &leaks[..leaks.len().min(3)]
        );
        let occ_leaks = rays.iter().filter(|r| !accel.occluded(r)).count();
        assert_eq!(occ_leaks, 0, "{kind} on {label}: occluded() misses {occ_leaks} rays");
    }
}

#[test]
fn unit_cube_has_no_leaks_at_vertices_and_edges() {
    let origins = [Vec3::splat(0.5), Vec3::new(0.1, 0.7, 0.3), Vec3::new(0.99, 0.01, 0.5), Vec3::new(0.25, 0.25, 0.25)];
    assert_no_leaks("unit cube", &unit_cube(), &origins);
}

#[test]
fn icosphere_has_no_leaks_at_vertices_and_edges() {
    let mesh = icosphere(Vec3::new(0.3, -1.2, 2.0), 1.7, 3);
    let c = Vec3::new(0.3, -1.2, 2.0);
    let origins = [c, c + Vec3::new(0.4, -0.3, 0.2), c + Vec3::new(-1.1, 0.5, 0.7) * 0.9];
    assert_no_leaks("icosphere", &mesh, &origins);
}
