//! Scene model of dynray and its loaders.
#![deny(missing_docs)]

pub mod demo;
mod error;
pub mod gltf_loader;
mod load;
mod model;
mod mtl;
pub mod obj;
pub mod ply;
pub mod scn;
pub mod shapes;

pub use error::LoadError;
pub use load::{load_file, load_file_report, FileFormat, LoadReport, Warning};
pub use model::{
    Actor, Camera, Color, Environment, Finish, Frame, Light, LightKind, Material, Projection, Scene, Settings,
};
pub use scn::{load_scn, parse_scn_str};
