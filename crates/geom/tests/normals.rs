//! Smooth vertex normals (`SmoothNormals`): hard edges stay hard, smooth surfaces get
//! their true normals, the angle weighting is the one of Thürmer & Wüthrich, seams weld,
//! degenerate input gives no NaN, and triangles keep their positions bit for bit.

use dynray_geom::{MeshError, SmoothNormals, TriangleMesh, Vec3};
use rand::{Rng, SeedableRng};

fn smooth(mesh: &TriangleMesh, crease_deg: f32) -> (SmoothNormals, TriangleMesh) {
    let s = SmoothNormals::new(mesh, crease_deg).expect("valid mesh");
    let mut out = mesh.clone();
    s.apply(&mut out).expect("same mesh");
    (s, out)
}

/// The normal at corner `k` of triangle `t`.
fn corner_normal(m: &TriangleMesh, t: usize, k: usize) -> Vec3 {
    Vec3::from_array(m.normals.as_ref().expect("normals")[m.indices[t][k] as usize])
}

fn face_normal(m: &TriangleMesh, t: usize) -> Vec3 {
    let tri = m.triangle(t);
    (tri.p1 - tri.p0).cross(tri.p2 - tri.p0).normalize()
}

/// Angle between two vectors, accurate near 0 (where `acos` of an `f32` dot is not).
fn angle_deg(a: Vec3, b: Vec3) -> f32 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// What every output must keep: the triangles, in order, with their positions' bits.
#[track_caller]
fn assert_same_triangles(before: &TriangleMesh, after: &TriangleMesh) {
    assert_eq!(after.triangle_count(), before.triangle_count());
    for t in 0..before.triangle_count() {
        for k in 0..3 {
            let (a, b) =
                (before.positions[before.indices[t][k] as usize], after.positions[after.indices[t][k] as usize]);
            assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "triangle {t} corner {k}");
        }
    }
    assert_eq!(after.validate(), Ok(()));
}

/// A unit cube with 8 shared vertices and no normals, wound outwards.
fn cube() -> TriangleMesh {
    let p = (0..8).map(|i| [(i & 1) as f32, (i >> 1 & 1) as f32, (i >> 2 & 1) as f32]).collect();
    let quads: [[u32; 4]; 6] = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let indices = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    TriangleMesh::new(p, indices)
}

/// A lat-long unit sphere without normals: `bands` latitude bands, `segments` longitude
/// segments, single-vertex poles. With `seam`, the first column of vertices is repeated
/// (same position bits, new indices) at the end, as loaders of uv-mapped meshes do.
fn sphere(bands: u32, segments: u32, seam: bool) -> TriangleMesh {
    let cols = segments + seam as u32;
    let mut p = vec![[0.0f32, 1.0, 0.0]];
    for b in 1..bands {
        let th = std::f64::consts::PI * b as f64 / bands as f64;
        for s in 0..cols {
            let ph = std::f64::consts::TAU * (s % segments) as f64 / segments as f64;
            p.push([(th.sin() * ph.cos()) as f32, th.cos() as f32, (th.sin() * ph.sin()) as f32]);
        }
    }
    p.push([0.0, -1.0, 0.0]);
    let south = p.len() as u32 - 1;
    let at = |b: u32, s: u32| 1 + (b - 1) * cols + if seam { s } else { s % segments };
    let mut idx = Vec::new();
    for s in 0..segments {
        // Outwards: counter-clockwise seen from outside (y up, longitude towards +z).
        idx.push([0, at(1, s + 1), at(1, s)]);
        for b in 1..bands - 1 {
            idx.push([at(b, s), at(b, s + 1), at(b + 1, s + 1)]);
            idx.push([at(b, s), at(b + 1, s + 1), at(b + 1, s)]);
        }
        idx.push([south, at(bands - 1, s), at(bands - 1, s + 1)]);
    }
    TriangleMesh::new(p, idx)
}

#[test]
fn cube_edges_stay_hard_at_the_default_crease() {
    let cube = cube();
    for t in 0..12 {
        assert!(face_normal(&cube, t).dot(Vec3::from_array(cube.positions[cube.indices[t][0] as usize]) - 0.5) > 0.0);
    }
    let (s, out) = smooth(&cube, 60.0);
    assert_same_triangles(&cube, &out);
    for t in 0..12 {
        for k in 0..3 {
            assert_eq!(corner_normal(&out, t, k), face_normal(&cube, t), "triangle {t} corner {k}");
        }
    }
    // Each corner of the cube meets three faces: 3 vertices where there was 1.
    assert_eq!(s.vertex_count(), 24);
    assert_eq!(s.split_count(), 16);
    // Just below 90° the same; at 90° and above the faces meet within the crease.
    assert_eq!(SmoothNormals::new(&cube, 89.9).unwrap().split_count(), 16);
}

#[test]
fn crease_180_smooths_the_cube_into_corner_diagonals() {
    let cube = cube();
    let (s, out) = smooth(&cube, 180.0);
    assert_eq!(s.split_count(), 0);
    // Each face meets a cube corner with 90° in all (one right-angled corner, or two
    // 45° ones): equal weights, so the normal is the diagonal.
    for (v, n) in out.normals.as_ref().unwrap().iter().enumerate() {
        let want = (Vec3::from_array(cube.positions[v]) - 0.5).normalize();
        assert!(angle_deg(Vec3::from_array(*n), want) < 1e-3, "vertex {v}: {n:?}, want {want}");
    }
}

#[test]
fn crease_0_is_flat_shading() {
    let cube = cube();
    let (_, out) = smooth(&cube, 0.0);
    for t in 0..12 {
        for k in 0..3 {
            assert!(angle_deg(corner_normal(&out, t, k), face_normal(&cube, t)) < 1e-4);
        }
    }
    let sphere = sphere(8, 16, false);
    let (s, out) = smooth(&sphere, 0.0);
    assert!(s.split_count() > 0);
    for t in 0..sphere.triangle_count() {
        for k in 0..3 {
            assert!(angle_deg(corner_normal(&out, t, k), face_normal(&sphere, t)) < 1e-3, "triangle {t}");
        }
    }
}

#[test]
fn fine_sphere_gets_radial_normals() {
    let mesh = sphere(48, 96, false);
    let (s, out) = smooth(&mesh, 60.0);
    assert_eq!(s.split_count(), 0, "a smooth surface is not split");
    assert_same_triangles(&mesh, &out);
    let normals = out.normals.as_ref().unwrap();
    let worst = normals
        .iter()
        .zip(&out.positions)
        .map(|(n, p)| angle_deg(Vec3::from_array(*n), Vec3::from_array(*p).normalize()))
        .fold(0.0f32, f32::max);
    // The face normals themselves stray up to half a band (1.9°) from the radial
    // direction at their corners; the average cancels that to a small fraction (0.039°
    // worst, next to the poles).
    assert!(worst < 0.1, "worst generated normal is {worst}° from radial");
}

#[test]
fn seam_duplicates_are_welded_and_get_identical_normals() {
    let plain = sphere(16, 32, false);
    let seamed = sphere(16, 32, true);
    assert_eq!(seamed.vertex_count(), plain.vertex_count() + 15, "one extra column of 15 vertices");
    let (s, out) = smooth(&seamed, 60.0);
    assert_eq!(s.split_count(), 0);
    assert_same_triangles(&seamed, &out);
    let (_, want) = smooth(&plain, 60.0);
    let (n, w) = (out.normals.as_ref().unwrap(), want.normals.as_ref().unwrap());
    // Corner for corner, the seamed sphere shades as the closed one: across the seam too.
    for t in 0..plain.triangle_count() {
        for k in 0..3 {
            let (a, b) = (n[out.indices[t][k] as usize], w[want.indices[t][k] as usize]);
            assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "triangle {t} corner {k}");
        }
    }
}

#[test]
fn faces_are_weighted_by_their_corner_angle() {
    // Two faces around the origin O, 26.6° apart (within the crease):
    //   A = O, (1,0,0), (0,1,0):     normal (0,0,1),         angle at O = 90° = π/2
    //   B = O, (0,1,0), (-1,1,0.5):  normal (0.5,0,1)/√1.25, angle at O = acos(1/1.5)
    // By hand: acos(2/3) = 0.8410686706, /√1.25 = 0.7522747202, so the sum is
    //   (0.5 × 0.7522747202, 0, π/2 + 0.7522747202) = (0.3761373601, 0, 2.3230710470),
    // of length 2.3533255, giving (0.1598327, 0, 0.9871441).
    let mesh = TriangleMesh::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 1.0, 0.5]],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    let (s, out) = smooth(&mesh, 60.0);
    assert_eq!(s.split_count(), 0);
    let n = Vec3::from_array(out.normals.as_ref().unwrap()[0]);
    let want = Vec3::new(0.1598327, 0.0, 0.9871441);
    assert!((n - want).abs().max_element() < 2e-6, "{n} != {want}");
    // Not the plain mean of the two normals (0.2298, 0, 0.9732), nor area weighting.
    let mean = (Vec3::Z + Vec3::new(0.5, 0.0, 1.0).normalize()).normalize();
    assert!(angle_deg(n, mean) > 3.0);

    // Splitting A into a fan of two triangles does not change the weights.
    let fan = TriangleMesh::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 1.0, 0.5], [1.0, 1.0, 0.0]],
        vec![[0, 1, 4], [0, 4, 2], [0, 2, 3]],
    );
    let (_, out) = smooth(&fan, 60.0);
    let n = Vec3::from_array(out.normals.as_ref().unwrap()[0]);
    assert!((n - want).abs().max_element() < 2e-6, "fan: {n} != {want}");
}

#[test]
fn a_face_beyond_the_crease_is_left_out_and_its_corner_split() {
    // Three faces around O: A and B as above, C folded 80° down from A along the x axis.
    let c = [1.0, -(80f32.to_radians().cos()), 80f32.to_radians().sin()];
    let mesh = TriangleMesh::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 1.0, 0.5], c],
        vec![[0, 1, 2], [0, 2, 3], [0, 4, 1]],
    );
    let (s, out) = smooth(&mesh, 60.0);
    assert_same_triangles(&mesh, &out);
    // O splits in two: A and B share the smooth normal; C gets its own. Vertex 1 (on the
    // crease between A and C) splits too.
    assert_eq!(s.split_count(), 2);
    let (na, nb, nc) = (corner_normal(&out, 0, 0), corner_normal(&out, 1, 0), corner_normal(&out, 2, 0));
    assert_eq!(na, nb);
    assert!((na - Vec3::new(0.1598327, 0.0, 0.9871441)).abs().max_element() < 2e-6, "{na}");
    assert!(angle_deg(nc, face_normal(&mesh, 2)) < 1e-4, "{nc}");
    // A 100° crease takes C in.
    assert_eq!(SmoothNormals::new(&mesh, 100.0).unwrap().split_count(), 0);
}

#[test]
fn degenerate_triangles_give_no_nan() {
    let mesh = TriangleMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],  // collinear with 0 and 1
            [5.0, 5.0, 5.0],  // only in zero-area triangles
            [1e30, 0.0, 0.0], // huge but finite
            [-1e30, 1e30, 0.0],
            [-0.0, 0.0, 0.0], // the origin again (welded with vertex 0)
        ],
        vec![
            [0, 1, 2],
            [0, 1, 3], // collinear
            [4, 4, 4], // one point
            [1, 1, 2], // repeated index
            [0, 5, 6], // huge: its cross product overflows f32, not f64
            [7, 0, 1], // two corners at one position
        ],
    );
    for crease in [0.0, 60.0, 180.0, f32::NAN, -5.0, 1e9] {
        let (_, out) = smooth(&mesh, crease);
        assert_same_triangles(&mesh, &out);
        for (v, n) in out.normals.as_ref().unwrap().iter().enumerate() {
            let len = Vec3::from_array(*n).length();
            assert!(n.iter().all(|c| c.is_finite()), "crease {crease}: vertex {v} normal {n:?}");
            assert!(len == 0.0 || (len - 1.0).abs() < 1e-6, "crease {crease}: vertex {v} |n| = {len}");
        }
        let n = out.normals.as_ref().unwrap();
        // Vertex 4 touches no face with an area: zero, which shading reads as geometric.
        assert_eq!(n[out.indices[2][0] as usize], [0.0; 3]);
        // The real triangle is shaded with its own normal where nothing else counts.
        assert_eq!(n[out.indices[0][2] as usize], [0.0, 0.0, 1.0], "crease {crease}");
    }
    // A mesh of nothing but a point.
    let point = TriangleMesh::new(vec![[1.0, 2.0, 3.0]], vec![[0, 0, 0]]);
    assert_eq!(smooth(&point, 60.0).1.normals, Some(vec![[0.0; 3]]));
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let mesh = TriangleMesh::new(vec![[0.0; 3]; 3], vec![[0, 1, 3]]);
    assert_eq!(
        SmoothNormals::new(&mesh, 60.0).unwrap_err(),
        MeshError::IndexOutOfRange { triangle: 0, index: 3, vertices: 3 }
    );
    let s = SmoothNormals::new(&cube(), 60.0).unwrap();
    let mut normals = Vec::new();
    assert_eq!(
        s.compute(&[[0.0; 3]; 7], &mut normals),
        Err(MeshError::AttributeCount { what: "positions", got: 7, vertices: 8 })
    );
    let mut other = TriangleMesh::new(vec![[0.0; 3]; 9], vec![[0, 1, 2]]);
    let before = other.clone();
    assert_eq!(s.apply(&mut other), Err(MeshError::AttributeCount { what: "positions", got: 9, vertices: 8 }));
    assert_eq!(other, before, "a failed apply changes nothing");
    let mut bad_uvs = cube();
    bad_uvs.uvs = Some(vec![[0.0; 2]; 3]);
    assert!(s.apply(&mut bad_uvs).is_err());
    assert_eq!(bad_uvs.normals, None);
}

#[test]
fn unused_vertices_are_kept() {
    let mut mesh = cube();
    mesh.positions.push([9.0, 9.0, 9.0]);
    mesh.uvs = Some((0..9).map(|i| [i as f32, 0.0]).collect());
    let (s, out) = smooth(&mesh, 60.0);
    assert_eq!(out.positions[8], [9.0, 9.0, 9.0]);
    assert_eq!(out.normals.as_ref().unwrap()[8], [0.0; 3]);
    assert_eq!(s.vertex_count(), 25);
    // Uvs follow their vertices into the splits.
    let uvs = out.uvs.as_ref().unwrap();
    for t in 0..12 {
        for k in 0..3 {
            assert_eq!(uvs[out.indices[t][k] as usize][0], mesh.indices[t][k] as f32);
        }
    }
}

#[test]
fn compute_on_deformed_positions_keeps_the_topology() {
    let mesh = sphere(12, 24, true);
    let s = SmoothNormals::new(&mesh, 60.0).unwrap();
    // Squash it into an ellipsoid and move it: the normals are the ellipsoid's, from the
    // same vertices, without rebuilding.
    let moved: Vec<[f32; 3]> = mesh.positions.iter().map(|p| [p[0] * 1.5 + 1.0, p[1] * 0.75, p[2] - 3.0]).collect();
    let mut normals = Vec::new();
    s.compute(&moved, &mut normals).unwrap();
    assert_eq!(normals.len(), s.vertex_count());
    let (again, rebuilt) = smooth(&TriangleMesh::new(moved.clone(), mesh.indices.clone()), 60.0);
    assert_eq!(again.split_count(), s.split_count(), "the ellipsoid is smooth too");
    for t in 0..mesh.triangle_count() {
        for k in 0..3 {
            let got = Vec3::from_array(normals[s.indices()[t][k] as usize]);
            let want = corner_normal(&rebuilt, t, k);
            assert!(angle_deg(got, want) < 1e-4, "triangle {t} corner {k}: {got} != {want}");
        }
    }
    // On the ellipsoid, the normal at (1.5x+1, 0.75y, z-3) is along (x/1.5, y/0.75, z).
    for (o, n) in normals.iter().enumerate() {
        let v = s.indices().iter().flatten().position(|&i| i as usize == o).map(|c| mesh.indices[c / 3][c % 3]);
        let p = Vec3::from_array(mesh.positions[v.unwrap() as usize]);
        let want = Vec3::new(p.x / 1.5, p.y / 0.75, p.z).normalize();
        assert!(angle_deg(Vec3::from_array(*n), want) < 4.0, "vertex {o}");
    }
}

#[test]
fn random_meshes_keep_their_triangles_and_get_unit_or_zero_normals() {
    let mut rng = rand::rngs::StdRng::seed_from_u64(17);
    for round in 0..50 {
        let nv = rng.gen_range(1..40);
        // Few distinct coordinates, so that positions repeat and weld.
        let positions: Vec<[f32; 3]> = (0..nv).map(|_| [(); 3].map(|_| rng.gen_range(-2..=2) as f32 * 0.5)).collect();
        let indices: Vec<[u32; 3]> =
            (0..rng.gen_range(1..80)).map(|_| [(); 3].map(|_| rng.gen_range(0..nv as u32))).collect();
        let mesh = TriangleMesh::new(positions, indices);
        for crease in [0.0, 30.0, 60.0, 120.0, 180.0] {
            let (s, out) = smooth(&mesh, crease);
            assert_same_triangles(&mesh, &out);
            assert_eq!(out.vertex_count(), nv + s.split_count());
            for n in out.normals.as_ref().unwrap() {
                let len = Vec3::from_array(*n).length();
                assert!(len == 0.0 || (len - 1.0).abs() < 1e-6, "round {round} crease {crease}: {n:?}");
            }
            // Below 90°, a corner averages only faces within 90° of its own: its normal
            // faces the triangle's side.
            for t in (0..mesh.triangle_count()).filter(|_| crease < 90.0) {
                let tri = mesh.triangle(t);
                let ng = (tri.p1 - tri.p0).cross(tri.p2 - tri.p0);
                if ng.length() > 1e-6 {
                    for k in 0..3 {
                        let d = corner_normal(&out, t, k).dot(ng);
                        assert!(d > 0.0, "round {round} crease {crease}: triangle {t} corner {k}: {d}");
                    }
                }
            }
        }
    }
}
