//! The bench's presets beyond the standard measurements: each seed's experiment
//! (seed000, seed001, seed002, seed003, seed004), the dynamic-scene experiment and the path
//! tracer's measurements.

pub mod dynamic;
pub mod experiment;
pub mod path;
pub mod seed000;
pub mod seed000_physics;
pub mod seed001;
pub mod seed002;
pub mod seed003;
pub mod seed004;
pub mod seed004_renderers;
pub mod study;

use dynray_accel::AccelKind;
use dynray_accel::AccelSpec;

/// The accelerated structure of a preset that compares one structure with brute force:
/// the first non-brute one asked for, else brute itself.
pub fn accelerated(accels: &[AccelSpec]) -> AccelSpec {
    accels
        .iter()
        .find(|a| a.kind != AccelKind::Brute)
        .or(accels.first())
        .cloned()
        .unwrap_or_else(|| AccelSpec::new(AccelKind::Brute))
}
