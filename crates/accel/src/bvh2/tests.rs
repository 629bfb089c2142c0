//! Unit tests of the BVH module: builds on tiny meshes, and `validate` catching corruption.

use super::*;
use dynray_geom::Vec3;

/// A strip of `n` unit triangles along x.
fn strip(n: usize) -> TriangleMesh {
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for i in 0..n {
        let x = i as f32 * 2.0;
        let b = pos.len() as u32;
        pos.extend([[x, 0.0, 0.0], [x + 1.0, 0.0, 0.0], [x, 1.0, (i % 3) as f32]]);
        idx.push([b, b + 1, b + 2]);
    }
    TriangleMesh::new(pos, idx)
}

#[test]
fn single_triangle_is_one_leaf() {
    let m = strip(1);
    let bvh = Bvh::build(&m, &BvhParams::default()).unwrap();
    assert_eq!(bvh.nodes().len(), 1);
    assert!(bvh.nodes()[0].is_leaf());
    let s = bvh.validate(&m).unwrap();
    assert_eq!((s.nodes, s.leaves, s.max_depth), (1, 1, 0));
    let hit = bvh.intersect(&Ray::new(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z));
    assert_eq!(hit.prim, 0);
}

#[test]
fn strip_builds_a_valid_tree_with_small_leaves() {
    let m = strip(1000);
    let p = BvhParams::default();
    let bvh = Bvh::build(&m, &p).unwrap();
    let s = bvh.validate(&m).unwrap();
    assert_eq!(s.leaf_sizes.iter().enumerate().map(|(k, c)| k * c).sum::<usize>(), 1000);
    assert!(s.leaf_sizes.len() <= p.max_leaf_size as usize + 1, "{:?}", s.leaf_sizes);
    assert!(s.max_depth < 40, "depth {}", s.max_depth);
    assert!(s.sah_cost.unwrap() > 0.0);
    // Every triangle is found by a ray straight down onto it.
    for i in 0..1000 {
        let x = i as f32 * 2.0 + 0.25;
        let hit = bvh.intersect(&Ray::new(Vec3::new(x, 0.25, 10.0), -Vec3::Z));
        assert_eq!(hit.prim, i as u32, "triangle {i}");
    }
}

#[test]
fn invalid_params_are_rejected() {
    let e = Bvh::build(&strip(4), &BvhParams { bins: 0, ..Default::default() }).unwrap_err();
    assert!(matches!(e, BuildError::Param { name: "bins", .. }), "{e}");
}

fn built(n: usize) -> (TriangleMesh, Bvh) {
    let m = strip(n);
    let b = Bvh::build(&m, &BvhParams::default()).unwrap();
    (m, b)
}

#[test]
fn validate_catches_a_child_outside_its_parent() {
    let (m, mut b) = built(64);
    let l = b.nodes[0].index as usize;
    b.nodes[l].max[1] += 10.0;
    let e = b.check_invariants(&m).unwrap_err();
    assert!(e.what.contains("outside"), "{e}");
}

#[test]
fn validate_catches_a_triangle_in_two_leaves() {
    let (m, mut b) = built(64);
    let leaves: Vec<usize> = (0..b.nodes.len()).filter(|&i| b.nodes[i].is_leaf()).collect();
    let first = b.nodes[leaves[0]].index;
    b.nodes[leaves[1]].index = first;
    // The stolen leaf's box may no longer hold its triangles; either error is a catch,
    // but the double reference must be what is reported when boxes are widened.
    b.nodes[leaves[1]].min = [-1e9; 3];
    b.nodes[leaves[1]].max = [1e9; 3];
    let e = b.check_invariants(&m).unwrap_err();
    assert!(e.what.contains("two leaves") || e.what.contains("outside"), "{e}");
}

#[test]
fn validate_catches_a_bad_child_index_and_a_wrong_copy() {
    let (m, mut b) = built(64);
    let mut c = b.clone();
    c.nodes[0].index = c.nodes.len() as u32;
    assert!(c.check_invariants(&m).unwrap_err().what.contains("out of range"));
    b.tris[3].p0.x += 0.5;
    let e = b.check_invariants(&m).unwrap_err();
    assert!(e.what.contains("not a copy") || e.what.contains("sticks out"), "{e}");
}

#[test]
fn validate_catches_repeated_ids() {
    let (m, mut b) = built(16);
    b.ids[1] = b.ids[0];
    assert!(b.check_invariants(&m).unwrap_err().what.contains("repeated"));
}

#[test]
fn refit_rejects_a_different_triangle_count() {
    let (_, mut b) = built(16);
    assert!(matches!(b.refit(&strip(17)), Err(BuildError::TopologyChanged { built: 16, given: 17 })));
}

#[test]
fn the_per_frame_sah_cost_is_the_one_stats_reports() {
    // `Accel::sah_cost` sums the node array in order, `stats` walks the tree: the same
    // terms, so equal up to the order of a floating-point sum.
    let m = strip(1000);
    let mut bvh = Bvh::build(&m, &BvhParams::default()).unwrap();
    let mut moved = m.clone();
    for (i, p) in moved.positions.iter_mut().enumerate() {
        p[1] += (i % 7) as f32 * 0.3;
    }
    for mesh in [&m, &moved] {
        bvh.refit(mesh).unwrap();
        let (fast, full) = (Accel::sah_cost(&bvh).unwrap(), bvh.stats().sah_cost.unwrap());
        assert!((fast - full).abs() <= 1e-9 * full, "{fast} vs {full}");
    }
}

#[test]
fn from_parts_accepts_a_built_tree_and_rejects_a_broken_one() {
    let (m, bvh) = built(300);
    let p = *bvh.params();
    let again =
        Bvh::from_parts(&m, bvh.nodes().to_vec(), bvh.triangles().to_vec(), bvh.triangle_ids().to_vec(), &p).unwrap();
    assert_eq!((again.nodes(), again.depth()), (bvh.nodes(), bvh.depth()));
    let mut ids = bvh.triangle_ids().to_vec();
    ids.swap(0, 1);
    let err = Bvh::from_parts(&m, bvh.nodes().to_vec(), bvh.triangles().to_vec(), ids, &p).unwrap_err();
    assert!(err.what.contains("not a copy"), "{err}");
}
