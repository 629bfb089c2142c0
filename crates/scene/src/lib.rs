//! Scene model of dynray and its loaders.
#![deny(missing_docs)]

mod error;
pub mod ply;

pub use error::LoadError;
