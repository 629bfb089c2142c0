//! `dynray info --gpu`: the machine's GPU adapters, and whether the chosen one's kernels
//! return the CPU's hits (docs/gpu.md, "Exactness").

use anyhow::{bail, Result};
use dynray_gpu::{list_adapters, GpuContext, GpuOptions, SOFTWARE_DRIVER_HINT};
use std::io::Write;
use std::sync::Arc;

/// Writes the adapter list and the self-check; an error (exit 1) when there is no adapter.
pub fn write(out: &mut impl Write, adapter: Option<&str>) -> Result<()> {
    let adapters = list_adapters();
    if adapters.is_empty() {
        bail!("no GPU adapter found (Vulkan); {SOFTWARE_DRIVER_HINT}");
    }
    for (i, a) in adapters.iter().enumerate() {
        let mib = |b: u64| b as f64 / (1 << 20) as f64;
        writeln!(out, "adapter {i}   {} ({}, {})", a.name, a.device_type, a.backend)?;
        writeln!(out, "  driver      {}", if a.driver.is_empty() { "(not reported)" } else { &a.driver })?;
        writeln!(out, "  f64         {}", if a.f64 { "yes (exact kernels)" } else { "no (f32 kernels)" })?;
        let sg = if a.subgroups {
            format!("yes, size {}–{}", a.subgroup_sizes.0, a.subgroup_sizes.1)
        } else {
            "no".into()
        };
        writeln!(out, "  subgroups   {sg}")?;
        writeln!(out, "  timestamps  {}", if a.timestamps { "yes" } else { "no" })?;
        writeln!(
            out,
            "  storage     {:.0} MiB per binding, {:.0} MiB per buffer",
            mib(a.max_storage_binding),
            mib(a.max_buffer)
        )?;
        writeln!(out, "  workgroup   {} invocations at most", a.max_workgroup_invocations)?;
    }
    out.flush()?;
    let ctx = Arc::new(GpuContext::new(&GpuOptions { adapter: adapter.map(str::to_string), ..Default::default() })?);
    let e = ctx.exactness();
    writeln!(out, "chosen      {} ({} kernels)", ctx.adapter().name, ctx.precision().name())?;
    let verdict =
        if e.is_exact() { "every hit equals the CPU's".to_string() } else { format!("{} differ", e.mismatches) };
    writeln!(out, "self-check  {} hard rays: {verdict}", e.rays)?;
    Ok(())
}
