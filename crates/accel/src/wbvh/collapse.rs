//! From the binary SAH tree to the wide one: each wide node takes the children of a binary
//! node and keeps opening its largest-area interior child (replacing it by its two
//! children) until it has `W` children or only leaves (the greedy collapse of Embree's
//! and tinybvh's wide builders); each binary leaf becomes a run of 4-triangle blocks.
//!
//! Boxes are copied from the binary nodes unchanged, so every child box is exactly the
//! union of what lies below it, as the binary tree's are.

use super::block::{TriBlock, LANES};
use super::node::{leaf_ref, WideNode, MAX_BLOCKS};
use crate::{BuildError, BvhNode};
use dynray_geom::Triangle;

/// A collapsed tree: nodes root first (children after parents), blocks in leaf order.
pub(super) struct Collapsed<N> {
    pub nodes: Vec<N>,
    pub blocks: Vec<TriBlock>,
    /// Interior levels on the deepest path (the root alone: 1).
    pub levels: u32,
}

/// Collapses the binary tree `bin` (leaf-order mesh ids `ids`) into `W`-wide nodes;
/// `tri(i, id)` gives leaf-order triangle `i`, mesh index `id` (the build reads the mesh,
/// so the binary tree need not copy its triangles).
pub(super) fn collapse<N: WideNode>(
    bin: &[BvhNode],
    ids: &[u32],
    tri: impl Fn(usize, u32) -> Triangle,
) -> Result<Collapsed<N>, BuildError> {
    let n = ids.len();
    if n.div_ceil(4) + bin.len() > MAX_BLOCKS as usize {
        return Err(BuildError::Limit(format!("{n} triangles: a wide leaf reference addresses {MAX_BLOCKS} blocks")));
    }
    let mut c = Collapser {
        bin,
        ids,
        tri,
        out: Collapsed { nodes: Vec::with_capacity(bin.len() / 4), blocks: Vec::new(), levels: 0 },
    };
    c.out.blocks.reserve(n / 3);
    c.out.nodes.push(N::empty());
    c.node(0, 0, 1);
    Ok(c.out)
}

struct Collapser<'a, N, T> {
    bin: &'a [BvhNode],
    ids: &'a [u32],
    tri: T,
    out: Collapsed<N>,
}

impl<N: WideNode, T: Fn(usize, u32) -> Triangle> Collapser<'_, N, T> {
    /// Emits the wide node for binary node `b` at interior level `level` (root: 1) into the
    /// slot `idx` (already pushed).
    ///
    /// Layout: a node's leaf children's blocks are emitted together, and its interior
    /// children take adjacent slots, before any grandchild is emitted; so the children a
    /// ray visits after one box test lie together in memory rather than a subtree apart.
    fn node(&mut self, b: usize, idx: usize, level: u32) {
        self.out.levels = self.out.levels.max(level);
        let bin = self.bin;
        // A one-leaf tree (few triangles) is a root with a single leaf child.
        let mut kids = [0usize; 8];
        let mut len = if bin[b].is_leaf() {
            kids[0] = b;
            1
        } else {
            kids[0] = bin[b].index as usize;
            kids[1] = kids[0] + 1;
            2
        };
        while len < N::W {
            let open = (0..len)
                .filter(|&k| !bin[kids[k]].is_leaf())
                .max_by(|&x, &y| bin[kids[x]].bounds().surface_area().total_cmp(&bin[kids[y]].bounds().surface_area()));
            let Some(k) = open else { break };
            let l = bin[kids[k]].index as usize;
            kids[k] = l;
            kids[len] = l + 1;
            len += 1;
        }
        let mut interior = [(0usize, 0usize); 8];
        let mut n_interior = 0;
        for &k in &kids[..len] {
            let r = if bin[k].is_leaf() {
                let (first, count) = (bin[k].index as usize, bin[k].count as usize);
                let start = self.out.blocks.len() as u32;
                for (c, ids) in self.ids[first..first + count].chunks(LANES).enumerate() {
                    let mut block = TriBlock::PAD;
                    for (lane, &id) in ids.iter().enumerate() {
                        block.set(lane, &(self.tri)(first + c * LANES + lane, id), id);
                    }
                    self.out.blocks.push(block);
                }
                leaf_ref(start, self.out.blocks.len() as u32 - start)
            } else {
                let slot = self.out.nodes.len();
                self.out.nodes.push(N::empty());
                interior[n_interior] = (k, slot);
                n_interior += 1;
                slot as u32
            };
            self.out.nodes[idx].push(r, &bin[k].bounds());
        }
        for &(k, slot) in &interior[..n_interior] {
            self.node(k, slot, level + 1);
        }
    }
}
