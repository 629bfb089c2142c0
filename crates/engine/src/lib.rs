//! dynray's engine layer: what every front end — the command line, the Python package,
//! the bench and the viewer — shares to go from a file to images, frames or hits over
//! time (docs/architecture.md, "The engine").
//!
//! - [`Loaded`]: a scene, mesh or distance-field file (or the demo), unshaded, with its
//!   warnings; [`TimeChoice`]: the one definition of an instant and of frame 0.
//! - [`Stage`] and [`FrameStep`]: pose → physics → structure update, one `advance_to(t)`
//!   per frame.
//! - [`Tracer`]: the seam over backends (the CPU's structures in any scene layout with
//!   distance fields beside the triangles, the GPU's device BVH), both following the one
//!   update policy ([`dynray_accel::PolicyState`]).
//! - [`jobs`]: render, animate and trace, built from plain option structs, every option
//!   combination checked before any work, progress through callbacks; [`Live`], the
//!   viewer's progressive frames over the same render job. [`merge_hits`] joins the
//!   trace job's row slices (`trace-rays --rows`) into one run's archive.
//!
//! Errors are `anyhow` chains: the engine adds file, frame and option context to the
//! typed errors of the crates below it, and front ends print the chain (the binary) or
//! map it (Python, by the `std::io::Error` or `LoadError` inside).

#![deny(missing_docs)]

pub mod backend;
pub mod camera_text;
pub mod fields;
pub mod format;
pub mod frame_step;
pub mod heat;
pub mod hit_file;
pub mod hit_merge;
pub mod jobs;
pub mod load;
pub mod output;
pub mod timeline;
pub mod tracer;

pub use backend::BackendChoice;
pub use camera_text::{camera_text, parse_camera};
pub use fields::Fields;
pub use frame_step::{FrameSettings, FrameStep, PoseTiming, Stage, StepReport};
pub use hit_merge::merge_hits;
pub use jobs::animate::{AnimateEvent, AnimateJob};
pub use jobs::live::{Live, LiveFrame};
pub use jobs::render::{RenderJob, Rendered};
pub use jobs::trace::{Query, TraceJob};
pub use load::Loaded;
pub use timeline::TimeChoice;
pub use tracer::Tracer;
