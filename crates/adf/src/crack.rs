//! Continuity across level changes: the T-junction rule.
//!
//! Trilinear interpolation is continuous between two leaves of the same level (they
//! share a face and its four corner samples) but not between a coarse leaf and the finer
//! leaves beside it: the fine leaves have samples in the middle of the coarse leaf's face
//! or edge (T-junctions) that the coarse interpolant does not see, so the field would
//! jump there (a crack, which a sphere tracer can fall through).
//!
//! **Rule (applied at build time, before packing):** every sample at a vertex lying on
//! the boundary of a coarser leaf, but not at one of its corners, is replaced by that
//! leaf's interpolant there. The coarsest leaf touching the vertex decides (a vertex that
//! is a corner of the coarsest touching leaf is a corner of every finer one, so it keeps
//! its exact sample). The fine cells' interpolant on the shared face is then the bilinear
//! interpolant of samples of the coarse one's bilinear face, which is that face exactly:
//! the field is continuous everywhere, and its Lipschitz bound holds across cells.
//! Blocks are fixed level by level from the root down, so a coarse leaf's own corners are
//! final before a finer block reads them. Exact samples stay exact wherever no coarser
//! leaf touches.

use crate::build::{block_at, trilinear, Cell, Tree};
use rayon::prelude::*;
use std::collections::HashMap;

/// Map from an internal cell's [`Cell::map_key`] to its block (its index in the tree).
pub(crate) type CellMap = HashMap<u64, u32>;

/// The map of `tree`'s internal cells.
pub(crate) fn cell_map(tree: &Tree) -> CellMap {
    tree.cells.iter().enumerate().map(|(i, c)| (Cell::map_key(c.level, c.index), i as u32)).collect()
}

/// Applies the T-junction rule to every block; returns how many samples it changed.
pub(crate) fn constrain_t_junctions(tree: &mut Tree, map: &CellMap) -> usize {
    let mut changed = 0;
    let mut start = 0usize;
    for level in 0..tree.max_level {
        let n = tree.internal_per_level[level as usize] as usize;
        let (done, rest) = tree.blocks.split_at_mut(start);
        let cells = &tree.cells[start..start + n];
        changed += rest[..n].par_iter_mut().zip(cells).map(|(b, c)| constrain_block(b, c, done, map)).sum::<usize>();
        start += n;
    }
    changed
}

fn internal(map: &CellMap, level: u32, index: [u32; 3]) -> bool {
    map.contains_key(&Cell::map_key(level, index))
}

/// Constrains the boundary samples of internal cell `c`'s block; `done` holds every
/// block of a coarser level.
fn constrain_block(block: &mut [f32; 27], c: &Cell, done: &[[f32; 27]], map: &CellMap) -> usize {
    let l = c.level;
    let n = 1i64 << l;
    let mut changed = 0;
    for i in 0..27u32 {
        let g = [i % 3, (i / 3) % 3, i / 9];
        // The level-l cells around the vertex on each axis: offsets from `c`.
        let offs = g.map(|x| match x {
            0 => [-1i64, 0],
            2 => [0, 1],
            _ => [0, 0],
        });
        // (leaf level, leaf index) of the coarsest leaf touching the vertex from outside c.
        let mut coarsest: Option<(u32, [u32; 3])> = None;
        for ox in offs[0] {
            for oy in offs[1] {
                for oz in offs[2] {
                    if (ox, oy, oz) == (0, 0, 0) {
                        continue;
                    }
                    let d = [c.index[0] as i64 + ox, c.index[1] as i64 + oy, c.index[2] as i64 + oz];
                    if d.iter().any(|&x| x < 0 || x >= n) {
                        continue;
                    }
                    let d = d.map(|x| x as u32);
                    if internal(map, l, d) {
                        continue;
                    }
                    // The leaf holding d's region: the first level whose parent is internal
                    // (the root always is).
                    let mut lc = l;
                    while lc > 0 && !internal(map, lc - 1, d.map(|x| x >> (l - lc + 1))) {
                        lc -= 1;
                    }
                    if coarsest.is_none_or(|(cl, _)| lc < cl) {
                        coarsest = Some((lc, d.map(|x| x >> (l - lc))));
                    }
                }
            }
        }
        let Some((lc, leaf)) = coarsest else { continue };
        // The vertex at resolution 2^(l+1), and its position in the leaf's grid.
        let v = [2 * c.index[0] + g[0], 2 * c.index[1] + g[1], 2 * c.index[2] + g[2]];
        let shift = l + 1 - lc;
        if v.iter().all(|x| x & ((1 << shift) - 1) == 0) {
            continue; // a corner of the leaf: its exact sample stays
        }
        let Some(&parent) = map.get(&Cell::map_key(lc - 1, leaf.map(|x| x >> 1))) else { continue };
        let Some(pb) = done.get(parent as usize) else { continue };
        let o = leaf.map(|x| x & 1);
        let corner = |x: u32, y: u32, z: u32| pb[block_at(o[0] + x, o[1] + y, o[2] + z)];
        let scale = 1.0 / (1u32 << shift) as f32;
        let t = [0, 1, 2].map(|k| v[k] as f32 * scale - leaf[k] as f32);
        let value = trilinear(&corner, t);
        if value.to_bits() != block[i as usize].to_bits() {
            block[i as usize] = value;
            changed += 1;
        }
    }
    changed
}

/// Lipschitz bounds of the reconstructed field, one per internal cell: the largest
/// gradient norm of any leaf's trilinear interpolant inside the cell (per axis, the
/// largest of the leaf's 4 edge differences over the edge length). With the field
/// continuous (T-junction rule) a cell's bound holds along any segment inside it, so a
/// sphere tracer may step `|d| / L` within it; the root's is the global bound.
pub(crate) fn lipschitz(tree: &Tree, map: &CellMap, cube_size: f32) -> Vec<f32> {
    let mut bound: Vec<f32> = tree
        .cells
        .par_iter()
        .zip(&tree.blocks)
        .map(|(c, b)| {
            let h = cube_size / (1u64 << (c.level + 1)) as f32;
            let mut worst = 0.0f32;
            for o in 0..8u32 {
                let o = [o & 1, (o >> 1) & 1, o >> 2];
                let child = [0, 1, 2].map(|k| 2 * c.index[k] + o[k]);
                if internal(map, c.level + 1, child) {
                    continue;
                }
                worst = worst.max(leaf_gradient_bound(&|x, y, z| b[block_at(o[0] + x, o[1] + y, o[2] + z)], h));
            }
            worst
        })
        .collect();
    // Children come after their parents (breadth-first): fold each into its parent, deepest first.
    for i in (1..tree.cells.len()).rev() {
        let c = tree.cells[i];
        if let Some(&p) = map.get(&Cell::map_key(c.level - 1, c.index.map(|x| x >> 1))) {
            bound[p as usize] = bound[p as usize].max(bound[i]);
        }
    }
    bound
}

/// The gradient bound of one leaf's trilinear interpolant of `at(x, y, z)` over edge `h`.
#[inline]
pub(crate) fn leaf_gradient_bound(at: &impl Fn(u32, u32, u32) -> f32, h: f32) -> f32 {
    let mut g2 = 0.0f32;
    for axis in 0..3 {
        let mut m = 0.0f32;
        for j in 0..4u32 {
            let (u, w) = (j & 1, j >> 1);
            let (lo, hi) = match axis {
                0 => (at(0, u, w), at(1, u, w)),
                1 => (at(u, 0, w), at(u, 1, w)),
                _ => (at(u, w, 0), at(u, w, 1)),
            };
            m = m.max((hi - lo).abs());
        }
        g2 += (m / h) * (m / h);
    }
    g2.sqrt()
}
