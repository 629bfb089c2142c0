//! Scene model of dynray and its loaders.
#![deny(missing_docs)]

pub mod demo;
mod error;
mod model;
pub mod ply;
pub mod scn;
pub mod shapes;

pub use error::LoadError;
pub use model::{
    Actor, Camera, Color, Environment, Finish, Frame, Light, LightKind, Material, Projection, Scene, Settings,
};
pub use scn::{load_scn, parse_scn_str};
