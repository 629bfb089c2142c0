//! What the live viewer's "boxes" view draws of a structure: its node bounds or cells down
//! to a chosen depth ([`crate::Accel::outline`]). Each structure's own walk lives in its
//! folder (`bvh2/outline.rs`, `kdtree/outline.rs`, …); this file holds the record they
//! push and the checks every structure's tests run on it.

use dynray_geom::Aabb;

/// One box of a structure's outline ([`crate::Accel::outline`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutlineBox {
    /// Depth in the structure (the root, or the whole grid, is 0).
    pub depth: u32,
    /// The node's bounds or the cell, in the mesh's (world) space.
    pub bounds: Aabb,
    /// True for a leaf (a node or cell that holds triangles, or an empty leaf cell).
    pub leaf: bool,
}

/// The checks every structure's outline tests share, over meshes with some depth to them.
#[cfg(test)]
pub(crate) mod checks {
    use super::OutlineBox;
    use crate::Accel;
    use dynray_geom::{Aabb, TriangleMesh, Vec3};

    /// Two spheres of different sizes and a tilted strip (≈ 3k triangles): uneven enough
    /// that every structure builds several levels.
    pub(crate) fn mesh() -> TriangleMesh {
        use dynray_scene::shapes::uv_sphere;
        let mut m = uv_sphere(Vec3::ZERO, 1.0, 24, 40);
        m.append(&uv_sphere(Vec3::new(2.5, 0.5, -0.5), 0.3, 12, 16));
        let base = m.positions.len() as u32;
        for i in 0..200 {
            let x = -2.0 + i as f32 * 0.02;
            m.positions.extend([[x, -1.5, 1.0 + 0.2 * x], [x + 0.015, -1.5, 1.0], [x, -1.2, 1.3 - 0.1 * x]]);
            let b = base + 3 * i;
            m.indices.push([b, b + 1, b + 2]);
        }
        m.normals = None;
        m
    }

    /// How a structure's leaves must cover the triangles.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub(crate) enum Cover {
        /// Node bounds: the union of the leaf boxes holds every triangle's centroid.
        Centroids,
        /// Cells that tile the root box: every triangle overlaps some leaf cell, and the
        /// leaf cells' volumes add up to the root's.
        Tiling,
        /// Non-empty cells only (a grid): every triangle overlaps some leaf cell.
        Cells,
    }

    /// `accel.outline(max_depth)` in a fresh vector.
    pub(crate) fn outline(accel: &dyn Accel, max_depth: u32) -> Vec<OutlineBox> {
        let mut out = Vec::new();
        accel.outline(max_depth, &mut out);
        out
    }

    /// Runs the shared checks on `accel`, built over `mesh`; returns the full outline's
    /// deepest depth (callers assert that the structure has some depth).
    ///
    /// 1. `outline(0)` is one box, at depth 0, holding every vertex;
    /// 2. every box at depth `d + 1` lies inside some box of depth `d`;
    /// 3. the full outline's leaves cover the triangles as `cover` says;
    /// 4. `outline(d)` is exactly the full outline's boxes of depth `<= d` (so the count
    ///    grows with `d`, strictly while deeper boxes remain), and it never pushes a box
    ///    deeper than asked.
    pub(crate) fn check(accel: &dyn Accel, mesh: &TriangleMesh, cover: Cover) -> u32 {
        let name = accel.name();
        // 1. The root.
        let root = outline(accel, 0);
        assert_eq!(root.len(), 1, "{name}: outline(0) = {root:?}");
        assert_eq!(root[0].depth, 0, "{name}");
        let root_box = root[0].bounds;
        for (i, p) in mesh.positions.iter().enumerate() {
            assert!(root_box.contains_point(Vec3::from_array(*p)), "{name}: vertex {i} {p:?} outside {root_box:?}");
        }

        let full = outline(accel, u32::MAX);
        let deepest = full.iter().map(|b| b.depth).max().unwrap();
        assert!(full.iter().all(|b| !b.bounds.is_empty()), "{name}: an empty box");

        // 2. Nesting, level by level.
        let level = |d: u32| full.iter().filter(move |b| b.depth == d);
        for d in 0..deepest {
            assert!(level(d + 1).next().is_some(), "{name}: no box at depth {} below {deepest}", d + 1);
            for c in level(d + 1) {
                assert!(
                    level(d).any(|p| !p.leaf && p.bounds.contains(&c.bounds)),
                    "{name}: {c:?} lies inside no interior box of depth {d}"
                );
            }
        }

        // 3. Cover.
        let leaves: Vec<Aabb> = full.iter().filter(|b| b.leaf).map(|b| b.bounds).collect();
        assert!(!leaves.is_empty(), "{name}: no leaf");
        match cover {
            Cover::Centroids => {
                for (i, t) in mesh.triangles().enumerate() {
                    let c = t.centroid();
                    assert!(leaves.iter().any(|l| l.contains_point(c)), "{name}: centroid of {i} in no leaf box");
                }
            }
            Cover::Tiling | Cover::Cells => {
                for (i, t) in mesh.triangles().enumerate() {
                    let overlaps = |l: &Aabb| {
                        let (c, h) = (l.center().as_dvec3(), (l.extent() * 0.5).as_dvec3());
                        t.overlaps_box(c.to_array(), h.to_array())
                    };
                    assert!(leaves.iter().any(overlaps), "{name}: triangle {i} overlaps no leaf cell");
                }
                if cover == Cover::Tiling {
                    let volume = |b: &Aabb| b.extent().as_dvec3().element_product();
                    let sum: f64 = leaves.iter().map(volume).sum();
                    let whole = volume(&root_box);
                    assert!((sum - whole).abs() <= 1e-4 * whole, "{name}: leaf cells {sum}, root {whole}");
                }
            }
        }

        // 4. Depth limits: a prefix of the full outline, growing with the depth.
        let mut last = 0;
        for d in 0..=deepest + 1 {
            let part = outline(accel, d);
            assert!(part.iter().all(|b| b.depth <= d), "{name}: outline({d}) goes deeper");
            let expected = sorted_keys(full.iter().filter(|b| b.depth <= d));
            assert!(sorted_keys(part.iter()) == expected, "{name}: outline({d}) is not the full one cut at {d}");
            assert!(
                part.len() > last || d > deepest,
                "{name}: outline({d}) has {} boxes, as depth {d} - 1",
                part.len()
            );
            last = part.len();
        }
        deepest
    }

    /// The boxes as sortable bit patterns, sorted: equal vectors are equal multisets.
    fn sorted_keys<'a>(boxes: impl Iterator<Item = &'a OutlineBox>) -> Vec<(u32, bool, [u32; 6])> {
        let key = |b: &OutlineBox| {
            let (lo, hi) = (b.bounds.min.to_array(), b.bounds.max.to_array());
            (b.depth, b.leaf, [lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]].map(f32::to_bits))
        };
        let mut keys: Vec<_> = boxes.map(key).collect();
        keys.sort_unstable();
        keys
    }

    /// `out` keeps what it held: outline appends.
    pub(crate) fn appends(accel: &dyn Accel) {
        let marker = OutlineBox { depth: 99, bounds: Aabb::new(Vec3::ZERO, Vec3::ONE), leaf: true };
        let mut out = vec![marker];
        accel.outline(1, &mut out);
        assert_eq!(out[0], marker, "{}", accel.name());
        assert!(out.len() > 1, "{}", accel.name());
    }
}
