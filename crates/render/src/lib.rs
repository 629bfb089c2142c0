//! Rendering of dynray: cameras, the Whitted integrator of seed 003, the film and image
//! output.
//!
//! The data path is `Frame` + an acceleration structure -> [`render`] -> [`Film`] ->
//! [`write_image`] (PNG/BMP 8-bit sRGB, EXR linear f32, chosen by the file extension).
#![deny(missing_docs)]

mod camera;
mod error;
mod film;
mod output;
mod render;
mod whitted;

pub use camera::CameraRays;
pub use error::RenderError;
pub use film::{linear_to_srgb8, Film};
pub use output::{write_image, OutputFormat};
pub use render::{render, RenderOptions, RenderStats};
pub use whitted::{RayCounts, Whitted, MAX_LEVEL_CAP};
