//! Tessellated primitives: boxes, UV spheres and icospheres. Seed 003 turns every actor
//! into triangles, so these feed the same structures as loaded meshes.

use dynray_geom::{TriangleMesh, Vec3};
use glam::{EulerRot, Mat4, Quat};

/// A box centred at `center`, with edge lengths `size`, rotated by `rotation_deg`
/// (degrees about x, then y, then z). 24 vertices with flat face normals, 12 triangles.
///
/// Each face carries the whole texture, `(0, 0)` to `(1, 1)`, upright and unmirrored
/// seen from outside: on the four side faces `v` runs up the box's `+y`; on the top its
/// `v` runs towards `-z` (the image reads as seen from above with the box's front, `+z`,
/// at the bottom) and on the bottom towards `+z`.
pub fn cuboid(center: Vec3, size: Vec3, rotation_deg: Vec3) -> TriangleMesh {
    let mut positions = Vec::with_capacity(24);
    let mut normals = Vec::with_capacity(24);
    let mut uvs = Vec::with_capacity(24);
    let mut indices = Vec::with_capacity(12);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let (u, v) = (Vec3::from(unit((axis + 1) % 3)), Vec3::from(unit((axis + 2) % 3)));
            // Order the quad counter-clockwise seen from outside.
            let (u, v) = if sign > 0.0 { (u, v) } else { (v, u) };
            // The texture's up and right on this face; right × up = n, so seen from
            // outside the image is not mirrored.
            let up = if axis == 1 { Vec3::Z * -sign } else { Vec3::Y };
            let right = up.cross(n);
            let base = positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let q = (n + u * a + v * b) * 0.5;
                positions.push(q.to_array());
                normals.push(n.to_array());
                uvs.push([q.dot(right) + 0.5, q.dot(up) + 0.5]);
            }
            indices.push([base, base + 1, base + 2]);
            indices.push([base, base + 2, base + 3]);
        }
    }
    let mut m = TriangleMesh { positions, indices, normals: Some(normals), uvs: Some(uvs) };
    let r = rotation_deg * (std::f32::consts::PI / 180.0);
    let rot = Quat::from_euler(EulerRot::ZYX, r.z, r.y, r.x);
    m.transform(&Mat4::from_scale_rotation_translation(size, rot, center));
    m
}

fn unit(axis: usize) -> [f32; 3] {
    let mut a = [0.0; 3];
    a[axis] = 1.0;
    a
}

/// A UV sphere with `stacks` latitude bands and `slices` longitude segments and smooth
/// vertex normals. Poles are single vertices, so the mesh is closed.
pub fn uv_sphere(center: Vec3, radius: f32, stacks: u32, slices: u32) -> TriangleMesh {
    let stacks = stacks.max(2);
    let slices = slices.max(3);
    let mut positions = vec![(center + Vec3::Y * radius).to_array()];
    let mut normals = vec![[0.0, 1.0, 0.0]];
    for i in 1..stacks {
        let phi = std::f32::consts::PI * i as f32 / stacks as f32;
        for j in 0..slices {
            let th = std::f32::consts::TAU * j as f32 / slices as f32;
            let n = Vec3::new(phi.sin() * th.cos(), phi.cos(), -phi.sin() * th.sin());
            positions.push((center + n * radius).to_array());
            normals.push(n.to_array());
        }
    }
    let south = positions.len() as u32;
    positions.push((center - Vec3::Y * radius).to_array());
    normals.push([0.0, -1.0, 0.0]);
    let ring = |i: u32, j: u32| 1 + (i - 1) * slices + j % slices;
    let mut indices = Vec::new();
    for j in 0..slices {
        indices.push([0, ring(1, j), ring(1, j + 1)]);
    }
    for i in 1..stacks - 1 {
        for j in 0..slices {
            let (a, b, c, d) = (ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1));
            indices.push([a, b, c]);
            indices.push([a, c, d]);
        }
    }
    for j in 0..slices {
        indices.push([south, ring(stacks - 1, j + 1), ring(stacks - 1, j)]);
    }
    TriangleMesh { positions, indices, normals: Some(normals), uvs: None }
}

/// An icosphere: an icosahedron subdivided `levels` times and projected onto the sphere
/// (20·4^levels triangles, every edge shared by exactly two of them).
pub fn icosphere(center: Vec3, radius: f32, levels: u32) -> TriangleMesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut verts: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, verts: &mut Vec<Vec3>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                verts.push(((verts[a as usize] + verts[b as usize]) * 0.5).normalize());
                verts.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let ab = midpoint(a, b, &mut verts);
            let bc = midpoint(b, c, &mut verts);
            let ca = midpoint(c, a, &mut verts);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    TriangleMesh {
        positions: verts.iter().map(|v| (center + *v * radius).to_array()).collect(),
        normals: Some(verts.iter().map(|v| v.to_array()).collect()),
        indices: faces,
        uvs: None,
    }
}

/// `mesh` with every triangle split into four at its edge midpoints, `levels` times
/// (4^levels times the triangles). Vertices on a shared edge are shared; normals and uvs,
/// where present, are interpolated (normals renormalised). A simulated box
/// (`docs/physics.md`) is subdivided so that its bending shows.
pub fn subdivide(mesh: &TriangleMesh, levels: u32) -> TriangleMesh {
    let mut m = mesh.clone();
    for _ in 0..levels {
        let mut mid: std::collections::HashMap<(u32, u32), u32> = std::collections::HashMap::new();
        let mut indices = Vec::with_capacity(m.indices.len() * 4);
        let old = std::mem::take(&mut m.indices);
        for t in &old {
            let mut e = [0u32; 3];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let key = (a.min(b), a.max(b));
                e[k] = *mid.entry(key).or_insert_with(|| {
                    let avg =
                        |x: [f32; 3], y: [f32; 3]| [0.5 * (x[0] + y[0]), 0.5 * (x[1] + y[1]), 0.5 * (x[2] + y[2])];
                    let (a, b) = (a as usize, b as usize);
                    m.positions.push(avg(m.positions[a], m.positions[b]));
                    if let Some(n) = &mut m.normals {
                        let v = Vec3::from_array(avg(n[a], n[b])).normalize_or_zero();
                        n.push(v.to_array());
                    }
                    if let Some(uv) = &mut m.uvs {
                        uv.push([0.5 * (uv[a][0] + uv[b][0]), 0.5 * (uv[a][1] + uv[b][1])]);
                    }
                    m.positions.len() as u32 - 1
                });
            }
            indices.push([t[0], e[0], e[2]]);
            indices.push([e[0], t[1], e[1]]);
            indices.push([e[2], e[1], t[2]]);
            indices.push([e[0], e[1], e[2]]);
        }
        m.indices = indices;
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Every undirected edge is used by exactly two triangles, in opposite directions.
    fn assert_closed_and_consistent(m: &TriangleMesh) {
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        for t in &m.indices {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "edge {a}-{b} used {n} times in one direction");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}-{b} has no opposite");
        }
    }

    #[test]
    fn uv_sphere_is_closed_with_outward_winding() {
        let m = uv_sphere(Vec3::new(1.0, 2.0, 3.0), 2.0, 8, 12);
        m.validate().unwrap();
        assert_closed_and_consistent(&m);
        for i in 0..m.triangle_count() {
            let t = m.triangle(i);
            assert!(t.normal().dot(t.centroid() - Vec3::new(1.0, 2.0, 3.0)) > 0.0, "triangle {i} faces inwards");
        }
    }

    #[test]
    fn subdividing_a_box_keeps_its_shape() {
        let b = cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO);
        let s = subdivide(&b, 2);
        assert_eq!(s.triangle_count(), 12 * 16);
        // Each face of 4 corners gains 21 vertices (a 5×5 grid).
        assert_eq!(s.vertex_count(), 6 * 25);
        assert_eq!(s.bounds(), b.bounds());
        s.validate().unwrap();
        let area =
            |m: &TriangleMesh| -> f32 { m.triangles().map(|t| 0.5 * (t.p1 - t.p0).cross(t.p2 - t.p0).length()).sum() };
        assert!((area(&s) - area(&b)).abs() < 1e-4);
    }

    #[test]
    fn icosphere_is_closed_and_counts_match() {
        let m = icosphere(Vec3::ZERO, 1.0, 2);
        assert_eq!(m.triangle_count(), 320);
        assert_closed_and_consistent(&m);
    }

    #[test]
    fn cuboid_has_requested_extent_and_outward_faces() {
        let m = cuboid(Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 4.0, 6.0), Vec3::ZERO);
        let b = m.bounds();
        assert!((b.min - Vec3::new(0.0, -2.0, -3.0)).abs().max_element() < 1e-6);
        assert!((b.max - Vec3::new(2.0, 2.0, 3.0)).abs().max_element() < 1e-6);
        for i in 0..12 {
            let t = m.triangle(i);
            assert!(t.normal().dot(t.centroid() - Vec3::new(1.0, 0.0, 0.0)) > 0.0, "face {i} inwards");
        }
    }

    #[test]
    fn cuboid_rotation_is_in_degrees() {
        let m = cuboid(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0), Vec3::new(0.0, 90.0, 0.0));
        let e = m.bounds().extent();
        assert!((e - Vec3::new(1.0, 1.0, 2.0)).abs().max_element() < 1e-5, "{e}");
    }

    #[test]
    fn cuboid_faces_carry_the_texture_upright_and_unmirrored() {
        let m = cuboid(Vec3::ZERO, Vec3::ONE, Vec3::ZERO);
        let uvs = m.uvs.as_ref().expect("boxes have uvs");
        for t in &m.indices {
            let p = t.map(|i| Vec3::from_array(m.positions[i as usize]));
            let uv = t.map(|i| glam::Vec2::from_array(uvs[i as usize]));
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            // Counter-clockwise in space and in uv alike: not mirrored.
            let uv_area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
            assert!(uv_area > 0.0, "triangle {t:?} is mirrored in uv");
            for k in 0..3 {
                assert!(uv[k].min_element() >= 0.0 && uv[k].max_element() <= 1.0);
                // On side faces v grows with y; on the top, towards -z.
                let up = if n.y.abs() > 0.5 { Vec3::Z * -n.y.signum() } else { Vec3::Y };
                assert!((uv[k].y - (p[k].dot(up) + 0.5)).abs() < 1e-6, "{t:?}");
            }
        }
        // The front face (+z): (0, 0) at its bottom-left corner seen from the front.
        let normals = m.normals.as_ref().unwrap();
        let corner = |p: &[f32; 3]| p[0] < -0.4 && p[1] < -0.4 && p[2] > 0.4;
        let front = (0..24).find(|&i| corner(&m.positions[i]) && normals[i] == [0.0, 0.0, 1.0]).unwrap();
        assert_eq!(uvs[front], [0.0, 0.0]);
    }
}
