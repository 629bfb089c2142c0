//! The measurement lab behind `dynray bench`: builds every asked structure over every asked
//! scene, times builds and ray passes, measures traversal work and memory, renders, checks
//! every structure against brute force in the same run, and writes `report.md`,
//! `report.json`, charts and heat maps (docs/bench.md describes all of it).
#![deny(missing_docs)]

pub mod carousel;
pub mod charts;
#[cfg(feature = "compare")]
pub mod compare;
pub mod config;
pub mod fonts;
pub mod format;
pub mod framing;
pub mod gpu;
pub mod heatmap;
pub mod legend;
pub mod line_chart;
pub mod machine;
pub mod markdown;
pub mod measure;
pub mod output;
pub mod plan;
pub mod presets;
pub mod progress;
pub mod rays;
pub mod report;
pub mod results;
pub mod run;
pub mod scenes;
pub mod variant;

pub use config::{BenchConfig, Preset};
pub use dynray_accel::AccelSpec;
pub use framing::Framing;
pub use rays::RayKind;
pub use report::Report;
pub use run::run;
pub use variant::parse_accels;
