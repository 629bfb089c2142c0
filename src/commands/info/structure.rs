//! `dynray info FILE --accel SPEC`: what the structure built over the file looks like.

use super::super::thousands;
use anyhow::{Context, Result};
use dynray_accel::AccelSpec;
use dynray_geom::TriangleMesh;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

/// Builds `spec` over `mesh` (the file's frame 0) and prints its figures.
pub fn write(out: &mut impl Write, file: &Path, mesh: &TriangleMesh, spec: &AccelSpec) -> Result<()> {
    let t0 = Instant::now();
    let accel = spec.build(mesh, None).with_context(|| format!("{}: cannot build {spec}", file.display()))?;
    let build_ms = t0.elapsed().as_secs_f64() * 1e3;
    let s = accel.stats();
    writeln!(out)?;
    writeln!(out, "structure   {}", accel.name())?;
    writeln!(out, "build       {build_ms:.1} ms")?;
    writeln!(out, "nodes       {}", thousands(s.nodes))?;
    writeln!(out, "leaves      {}", thousands(s.leaves))?;
    writeln!(out, "max depth   {}", s.max_depth)?;
    let tris = mesh.triangle_count().max(1);
    writeln!(
        out,
        "prim refs   {} ({:.3} per triangle)",
        thousands(s.primitive_refs),
        s.primitive_refs as f64 / tris as f64
    )?;
    if s.leaves > 0 {
        writeln!(out, "prims/leaf  {:.2} (mean)", s.primitive_refs as f64 / s.leaves as f64)?;
    }
    if let Some(sah) = s.sah_cost {
        writeln!(out, "SAH cost    {sah:.2}")?;
    }
    writeln!(
        out,
        "memory      {} bytes ({:.2} MiB)",
        thousands(s.memory_bytes),
        s.memory_bytes as f64 / (1 << 20) as f64
    )?;
    for (k, v) in &s.extra {
        writeln!(out, "{k:<11} {v}")?;
    }
    if !s.leaf_sizes.is_empty() {
        writeln!(out, "leaf sizes  (triangles: leaves)")?;
        let last = s.leaf_sizes.len() - 1;
        for (n, &count) in s.leaf_sizes.iter().enumerate().filter(|(_, &c)| c > 0) {
            let label = if n == last { format!("{n}+") } else { n.to_string() };
            writeln!(out, "  {label:>4}: {}", thousands(count))?;
        }
    }
    out.flush()?;
    Ok(())
}
