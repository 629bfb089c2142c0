//! Tessellated primitives: boxes, UV spheres and icospheres. Seed 003 turns every actor
//! into triangles, so these feed the same structures as loaded meshes.

use dynray_geom::{TriangleMesh, Vec3};
use glam::{EulerRot, Mat4, Quat};

/// A box centred at `center`, with edge lengths `size`, rotated by `rotation_deg`
/// (degrees about x, then y, then z). 24 vertices with flat face normals, 12 triangles.
pub fn cuboid(center: Vec3, size: Vec3, rotation_deg: Vec3) -> TriangleMesh {
    let mut positions = Vec::with_capacity(24);
    let mut normals = Vec::with_capacity(24);
    let mut indices = Vec::with_capacity(12);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let (u, v) = (Vec3::from(unit((axis + 1) % 3)), Vec3::from(unit((axis + 2) % 3)));
            // Order the quad counter-clockwise seen from outside.
            let (u, v) = if sign > 0.0 { (u, v) } else { (v, u) };
            let base = positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                positions.push(((n + u * a + v * b) * 0.5).to_array());
                normals.push(n.to_array());
            }
            indices.push([base, base + 1, base + 2]);
            indices.push([base, base + 2, base + 3]);
        }
    }
    let mut m = TriangleMesh { positions, indices, normals: Some(normals), uvs: None };
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
}
