//! Physics checkpoints of an animation run on disk: `OUT/checkpoints/state_NNNN.bin`, the
//! simulation's state at frame `NNNN` ([`dynray_sim::World::checkpoint`]), written whole
//! (temporary file, then rename) so a reader never sees half of one, whichever task of an
//! array job wrote it.

use crate::frame_step::Stage;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// The folder of checkpoints inside an animation's output folder.
pub fn dir(out: &Path) -> PathBuf {
    out.join("checkpoints")
}

/// The checkpoint of frame `k`.
pub fn path(out: &Path, k: u32) -> PathBuf {
    dir(out).join(format!("state_{k:04}.bin"))
}

/// The frame number of a checkpoint's file name, `state_NNNN.bin`.
fn frame_of(name: &str) -> Option<u32> {
    let digits = name.strip_prefix("state_")?.strip_suffix(".bin")?;
    (digits.len() >= 4 && digits.bytes().all(|b| b.is_ascii_digit())).then(|| digits.parse().ok()).flatten()
}

/// The latest frame at or before `k` with a checkpoint in `out`, if any.
pub fn nearest(out: &Path, k: u32) -> Option<u32> {
    let entries = std::fs::read_dir(dir(out)).ok()?;
    entries.filter_map(|e| frame_of(e.ok()?.file_name().to_str()?)).filter(|&c| c <= k).max()
}

/// Restores `stage`'s simulation from frame `c`'s checkpoint.
pub fn restore(stage: &mut Stage, out: &Path, c: u32) -> Result<()> {
    let p = path(out, c);
    let bytes = dynray_geom::file::read_back(&p).with_context(|| format!("{}: cannot read", p.display()))?;
    stage.restore_physics(&bytes).with_context(|| {
        format!("{}: cannot continue from it (delete the checkpoints folder to simulate from time 0)", p.display())
    })
}

/// Writes the simulation's state now as frame `k`'s checkpoint, unless one is there.
pub fn save(stage: &Stage, out: &Path, k: u32) -> Result<()> {
    let p = path(out, k);
    if p.is_file() {
        return Ok(());
    }
    let Some(world) = stage.world() else { return Ok(()) };
    std::fs::create_dir_all(dir(out)).with_context(|| format!("{}: cannot create", dir(out).display()))?;
    crate::output::write_atomic(&p, &world.checkpoint())
}

#[cfg(test)]
mod tests {
    use super::frame_of;

    #[test]
    fn only_checkpoint_names_parse() {
        assert_eq!(frame_of("state_0007.bin"), Some(7));
        assert_eq!(frame_of("state_12345.bin"), Some(12345));
        for other in ["state_7.bin", "state_0007.bin.tmp", ".tmpX", "state_00a7.bin", "frame_0007.png"] {
            assert_eq!(frame_of(other), None, "{other}");
        }
    }
}
