//! From the binary SAH tree to the wide one: each wide node takes the children of a binary
//! node and keeps opening its largest-area interior child (replacing it by its two
//! children) until it has `W` children or only leaves (the greedy collapse of Embree's
//! and tinybvh's wide builders); each binary leaf becomes a run of 4-triangle blocks.
//!
//! Boxes are copied from the binary nodes unchanged, so every child box is exactly the
//! union of what lies below it, as the binary tree's are.
//!
//! The walk itself only lays out nodes and block slots (a few bytes per block); the blocks
//! are then filled in parallel, since reading each triangle from the mesh and writing 160
//! bytes per block was most of the collapse's time and all of it on one thread.

use super::block::{TriBlock, LANES};
use super::node::{leaf_ref, WideNode, MAX_BLOCKS};
use super::params::HugePages;
use crate::{huge_pages, BuildError, BvhNode};
use dynray_geom::Triangle;
use rayon::prelude::*;

/// A collapsed tree: nodes root first (children after parents), blocks in leaf order.
pub(super) struct Collapsed<N> {
    pub nodes: Vec<N>,
    pub blocks: Vec<TriBlock>,
    /// Interior levels on the deepest path (the root alone: 1).
    pub levels: u32,
    /// Both arrays were advised for huge pages.
    pub huge_pages: bool,
}

/// Collapses the binary tree `bin` (leaf-order mesh ids `ids`) into `W`-wide nodes;
/// `tri(i, id)` gives leaf-order triangle `i`, mesh index `id` (the build reads the mesh,
/// so the binary tree need not copy its triangles). `pages` says whether the arrays go on
/// huge pages, by the tree's size.
pub(super) fn collapse<N: WideNode>(
    bin: &[BvhNode],
    ids: &[u32],
    tri: impl Fn(usize, u32) -> Triangle + Sync,
    pages: HugePages,
) -> Result<Collapsed<N>, BuildError> {
    let n = ids.len();
    if n.div_ceil(4) + bin.len() > MAX_BLOCKS as usize {
        return Err(BuildError::Limit(format!("{n} triangles: a wide leaf reference addresses {MAX_BLOCKS} blocks")));
    }
    let mut c =
        Collapser { bin, nodes: Vec::with_capacity(bin.len() / 4), slots: Vec::with_capacity(n / 3), levels: 0 };
    c.nodes.push(N::empty());
    c.node(0, 0, 1);
    // The sizes are known now: the nodes (a quarter of the tree or less) are copied onto
    // huge pages, the blocks are written there in the first place.
    let bytes = c.nodes.len() * std::mem::size_of::<N>() + c.slots.len() * std::mem::size_of::<TriBlock>();
    let huge = pages.applies(bytes);
    let nodes = if huge { huge_pages::copy(&c.nodes) } else { c.nodes };
    let mut blocks = Vec::with_capacity(c.slots.len());
    if huge {
        huge_pages::advise(&blocks);
    }
    // Block `k` holds leaf-order triangles `slots[k] .. slots[k] + 4` (fewer at a leaf's
    // end); `collect_into_vec` fills the allocation made above.
    c.slots
        .par_iter()
        .with_min_len(1024)
        .map(|&(first, len)| {
            let mut block = TriBlock::PAD;
            for lane in 0..len as usize {
                let i = first as usize + lane;
                block.set(lane, &tri(i, ids[i]), ids[i]);
            }
            block
        })
        .collect_into_vec(&mut blocks);
    Ok(Collapsed { nodes, blocks, levels: c.levels, huge_pages: huge })
}

struct Collapser<'a, N> {
    bin: &'a [BvhNode],
    nodes: Vec<N>,
    /// Per block, in block order: its first leaf-order triangle and how many it holds.
    slots: Vec<(u32, u32)>,
    levels: u32,
}

impl<N: WideNode> Collapser<'_, N> {
    /// Emits the wide node for binary node `b` at interior level `level` (root: 1) into the
    /// slot `idx` (already pushed).
    ///
    /// Layout: a node's leaf children's blocks are emitted together, and its interior
    /// children take adjacent slots, before any grandchild is emitted; so the children a
    /// ray visits after one box test lie together in memory rather than a subtree apart.
    fn node(&mut self, b: usize, idx: usize, level: u32) {
        self.levels = self.levels.max(level);
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
                let (first, count) = (bin[k].index, bin[k].count);
                let start = self.slots.len() as u32;
                for c in (0..count).step_by(LANES) {
                    self.slots.push((first + c, (count - c).min(LANES as u32)));
                }
                leaf_ref(start, self.slots.len() as u32 - start)
            } else {
                let slot = self.nodes.len();
                self.nodes.push(N::empty());
                interior[n_interior] = (k, slot);
                n_interior += 1;
                slot as u32
            };
            self.nodes[idx].push(r, &bin[k].bounds());
        }
        for &(k, slot) in &interior[..n_interior] {
            self.node(k, slot, level + 1);
        }
    }
}
