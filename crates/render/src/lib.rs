//! Rendering of dynray: cameras, samplers, the integrators (seed 003's Whitted tracer,
//! seed 004's cumulative wavefront form of it, and a physically based path tracer) behind
//! one [`Integrator`] trait, the scene-level intersector that answers with surface hits,
//! the accumulating film, AOVs and image output.
//!
//! The data path is `Frame` + an acceleration structure -> [`SceneIntersector`] (surface
//! hits) -> an [`Integrator`] per pixel sample, driven by the one render loop
//! [`render_with`] -> [`Film`] -> [`write_image`] (PNG/BMP 8-bit sRGB, EXR linear f32,
//! chosen by the file extension) or [`write_aov`].
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod actors;
mod aov;
mod camera;
mod cone;
mod cumulative;
mod error;
mod facing;
mod film;
mod integrator;
mod intersector;
mod output;
mod path;
mod render;
mod sampler;
mod shading;
mod shadow;
mod surface;
mod whitted;

pub use actors::{actor_geometry, build_live_scene};
pub use aov::{Aov, AovIntegrator};
pub use camera::{CameraBasis, CameraRays};
pub use cone::RayCone;
pub use cumulative::{Cumulative, DEFAULT_BRANCH_DEPTH, MAX_LIVE_PATHS};
pub use error::RenderError;
pub use facing::{Facing, MIN_EXIT_COS};
pub use film::{linear_to_srgb8, Film};
pub use integrator::{Integrator, IntegratorKind, IntegratorParams, RayCounts};
pub use intersector::{Geometry, SceneIntersector, TriangleGeometry};
pub use output::{write_aov, write_image, OutputFormat};
pub use path::{
    BsdfDesc, EmitterDesc, EmitterTable, LobeDesc, PathTracer, Strategy as PathStrategy, MAX_PATH_DEPTH, RR_DEPTH,
};
pub use render::{render, render_aov, render_with, PassCallback, RenderOptions, RenderStats, BATCH_RAYS};
pub use sampler::{choice_random, Sampler};
pub use shading::MAX_LEVEL_CAP;
pub use shadow::{filter as shadow_filter, Shadows, MAX_SHADOW_CROSSINGS};
pub use surface::{GeometryRef, SurfaceHit};
pub use whitted::Whitted;

/// Largest image edge, in pixels, the renderer accepts from a user (16384² pixels hold
/// 4 GiB of film), so a typo cannot ask for terabytes.
pub const MAX_IMAGE_EDGE: u32 = 1 << 14;

/// Memory a render needs per pixel, for the budget check before one starts
/// (`dynray_geom::budget`): the film (16 bytes), the film a pass or tile merges into
/// it (16), and the encoded copy the output writer makes (8-bit sRGB, or the EXR's f32
/// rows: up to 12), rounded up.
pub const IMAGE_BYTES_PER_PIXEL: u64 = 48;

/// Checks that a `width` × `height` render fits the memory budget; the error says what
/// was asked and the limit.
pub fn check_image_budget(width: u32, height: u32) -> Result<(), String> {
    let bytes = width as u64 * height as u64 * IMAGE_BYTES_PER_PIXEL;
    dynray_geom::budget::check(&format!("a {width} × {height} image"), bytes)
}
