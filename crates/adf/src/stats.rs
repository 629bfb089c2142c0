//! Memory of the field against the two layouts the seed compares with (§3.1–3.2): a
//! full grid at the finest resolution, and the classic pointer ADF that keeps 8 voxels
//! in every cell and a record for every cell.

use crate::Adf;

/// Byte counts of the field and of the layouts it replaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryFigures {
    /// Voxel texture as allocated (27 texels per block slot, 4 bytes each).
    pub voxel_bytes: u64,
    /// 27 voxels per internal cell: the blocks alone, without the texture's unused slots.
    pub voxel_block_bytes: u64,
    /// H as allocated (`m̄³` entries of 8 bytes).
    pub cell_table_bytes: u64,
    /// Φ (`r̄³` entries of 8 bytes).
    pub offset_table_bytes: u64,
    /// The sphere tracer's per-cell Lipschitz bounds (4 bytes per internal cell; not in
    /// the seed's layout).
    pub step_bound_bytes: u64,
    /// A full grid of 4-byte samples at the finest resolution, `(2^L + 1)^3`.
    pub full_grid_bytes: u64,
    /// The classic ADF's voxels: 8 of 4 bytes in every non-root cell.
    pub classic_voxel_bytes: u64,
    /// The classic ADF's cell records: one per cell (8 bytes: identifier and pointer),
    /// where H stores internal cells only.
    pub classic_cell_bytes: u64,
}

impl MemoryFigures {
    /// Everything the field stores.
    pub fn total_bytes(&self) -> u64 {
        self.voxel_bytes + self.cell_table_bytes + self.offset_table_bytes + self.step_bound_bytes
    }

    /// The classic ADF's total.
    pub fn classic_bytes(&self) -> u64 {
        self.classic_voxel_bytes + self.classic_cell_bytes
    }
}

impl Adf {
    /// The memory figures of `dynray info`.
    pub fn memory(&self) -> MemoryFigures {
        let n = self.internal_cells();
        let cells = self.cells();
        let (table, phi) = self.hash.memory_bytes();
        let side = (1u64 << self.max_level) + 1;
        MemoryFigures {
            voxel_bytes: self.voxels.memory_bytes() as u64,
            voxel_block_bytes: 27 * 4 * n,
            cell_table_bytes: table as u64,
            offset_table_bytes: phi as u64,
            step_bound_bytes: 4 * self.cell_lipschitz.len() as u64,
            full_grid_bytes: 4 * side * side * side,
            classic_voxel_bytes: 8 * 4 * cells.saturating_sub(1),
            classic_cell_bytes: 8 * cells,
        }
    }
}
