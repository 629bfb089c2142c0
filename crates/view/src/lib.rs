//! `dynray view`: the seeds' real-time window. A scene is ray traced continuously through
//! the engine's live job ([`dynray_engine::Live`]: the frame step, then one progressive
//! frame of samples), shown with wgpu in a winit window, and driven by the mouse, the
//! keyboard, an egui panel or a `--script` (docs/view.md).
//!
//! - [`app`]: the window's event loop and the frame it runs;
//! - [`panel`]: the egui controls and statistics;
//! - [`present`]: the image, the panel and screenshots on the GPU;
//! - [`navigate`]: orbit, pan, zoom and fly;
//! - [`views`]: the heat map and the structure's boxes;
//! - [`script`], [`keys`], [`timings`], [`record`]: scripted input, key table, per-frame
//!   CSV, the window recorded as a GIF.

#![deny(missing_docs)]

pub mod app;
pub mod keys;
pub mod navigate;
pub mod panel;
pub mod present;
pub mod record;
pub mod script;
pub mod timings;
pub mod views;

pub use app::{run, ViewOptions};
pub use views::Show;
