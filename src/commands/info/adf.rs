//! `dynray info FILE.adf`: a distance field's figures beside the seed's.

use super::super::thousands;
use anyhow::Result;
use dynray_adf::{Adf, FORMAT_VERSION};
use std::io::Write;
use std::path::Path;

fn kib(bytes: u64) -> String {
    format!("{:.1} KiB", bytes as f64 / 1024.0)
}

fn saving(ours: u64, theirs: u64) -> String {
    format!("{:.1} %", 100.0 * (1.0 - ours as f64 / theirs.max(1) as f64))
}

/// `dynray info FILE.adf`.
pub fn write(out: &mut impl Write, file: &Path) -> Result<()> {
    let adf = Adf::load(file)?;
    let i = adf.info();
    let (b, c) = (adf.source_bounds(), adf.cube());
    let m = adf.memory();
    let h = adf.hash();
    let n = adf.internal_cells();
    let per_level = |v: &[u64]| v.iter().map(|&x| thousands(x as usize)).collect::<Vec<_>>().join(" ");
    writeln!(out, "file        {}", file.display())?;
    writeln!(out, "format      dynray distance field, version {FORMAT_VERSION}")?;
    writeln!(out, "source      {} triangles", thousands(i.triangles as usize))?;
    writeln!(
        out,
        "bounds      [{:.6}, {:.6}, {:.6}] .. [{:.6}, {:.6}, {:.6}]",
        b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
    )?;
    writeln!(out, "cube        origin [{:.6}, {:.6}, {:.6}], edge {:.6}", c.origin.x, c.origin.y, c.origin.z, c.size)?;
    writeln!(
        out,
        "levels      0..={} (finest cell {:.6})",
        adf.max_level(),
        c.size / (1u32 << adf.max_level()) as f32
    )?;
    writeln!(
        out,
        "cells       {} ({} internal, {} leaves)",
        thousands(adf.cells() as usize),
        thousands(n as usize),
        thousands((adf.cells() - n) as usize)
    )?;
    writeln!(out, "internal    per level {}", per_level(&i.internal_per_level))?;
    writeln!(out, "leaves      per level {}", per_level(&i.leaves_per_level))?;
    writeln!(
        out,
        "field       epsilon {:.3e}, Lipschitz bound {:.3} (global), {} samples set by the T-junction rule",
        adf.epsilon(),
        adf.lipschitz(),
        thousands(i.constrained_samples as usize)
    )?;
    let t = adf.voxels().size();
    writeln!(
        out,
        "voxels      {}x{}x{} texels, {} ({} in the {} blocks)",
        t[0],
        t[1],
        t[2],
        kib(m.voxel_bytes),
        kib(m.voxel_block_bytes),
        thousands(n as usize)
    )?;
    writeln!(
        out,
        "cell table  H {}^3 entries of 8 bytes, {} ({:.1} % full)",
        h.table_edge(),
        kib(m.cell_table_bytes),
        100.0 * n as f64 / (h.table_edge() as f64).powi(3)
    )?;
    writeln!(out, "offsets     Φ {}^3 entries of 8 bytes, {}", h.offset_edge(), kib(m.offset_table_bytes))?;
    writeln!(
        out,
        "step bounds {} floats, {} (per-cell Lipschitz bounds of the sphere tracer; not in the seed)",
        thousands(n as usize),
        kib(m.step_bound_bytes)
    )?;
    writeln!(out, "memory      {} in all", kib(m.total_bytes()))?;
    writeln!(
        out,
        "full grid   {}^3 samples, {}: the field takes {:.2} % of it",
        (1u64 << adf.max_level()) + 1,
        kib(m.full_grid_bytes),
        100.0 * m.total_bytes() as f64 / m.full_grid_bytes.max(1) as f64
    )?;
    writeln!(
        out,
        "classic ADF voxels {} (8 per cell): the 3x3x3 sibling blocks save {} (seed: ~57 %)",
        kib(m.classic_voxel_bytes),
        saving(m.voxel_block_bytes, m.classic_voxel_bytes)
    )?;
    writeln!(
        out,
        "classic ADF cells  {} (one per cell): H of internal cells saves {} ({} with its empty slots; seed: up to 87 %)",
        kib(m.classic_cell_bytes),
        saving(8 * n, m.classic_cell_bytes),
        saving(m.cell_table_bytes, m.classic_cell_bytes)
    )?;
    writeln!(
        out,
        "classic ADF total  {}: the field takes {:.1} % of it",
        kib(m.classic_bytes()),
        100.0 * m.total_bytes() as f64 / m.classic_bytes().max(1) as f64
    )?;
    writeln!(out, "build       {:.1} ms", i.build_ms)?;
    writeln!(out, "hash        {:.1} ms, {} attempt(s)", i.hash_ms, h.attempts())?;
    Ok(())
}
