//! Frisken et al. 2000 top-down subdivision of the full octree over the unit cube, level
//! by level (breadth-first), sampling the exact distance at every vertex of each
//! candidate cell's child grid (the 27 vertices its 3×3×3 block would hold).
//!
//! A cell splits when it is the root, when the surface may pass through it (its centre
//! is nearer to the surface than its half diagonal: those cells always reach the
//! maximum level), or when the trilinear interpolant of its 8 corners misses the exact
//! distance at its centre, 6 face centres or 12 edge midpoints (the other 19 vertices of
//! the child grid) by more than ε. Splitting stops at the maximum level.
//!
//! **Sign propagation.** The sign query (ray parity, `sign.rs`) costs several BVH walks;
//! the unsigned distance one. A vertex `v` whose unsigned distance `u` exceeds its
//! distance to the nearest coarser vertex `c` (`v >> 1`, sampled one level earlier) has
//! no surface within the segment `v`–`c` (the ball of radius `u` around `v` holds it), so
//! it takes `c`'s sign without a query. Only vertices near the surface pay for the vote.
//! Every sample is a pure function of its position, so the tree is the same for every
//! thread count.

use crate::field::DistanceSource;
use crate::Cube;
use rayon::prelude::*;

/// One internal cell: its level and integer index at that level (`0 ≤ index < 2^level`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Cell {
    pub level: u32,
    pub index: [u32; 3],
}

impl Cell {
    /// The map key of the cell at `level`, `index` (indices < 2^20).
    pub fn map_key(level: u32, index: [u32; 3]) -> u64 {
        (level as u64) << 60 | (index[0] as u64) << 40 | (index[1] as u64) << 20 | index[2] as u64
    }
}

/// The built tree before packing: internal cells breadth-first (by level, then in the
/// order their parents split) with the 27 samples of each one's child grid.
pub(crate) struct Tree {
    pub max_level: u32,
    pub cells: Vec<Cell>,
    /// `blocks[i]` = the child-grid samples of `cells[i]`, offset `(a, b, e)` at
    /// `a + 3 b + 9 e` ([`block_at`]).
    pub blocks: Vec<[f32; 27]>,
    /// Leaves at each level `0..=max_level`.
    pub leaves_per_level: Vec<u64>,
    /// Internal cells at each level `0..=max_level` (the last is always 0).
    pub internal_per_level: Vec<u64>,
}

/// Index of child-grid vertex `(a, b, e)` (each in `0..3`) in a block.
#[inline]
pub(crate) fn block_at(a: u32, b: u32, e: u32) -> usize {
    (a + 3 * b + 9 * e) as usize
}

/// Vertex key at some resolution (coordinates < 2^21).
fn vkey(v: [u32; 3]) -> u64 {
    v[0] as u64 | (v[1] as u64) << 21 | (v[2] as u64) << 42
}

fn vdecode(k: u64) -> [u32; 3] {
    let m = (1u64 << 21) - 1;
    [(k & m) as u32, ((k >> 21) & m) as u32, (k >> 42) as u32]
}

/// The samples of one level's vertices, sorted by key.
struct Samples {
    keys: Vec<u64>,
    values: Vec<f32>,
}

impl Samples {
    fn get(&self, v: [u32; 3]) -> Option<f32> {
        self.keys.binary_search(&vkey(v)).ok().map(|i| self.values[i])
    }
}

/// Builds the tree of `src` over `cube` (`max_level ≥ 1`, `eps` in world units).
/// `progress(levels_done, max_level)` is called after each level.
pub(crate) fn build_tree(
    src: &dyn DistanceSource,
    cube: &Cube,
    max_level: u32,
    eps: f32,
    progress: &(dyn Fn(u32, u32) + Sync),
) -> Tree {
    let corners: Vec<[u32; 3]> = (0..8).map(|i| [i & 1, (i >> 1) & 1, (i >> 2) & 1]).collect();
    let mut prev = Samples {
        keys: corners.iter().map(|&v| vkey(v)).collect(),
        values: corners.iter().map(|&v| src.signed_distance(cube.world(v, 0))).collect(),
    };
    let mut candidates: Vec<[u32; 3]> = vec![[0, 0, 0]];
    let mut tree = Tree {
        max_level,
        cells: Vec::new(),
        blocks: Vec::new(),
        leaves_per_level: vec![0; max_level as usize + 1],
        internal_per_level: vec![0; max_level as usize + 1],
    };
    for level in 0..max_level {
        // Every vertex of every candidate's child grid, once.
        let mut keys: Vec<u64> = candidates.par_iter().flat_map_iter(|c| grid27(*c).map(|(_, v)| vkey(v))).collect();
        keys.par_sort_unstable();
        keys.dedup();
        let res = level + 1;
        let values: Vec<f32> = keys.par_iter().map(|&k| sample(src, cube, vdecode(k), res, &prev)).collect();
        let here = Samples { keys, values };

        let half_diag = 3f32.sqrt() * 0.5 * cube.size / (1u64 << level) as f32;
        let blocks: Vec<Option<[f32; 27]>> = candidates
            .par_iter()
            .map(|&c| {
                let mut b = [0.0f32; 27];
                for (i, v) in grid27(c) {
                    // Present: `keys` holds every vertex of every candidate's grid.
                    b[i] = here.get(v).unwrap_or(f32::NAN);
                }
                let split = level == 0 || b[13].abs() <= half_diag || interpolation_error(&b) > eps;
                split.then_some(b)
            })
            .collect();
        let mut next = Vec::new();
        for (c, b) in candidates.iter().zip(blocks) {
            match b {
                Some(b) => {
                    tree.cells.push(Cell { level, index: *c });
                    tree.blocks.push(b);
                    tree.internal_per_level[level as usize] += 1;
                    for o in 0..8u32 {
                        next.push([2 * c[0] + (o & 1), 2 * c[1] + ((o >> 1) & 1), 2 * c[2] + (o >> 2)]);
                    }
                }
                None => tree.leaves_per_level[level as usize] += 1,
            }
        }
        prev = here;
        candidates = next;
        progress(level + 1, max_level);
    }
    tree.leaves_per_level[max_level as usize] = candidates.len() as u64;
    tree
}

/// The 27 vertices of cell `c`'s child grid (one level finer), with their block index.
fn grid27(c: [u32; 3]) -> impl Iterator<Item = (usize, [u32; 3])> {
    (0..27u32).map(move |i| {
        let (a, b, e) = (i % 3, (i / 3) % 3, i / 9);
        (i as usize, [2 * c[0] + a, 2 * c[1] + b, 2 * c[2] + e])
    })
}

/// Signed distance at vertex `v` of resolution `2^res`, its sign propagated from the
/// coarser vertex `v >> 1` where the ball of the unsigned distance allows (module docs).
fn sample(src: &dyn DistanceSource, cube: &Cube, v: [u32; 3], res: u32, prev: &Samples) -> f32 {
    let c = [v[0] >> 1, v[1] >> 1, v[2] >> 1];
    let coarse = prev.get(c);
    if v.iter().all(|x| x & 1 == 0) {
        // The same point as a coarser vertex: the same value, bit for bit, so every block
        // holding this position agrees.
        if let Some(d) = coarse {
            return d;
        }
    }
    let p = cube.world(v, res);
    let u = src.unsigned_distance(p);
    if let Some(dc) = coarse {
        let gap = (p - cube.world(c, res - 1)).length();
        if dc != 0.0 && u > gap * (1.0 + 1e-5) {
            return if dc < 0.0 { -u } else { u };
        }
    }
    if src.inside(p) {
        -u
    } else {
        u
    }
}

/// Largest gap between the samples of a child grid and the trilinear interpolant of its
/// 8 corners (the 19 non-corner vertices: centre, face centres, edge midpoints).
pub(crate) fn interpolation_error(b: &[f32; 27]) -> f32 {
    let mut worst = 0.0f32;
    for e in 0..3 {
        for bb in 0..3 {
            for a in 0..3 {
                if a != 1 && bb != 1 && e != 1 {
                    continue;
                }
                let t = [a as f32 * 0.5, bb as f32 * 0.5, e as f32 * 0.5];
                let corner = |x: u32, y: u32, z: u32| b[block_at(2 * x, 2 * y, 2 * z)];
                let interp = trilinear(&corner, t);
                worst = worst.max((interp - b[block_at(a, bb, e)]).abs());
            }
        }
    }
    worst
}

/// Trilinear interpolation of `corner(x, y, z)` (each 0 or 1) at local `t ∈ [0,1]^3`.
#[inline]
pub(crate) fn trilinear(corner: &impl Fn(u32, u32, u32) -> f32, t: [f32; 3]) -> f32 {
    let lerp = |a: f32, b: f32, s: f32| a + (b - a) * s;
    let x00 = lerp(corner(0, 0, 0), corner(1, 0, 0), t[0]);
    let x10 = lerp(corner(0, 1, 0), corner(1, 1, 0), t[0]);
    let x01 = lerp(corner(0, 0, 1), corner(1, 0, 1), t[0]);
    let x11 = lerp(corner(0, 1, 1), corner(1, 1, 1), t[0]);
    lerp(lerp(x00, x10, t[1]), lerp(x01, x11, t[1]), t[2])
}
