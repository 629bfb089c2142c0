//! Scene model of dynray and its loaders.
#![deny(missing_docs)]
// Loaders read untrusted files; nothing here needs unsafe, and this keeps it so.
#![forbid(unsafe_code)]

mod actor;
pub mod animation;
mod bsdf;
mod default_view;
pub mod demo;
mod error;
mod field;
pub mod formats;
mod frame;
mod load;
mod model;
mod physics;
pub mod reference;
mod report;
pub mod scn;
mod shading;
pub mod shapes;
pub mod texture;
mod transform;

pub use actor::{Actor, Motion};
pub use animation::{Animation, Timeline};
pub use bsdf::{Bsdf, BsdfKind, Microfacet, Roughness};
pub use error::LoadError;
pub use field::FieldPlacement;
pub use frame::{ActorState, Frame};
pub use load::{load_file, load_file_report, load_file_unshaded, load_mesh, FileFormat};
pub use model::{Camera, Clip, Color, Environment, Finish, Light, LightKind, Material, Projection, Scene, Settings};
pub use physics::{ElasticParams, PhysicsSettings};
pub use report::{LoadReport, Warning};
pub use scn::{load_scn, load_scn_report, parse_scn_str};
pub use shading::{NormalSource, Shading, DEFAULT_CREASE_DEG};
pub use texture::{Texture, TextureRef};
pub use transform::Transform;
