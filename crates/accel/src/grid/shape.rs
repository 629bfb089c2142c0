//! The grid's geometry: resolution, cell planes and the cell-index arithmetic shared by
//! the builder and the traversal, so both agree on where every cell is.

use dynray_geom::{Aabb, Vec3};

/// Fraction of a cell by which insertion is widened on every side: a triangle within
/// this distance of a cell is inserted into it too. This absorbs the rounding of the
/// traversal's cell arithmetic (far below 1e-3 of a cell for any scene whose cells are
/// wider than ~1000 ulps of its coordinates) at the cost of a few extra references.
pub const INSERT_SLACK: f32 = 1.0e-3;

/// Resolution and placement of a uniform grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridShape {
    /// The scene box; cells tile it exactly.
    pub bounds: Aabb,
    /// Cells per axis (each ≥ 1).
    pub res: [u32; 3],
    /// Cell size per axis (0 on a flat axis, which then has one cell).
    pub cell: Vec3,
    /// `1 / cell` per axis, or 0 on a flat axis so index arithmetic yields cell 0.
    pub inv_cell: Vec3,
}

impl GridShape {
    /// A grid of `res` cells over `bounds`.
    pub fn new(bounds: Aabb, res: [u32; 3]) -> Self {
        let ext = bounds.extent();
        let mut cell = Vec3::ZERO;
        let mut inv_cell = Vec3::ZERO;
        for a in 0..3 {
            cell[a] = ext[a] / res[a] as f32;
            inv_cell[a] = if cell[a] > 0.0 && cell[a].is_finite() { 1.0 / cell[a] } else { 0.0 };
        }
        Self { bounds, res, cell, inv_cell }
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.res.iter().map(|&r| r as usize).product()
    }

    /// Flat index of cell `(x, y, z)`.
    #[inline(always)]
    pub fn index(&self, c: [u32; 3]) -> usize {
        (c[2] as usize * self.res[1] as usize + c[1] as usize) * self.res[0] as usize + c[0] as usize
    }

    /// Coordinate of the `k`-th plane on axis `a` (`k = 0..=res[a]`); the last one is
    /// exactly the box's maximum so the outer faces agree with the scene box.
    #[inline(always)]
    pub fn plane(&self, a: usize, k: u32) -> f32 {
        if k >= self.res[a] {
            self.bounds.max[a]
        } else {
            self.bounds.min[a] + k as f32 * self.cell[a]
        }
    }

    /// Cell index on axis `a` of coordinate `x`, after moving it by `bias` cells,
    /// clamped into the grid (NaN gives 0).
    #[inline(always)]
    pub fn cell_of(&self, a: usize, x: f32, bias: f32) -> u32 {
        let f = ((x - self.bounds.min[a]) * self.inv_cell[a] + bias).floor();
        // `as` saturates and maps NaN to 0.
        (f as i64).clamp(0, self.res[a] as i64 - 1) as u32
    }

    /// Inclusive cell range of a box, widened by [`INSERT_SLACK`] cells on each side.
    pub fn range(&self, b: &Aabb) -> ([u32; 3], [u32; 3]) {
        let mut lo = [0; 3];
        let mut hi = [0; 3];
        for a in 0..3 {
            lo[a] = self.cell_of(a, b.min[a], -INSERT_SLACK);
            hi[a] = self.cell_of(a, b.max[a], INSERT_SLACK);
        }
        (lo, hi)
    }

    /// Centre and half-size (widened by [`INSERT_SLACK`]) of a cell, in f64 for the
    /// overlap test.
    pub fn cell_box(&self, c: [u32; 3]) -> ([f64; 3], [f64; 3]) {
        let mut centre = [0.0; 3];
        let mut half = [0.0; 3];
        let max_cell = self.cell.max_element() as f64;
        for a in 0..3 {
            let lo = self.plane(a, c[a]) as f64;
            let hi = self.plane(a, c[a] + 1) as f64;
            centre[a] = 0.5 * (lo + hi);
            // A flat axis (one cell of size 0) still gets a sliver of slack.
            half[a] = 0.5 * (hi - lo) + INSERT_SLACK as f64 * (self.cell[a] as f64).max(1e-3 * max_cell);
        }
        (centre, half)
    }
}
