//! The validator catches what traversal relies on: each test breaks one invariant of a
//! built tree and expects `check` to name it.

use super::block::{TriBlock, PAD_ID};
use super::kernel::KernelChoice;
use super::node::{is_leaf, leaf_blocks, Node4, Node8, WideNode};
use super::{Wbvh, WbvhParams, WideTree};
use crate::Bvh;
use dynray_geom::TriangleMesh;

/// A 30 × 30 grid of triangles (1,800): several levels at both widths.
fn grid() -> TriangleMesh {
    grid_of(30)
}

/// An `n` × `n` grid of quads, 2n² triangles on a bumpy sheet.
fn grid_of(n: u32) -> TriangleMesh {
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (x, y, z) = (i as f32, j as f32, ((i * 7 + j * 3) % 5) as f32 * 0.3);
            let b = pos.len() as u32;
            pos.extend([[x, y, z], [x + 0.9, y, z], [x, y + 0.9, z + 0.2], [x + 0.9, y + 0.9, z]]);
            idx.extend([[b, b + 1, b + 2], [b + 1, b + 3, b + 2]]);
        }
    }
    TriangleMesh::new(pos, idx)
}

fn tree<N: WideNode>(mesh: &TriangleMesh) -> WideTree<N> {
    let bvh = Bvh::build_block_cost(mesh, &WbvhParams::default().bvh, 2).unwrap();
    WideTree::<N>::build(&bvh, KernelChoice::Scalar).unwrap()
}

fn expect_broken<N: WideNode>(t: &WideTree<N>, mesh: &TriangleMesh, what: &str) {
    match t.check(mesh) {
        Ok(_) => panic!("{what}: the validator accepted a broken {}-wide tree", N::W),
        Err(e) => assert!(e.to_string().contains(what), "expected `{what}`, got: {e}"),
    }
}

fn breaks_are_caught<N: WideNode>() {
    let mesh = grid();
    let t = tree::<N>(&mesh);
    t.check(&mesh).unwrap();
    assert!(t.levels >= 3, "{} levels", t.levels);

    // A child box that no longer contains its subtree.
    let mut b = t.clone();
    let (i, lane) = (0, 0);
    let mut bx = b.nodes[i].child_box(lane);
    bx.max = bx.min + (bx.max - bx.min) * 0.5;
    b.nodes[i].set_box(lane, &bx);
    expect_broken(&b, &mesh, if is_leaf(b.nodes[i].child(lane)) { "sticks out" } else { "outside" });

    // A triangle twice (and another never).
    let mut b = t.clone();
    b.blocks[1].ids[0] = b.blocks[0].ids[0];
    expect_broken(&b, &mesh, "repeated");

    // A vertex moved behind the tree's back.
    let mut b = t.clone();
    for a in 0..3 {
        b.blocks[0].v[1][a][0] = b.blocks[0].v[0][a][0];
    }
    expect_broken(&b, &mesh, "not a copy");

    // A padding lane that could hit: the SIMD kernel relies on NaN padding.
    let mut b = t.clone();
    let padded = b.blocks.iter().position(|x| x.ids.contains(&PAD_ID)).expect("a padded block");
    let lane = b.blocks[padded].ids.iter().position(|&id| id == PAD_ID).unwrap();
    b.blocks[padded].v[0][0][lane] = 0.0;
    b.blocks[padded].v[0][1][lane] = 0.0;
    b.blocks[padded].v[0][2][lane] = 0.0;
    expect_broken(&b, &mesh, "not NaN");

    // A recorded depth that is not the tree's (the stack would be sized wrongly).
    let mut b = t.clone();
    b.levels -= 1;
    expect_broken(&b, &mesh, "levels");

    // An interior child pointing back at the root (a cycle).
    let mut b = t.clone();
    let (n, lane) = b
        .nodes
        .iter()
        .enumerate()
        .find_map(|(n, node)| (0..node.count()).find(|&k| !is_leaf(node.child(k))).map(|k| (n, k)))
        .unwrap();
    let node = b.nodes[n];
    let mut fresh = N::empty();
    for k in 0..node.count() {
        fresh.push(if k == lane { 0 } else { node.child(k) }, &node.child_box(k));
    }
    b.nodes[n] = fresh;
    expect_broken(&b, &mesh, "out of order");

    // A block in no leaf.
    let mut b = t.clone();
    b.blocks.push(TriBlock::PAD);
    expect_broken(&b, &mesh, "in no leaf");
}

/// The grid with two large slanted triangles across it, built pre-split.
fn presplit_tree() -> (TriangleMesh, WideTree<Node8>) {
    let mut mesh = grid();
    let b = mesh.positions.len() as u32;
    mesh.positions.extend([[0.0, 0.0, -2.0], [30.0, 3.0, 3.0], [2.0, 30.0, 1.0], [30.0, 30.0, -1.0]]);
    mesh.indices.extend([[b, b + 1, b + 2], [b + 1, b + 3, b + 2]]);
    let w = Wbvh::build(&mesh, &WbvhParams { presplit: 0.05, ..WbvhParams::default() }).unwrap();
    match w.tree {
        super::Tree::W8(t) => (mesh, t),
        super::Tree::W4(_) => unreachable!("width 8 asked for"),
    }
}

#[test]
fn the_validator_catches_broken_presplit_trees() {
    let (mesh, t) = presplit_tree();
    let shape = t.check(&mesh).unwrap();
    let big = (mesh.triangle_count() - 2) as u32;
    let leaves_of = |t: &WideTree<Node8>, id: u32| {
        let mut v = Vec::new();
        for (n, node) in t.nodes.iter().enumerate() {
            for k in 0..node.count() {
                let c = node.child(k);
                if is_leaf(c) {
                    let (first, count) = leaf_blocks(c);
                    if t.blocks[first..first + count].iter().any(|b| b.ids.contains(&id)) {
                        v.push((n, k));
                    }
                }
            }
        }
        v
    };
    assert!(t.presplit && shape.triangles > mesh.triangle_count(), "{shape:?}");
    assert!(leaves_of(&t, big).len() > 1, "the big triangle was not split");

    // One part of a triangle twice in a leaf.
    let mut b = t.clone();
    let (i, lane) = b
        .blocks
        .iter()
        .enumerate()
        .find_map(|(i, x)| (x.real_lanes() >= 2).then_some((i, 1)))
        .expect("a block of two triangles");
    let first = b.blocks[i].triangle(0);
    let id0 = b.blocks[i].ids[0];
    b.blocks[i].set(lane, &first, id0);
    expect_broken(&b, &mesh, "repeated");

    // The leaves of the big triangle shrunk away from one of its corners.
    let mut b = t.clone();
    for (n, k) in leaves_of(&b, big) {
        let mut bx = b.nodes[n].child_box(k);
        bx.max -= (bx.max - bx.min) * 0.01;
        b.nodes[n].set_box(k, &bx);
    }
    expect_broken(&b, &mesh, "do not cover");

    // A refit keeps it valid.
    let mut b = t.clone();
    b.refit(&mesh).unwrap();
    b.check(&mesh).unwrap();
}

#[test]
fn the_validator_catches_broken_4_wide_trees() {
    breaks_are_caught::<Node4>();
}

#[test]
fn the_validator_catches_broken_8_wide_trees() {
    breaks_are_caught::<Node8>();
}

#[test]
fn refit_on_the_same_mesh_reproduces_the_built_tree_bit_for_bit() {
    let mesh = grid();
    for width in [4, 8] {
        let p = WbvhParams { width, ..WbvhParams::default() };
        let built = Wbvh::build(&mesh, &p).unwrap();
        let mut moved = mesh.clone();
        for q in &mut moved.positions {
            q[2] += q[0] * 0.1;
        }
        let mut w = built.clone();
        crate::Accel::update(&mut w, &moved).unwrap();
        crate::Accel::update(&mut w, &mesh).unwrap();
        assert!(bytes(&w) == bytes(&built), "width {width}");
    }
}

/// The node and block arrays as bytes.
fn bytes(w: &Wbvh) -> (Vec<u8>, Vec<u8>) {
    match &w.tree {
        super::Tree::W4(t) => {
            (bytemuck::cast_slice::<_, u8>(&t.nodes).to_vec(), bytemuck::cast_slice::<_, u8>(&t.blocks).to_vec())
        }
        super::Tree::W8(t) => {
            (bytemuck::cast_slice::<_, u8>(&t.nodes).to_vec(), bytemuck::cast_slice::<_, u8>(&t.blocks).to_vec())
        }
    }
}

#[test]
fn same_tree_on_one_and_two_threads() {
    // 80,000 triangles: above the builder's parallel binning (65,536) and subtree (4,096)
    // thresholds and the collapse's parallel block fill (1,024 blocks per task).
    let mesh = grid_of(200);
    for width in [4, 8] {
        let p = WbvhParams { width, ..WbvhParams::default() };
        let build = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| Wbvh::build(&mesh, &p).unwrap())
        };
        assert!(bytes(&build(1)) == bytes(&build(2)), "width {width}");
    }
}

#[test]
fn leaves_hold_at_most_the_leaf_cap_and_blocks_are_full_but_the_last() {
    let mesh = grid();
    let t = tree::<Node8>(&mesh);
    for node in &t.nodes {
        for k in (0..node.count()).filter(|&k| is_leaf(node.child(k))) {
            let (first, count) = leaf_blocks(node.child(k));
            let lanes: Vec<usize> = t.blocks[first..first + count].iter().map(|b| b.real_lanes()).collect();
            assert!(lanes[..count - 1].iter().all(|&l| l == 4), "{lanes:?}");
            assert!(lanes.iter().sum::<usize>() <= WbvhParams::default().bvh.max_leaf_size as usize);
        }
    }
}
