//! Scene model of dynray and its loaders.
#![deny(missing_docs)]

pub mod demo;
mod error;
pub mod formats;
mod load;
mod model;
pub mod scn;
pub mod shapes;

pub use error::LoadError;
pub use load::{load_file, load_file_report, FileFormat, LoadReport, Warning};
pub use model::{
    Actor, Camera, Color, Environment, Finish, Frame, Light, LightKind, Material, Projection, Scene, Settings,
};
pub use scn::{load_scn, parse_scn_str};

/// The PLY reader under its old path. The canonical path is [`formats::ply`]; this stays
/// because crates/accel's tests and benches (worked on in another branch) still name
/// `dynray_scene::ply`. Remove it once they move.
#[doc(hidden)]
pub use formats::ply;
