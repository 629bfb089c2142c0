//! Grid construction: resolution from the density heuristic, then triangle references
//! in one flat array with CSR offsets per cell.
//!
//! Two parallel passes over the triangles: the first only counts the cells each one
//! overlaps (so an oversized grid is detected, and coarsened, before anything big is
//! allocated), the second emits `(cell, triangle)` pairs in triangle order, which a
//! stable counting sort turns into per-cell lists sorted by triangle index. The output
//! is therefore the same whatever the number of threads.

use super::params::GridParams;
use super::shape::GridShape;
use crate::BuildError;
use dynray_geom::{Aabb, Triangle};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// Cells and references of a built grid.
pub(super) struct Built {
    pub shape: GridShape,
    /// `refs[offsets[c]..offsets[c + 1]]` are the triangles of cell `c`.
    pub offsets: Vec<u32>,
    pub refs: Vec<u32>,
}

/// Resolution from the density heuristic: the longest axis gets `λ·N^(1/3)` cells, the
/// others in proportion to their length, then all are scaled to fit `max_cells`.
pub(super) fn resolution(bounds: &Aabb, n: usize, p: &GridParams) -> [u32; 3] {
    let ext = bounds.extent();
    let longest = ext.max_element();
    if !(longest > 0.0 && longest.is_finite()) {
        return [1; 3];
    }
    let along_longest = (p.density as f64 * (n as f64).cbrt()).max(1.0);
    let mut scale = along_longest / longest as f64;
    loop {
        let res = [0, 1, 2].map(|a| ((ext[a] as f64 * scale).floor() as u64).clamp(1, 1 << 20) as u32);
        let cells: u64 = res.iter().map(|&r| r as u64).product();
        if cells <= p.max_cells as u64 || res == [1; 3] {
            return res;
        }
        scale *= 0.95 * (p.max_cells as f64 / cells as f64).cbrt();
    }
}

/// The cells a triangle goes into, in x-fastest order.
fn cells_of<'a>(shape: &'a GridShape, tri: &'a Triangle, exact: bool) -> impl Iterator<Item = u32> + 'a {
    let (lo, hi) = shape.range(&tri.bounds());
    // A triangle whose widened box spans a single cell surely touches it: skip the test.
    let single = lo == hi;
    (lo[2]..=hi[2]).flat_map(move |z| {
        (lo[1]..=hi[1]).flat_map(move |y| {
            (lo[0]..=hi[0]).filter_map(move |x| {
                let c = [x, y, z];
                let keep = single || !exact || {
                    let (centre, half) = shape.cell_box(c);
                    tri.overlaps_box(centre, half)
                };
                keep.then(|| shape.index(c) as u32)
            })
        })
    })
}

/// True when inserting every triangle into `shape` stays within `budget` references.
/// The bounding-box count (O(1) per triangle) settles most cases; otherwise the exact
/// count runs with a shared counter and gives up as soon as the budget is exceeded, so
/// a hopeless resolution costs about `budget` overlap tests, not the full insertion.
fn fits(shape: &GridShape, tris: &[Triangle], exact: bool, budget: u64) -> bool {
    let box_total: u64 = tris
        .par_iter()
        .map(|t| {
            let (lo, hi) = shape.range(&t.bounds());
            (0..3).map(|a| (hi[a] - lo[a] + 1) as u64).product::<u64>()
        })
        .sum();
    if box_total <= budget {
        return true;
    }
    if !exact {
        return false;
    }
    let total = AtomicU64::new(0);
    tris.par_iter()
        .try_for_each(|t| {
            let c = cells_of(shape, t, true).count() as u64;
            if total.fetch_add(c, Ordering::Relaxed) + c > budget {
                Err(())
            } else {
                Ok(())
            }
        })
        .is_ok()
}

/// Builds the grid over `tris` (mesh order) whose union is `bounds`.
pub(super) fn build(tris: &[Triangle], bounds: Aabb, p: &GridParams) -> Result<Built, BuildError> {
    let n = tris.len();
    let budget = (p.max_refs_per_triangle as u64).saturating_mul(n as u64).min(u32::MAX as u64);
    let mut res = resolution(&bounds, n, p);
    let shape = loop {
        let shape = GridShape::new(bounds, res);
        if res == [1; 3] || fits(&shape, tris, p.exact_overlap, budget) {
            break shape;
        }
        res = res.map(|r| (r / 2).max(1));
    };
    let pairs: Vec<(u32, u32)> = tris
        .par_iter()
        .enumerate()
        .flat_map_iter(|(i, t)| cells_of(&shape, t, p.exact_overlap).map(move |c| (c, i as u32)))
        .collect();
    if pairs.len() > u32::MAX as usize {
        return Err(BuildError::Limit(format!("the grid would hold {} references; offsets are u32", pairs.len())));
    }
    let cells = shape.cells();
    let mut offsets = vec![0u32; cells + 1];
    for &(c, _) in &pairs {
        offsets[c as usize + 1] += 1;
    }
    for c in 0..cells {
        offsets[c + 1] += offsets[c];
    }
    let mut fill = offsets.clone();
    let mut refs = vec![0u32; pairs.len()];
    for &(c, t) in &pairs {
        refs[fill[c as usize] as usize] = t;
        fill[c as usize] += 1;
    }
    Ok(Built { shape, offsets, refs })
}
