//! `dynray info --structures`: the structure table (`dynray_accel::DESCRIPTORS`), one
//! line per `--accel` name.

use anyhow::Result;
use dynray_accel::DESCRIPTORS;
use std::io::Write;

/// Prints every structure: its name, whether its update refits, whether the GPU traces
/// it, its presets and what it is.
pub fn write(out: &mut impl Write) -> Result<()> {
    writeln!(out, "{:<15} {:<7} {:<4} {:<24} what it is", "--accel", "update", "gpu", "presets")?;
    for d in DESCRIPTORS {
        let update = if d.refits { "refit" } else { "rebuild" };
        let gpu = if d.gpu { "yes" } else { "no" };
        let presets = (d.presets)().join(",");
        writeln!(out, "{:<15} {update:<7} {gpu:<4} {presets:<24} {}", d.name, d.summary)?;
    }
    Ok(())
}
