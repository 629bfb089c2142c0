//! The bench's presets beyond the standard measurements: seed 003's speed-up tables and
//! the dynamic-scene experiment. (seed000/002/004 need structure parameters: see
//! docs/bench.md.)

pub mod dynamic;
pub mod seed003;

use crate::variant::AccelVariant;
use dynray_accel::AccelKind;

/// The accelerated structure of a preset that compares one structure with brute force:
/// the first non-brute one asked for, else brute itself.
pub fn accelerated(accels: &[AccelVariant]) -> AccelVariant {
    accels
        .iter()
        .find(|a| a.kind != AccelKind::Brute)
        .or(accels.first())
        .cloned()
        .unwrap_or_else(|| AccelVariant::new(AccelKind::Brute))
}
