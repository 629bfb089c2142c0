//! Self-check of a built or refitted wide BVH, which also measures its shape.

use super::block::{TriBlock, LANES};
use super::node::{is_leaf, leaf_blocks, WideNode, EMPTY};
use super::traverse::{stack_need, STACK_CAPACITY};
use super::WideTree;
use dynray_geom::{Aabb, TriangleMesh};

/// A broken invariant, with the node where it was found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("wide BVH invariant broken at node {node}: {what}")]
pub struct InvalidWbvh {
    /// Index of the offending node (0 for array-level problems).
    pub node: u32,
    /// What is wrong, with the values involved.
    pub what: String,
}

/// Shape and quality of a valid tree.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WbvhShape {
    /// Interior (wide) nodes.
    pub interior: usize,
    /// Leaves (runs of blocks).
    pub leaves: usize,
    /// Blocks.
    pub blocks: usize,
    /// Triangles (real lanes).
    pub triangles: usize,
    /// Interior levels on the deepest path: the depth of the deepest leaf (root = 0).
    pub levels: u32,
    /// Triangles per leaf, as [`crate::AccelStats::leaf_sizes`].
    pub leaf_sizes: Vec<usize>,
    /// SAH cost relative to the root's box: `K_T = 1` per interior node, `K_I = 1` per
    /// block of a leaf (what the kernel tests).
    pub sah_cost: Option<f64>,
}

impl WbvhShape {
    /// Share of block lanes that hold a triangle (the rest are padding).
    pub fn fill(&self) -> f64 {
        if self.blocks == 0 {
            0.0
        } else {
            self.triangles as f64 / (LANES * self.blocks) as f64
        }
    }
}

fn bad(node: usize, what: String) -> InvalidWbvh {
    InvalidWbvh { node: node as u32, what }
}

impl<N: WideNode> WideTree<N> {
    /// [`WideTree::shape`], then every block lane is an exact copy of its mesh triangle and
    /// the blocks hold every mesh triangle exactly once; in a pre-split tree at least once
    /// and never twice in one leaf, each vertex inside the box of a leaf holding the
    /// triangle, and the triangle's box inside the hull of those leaves' boxes (what the
    /// parts' boxes covering the triangle implies).
    pub(super) fn check(&self, mesh: &TriangleMesh) -> Result<WbvhShape, InvalidWbvh> {
        let (shape, leaf_of_block) = self.walk()?;
        let n = mesh.triangle_count();
        // More lanes than triangles are repeats, fewer leave a triangle out: both are
        // named below, triangle by triangle.
        if n != self.triangles {
            return Err(bad(0, format!("mesh has {n} triangles, the tree was built over {}", self.triangles)));
        }
        // Per triangle: the last leaf (by its first block) it was seen in, the hull of its
        // leaves' boxes, and which of its vertices a leaf box holds.
        let mut last_leaf = vec![usize::MAX; n];
        let mut hull = vec![Aabb::EMPTY; n];
        let mut vertices_in = vec![0u8; n];
        for (i, b) in self.blocks.iter().enumerate() {
            let (leaf, leaf_box) = leaf_of_block[i];
            for lane in (0..LANES).filter(|&l| !b.is_pad(l)) {
                let id = b.ids[lane] as usize;
                if id >= n {
                    return Err(bad(0, format!("block {i} lane {lane}: triangle id {id} out of range")));
                }
                let seen_before = last_leaf[id] != usize::MAX;
                if (seen_before && !self.presplit) || last_leaf[id] == leaf {
                    return Err(bad(0, format!("block {i} lane {lane}: triangle {id} repeated")));
                }
                let t = mesh.triangle(id);
                if b.triangle(lane) != t {
                    return Err(bad(0, format!("block {i} lane {lane} is not a copy of mesh triangle {id}")));
                }
                last_leaf[id] = leaf;
                hull[id] = hull[id].union(&leaf_box);
                for (k, p) in [t.p0, t.p1, t.p2].into_iter().enumerate() {
                    if leaf_box.contains_point(p) {
                        vertices_in[id] |= 1 << k;
                    }
                }
            }
        }
        for id in 0..n {
            if last_leaf[id] == usize::MAX {
                return Err(bad(0, format!("triangle {id} in no leaf")));
            }
            let t = mesh.triangle(id);
            if vertices_in[id] != 0b111 || !hull[id].contains(&t.bounds()) {
                return Err(bad(0, format!("the leaves holding triangle {id} do not cover it: {t:?}")));
            }
        }
        Ok(shape)
    }

    /// [`WideTree::walk`]'s shape.
    pub(super) fn shape(&self) -> Result<WbvhShape, InvalidWbvh> {
        self.walk().map(|(s, _)| s)
    }

    /// The invariants that need no mesh: every node reached once from the root and after
    /// its parent, lanes `count..W` empty, child boxes non-empty and inside the parent's
    /// box for that child, leaf triangles inside their leaf's box (in a pre-split tree:
    /// touching it), every block in exactly one leaf, padding lanes NaN (what makes them
    /// miss in the SIMD kernel), the recorded depth the real one and the stack it needs
    /// within [`STACK_CAPACITY`]. Also gives each block's leaf (its first block) and box.
    fn walk(&self) -> Result<(WbvhShape, Vec<(usize, Aabb)>), InvalidWbvh> {
        let nodes = &self.nodes;
        if nodes.is_empty() || self.blocks.is_empty() {
            return Err(bad(0, format!("{} nodes, {} blocks", nodes.len(), self.blocks.len())));
        }
        let mut s = WbvhShape::default();
        let mut sizes = crate::LeafSizes::new();
        let mut reached = vec![false; nodes.len()];
        let mut leaf_of_block = vec![(usize::MAX, Aabb::EMPTY); self.blocks.len()];
        let root_box = (0..nodes[0].count()).fold(Aabb::EMPTY, |b, k| b.union(&nodes[0].child_box(k)));
        let root_area = root_box.surface_area() as f64;
        let mut sah = 0.0f64;
        // (node, its box as the parent stores it, interior level: root 1)
        let mut stack = vec![(0usize, root_box, 1u32)];
        reached[0] = true;
        while let Some((i, parent_box, level)) = stack.pop() {
            let node = &nodes[i];
            s.interior += 1;
            s.levels = s.levels.max(level);
            sah += parent_box.surface_area() as f64;
            let count = node.count();
            if count == 0 || count > N::W {
                return Err(bad(i, format!("{count} children (width {})", N::W)));
            }
            if let Some(k) = (count..N::W).find(|&k| node.child(k) != EMPTY) {
                return Err(bad(i, format!("unused lane {k} holds reference {:#x}", node.child(k))));
            }
            for k in 0..count {
                let (c, b) = (node.child(k), node.child_box(k));
                if b.is_empty() || !parent_box.contains(&b) {
                    return Err(bad(i, format!("child {k} box {b:?} empty or outside {parent_box:?}")));
                }
                if is_leaf(c) {
                    let (first, nb) = leaf_blocks(c);
                    if c == EMPTY || first + nb > self.blocks.len() {
                        return Err(bad(
                            i,
                            format!("leaf {k} blocks {first}..{} of {}", first + nb, self.blocks.len()),
                        ));
                    }
                    let mut tris = 0;
                    for (j, blk) in self.blocks[first..first + nb].iter().enumerate() {
                        if std::mem::replace(&mut leaf_of_block[first + j], (first, b)).0 != usize::MAX {
                            return Err(bad(i, format!("block {} in two leaves", first + j)));
                        }
                        check_block(blk, &b, self.presplit).map_err(|e| bad(i, format!("block {}: {e}", first + j)))?;
                        tris += blk.real_lanes();
                    }
                    s.leaves += 1;
                    s.blocks += nb;
                    s.triangles += tris;
                    sizes.add(tris);
                    sah += b.surface_area() as f64 * nb as f64;
                } else {
                    let ci = c as usize;
                    if ci <= i || ci >= nodes.len() {
                        return Err(bad(
                            i,
                            format!("child {k} = node {ci} out of order or range ({} nodes)", nodes.len()),
                        ));
                    }
                    if std::mem::replace(&mut reached[ci], true) {
                        return Err(bad(i, format!("node {ci} has two parents")));
                    }
                    stack.push((ci, b, level + 1));
                }
            }
        }
        if s.interior != nodes.len() {
            return Err(bad(0, format!("{} of {} nodes unreachable", nodes.len() - s.interior, nodes.len())));
        }
        if let Some(j) = leaf_of_block.iter().position(|u| u.0 == usize::MAX) {
            return Err(bad(0, format!("block {j} in no leaf")));
        }
        if s.levels != self.levels || stack_need(s.levels, N::W) != self.stack_need {
            return Err(bad(0, format!("recorded {} levels, measured {}", self.levels, s.levels)));
        }
        if self.stack_need > STACK_CAPACITY {
            return Err(bad(
                0,
                format!("{} levels need {} stack entries, above {STACK_CAPACITY}", s.levels, self.stack_need),
            ));
        }
        s.leaf_sizes = sizes.finish();
        s.sah_cost = (root_area > 0.0).then(|| sah / root_area);
        Ok((s, leaf_of_block))
    }
}

/// A block's real lanes inside `leaf_box` (touching it, where `parts`: a pre-split
/// tree's leaf box holds only a part of a triangle), at least one real lane, padding all
/// NaN.
fn check_block(b: &TriBlock, leaf_box: &Aabb, parts: bool) -> Result<(), String> {
    if b.real_lanes() == 0 {
        return Err("no triangle".into());
    }
    for lane in 0..LANES {
        if b.is_pad(lane) {
            let t = b.triangle(lane);
            if ![t.p0, t.p1, t.p2].iter().all(|p| p.is_nan_mask().all()) {
                return Err(format!("padding lane {lane} is not NaN: {t:?}"));
            }
        } else {
            let t = b.triangle(lane).bounds();
            let inside = if parts { !leaf_box.intersection(&t).is_empty() } else { leaf_box.contains(&t) };
            if !inside {
                return Err(format!(
                    "lane {lane} ({t:?}) {} {leaf_box:?}",
                    if parts { "misses" } else { "sticks out of" }
                ));
            }
        }
    }
    Ok(())
}
