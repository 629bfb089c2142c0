//! Acceleration structures of dynray behind one interface, and the brute-force oracle.
//!
//! Every structure implements [`Accel`]: built from a [`TriangleMesh`], it answers
//! closest-hit ([`Accel::intersect`]) and any-hit ([`Accel::occluded`]) queries that are
//! bit-identical to [`Brute`]'s, because all of them call the one triangle test of
//! `dynray-geom` and break `t` ties towards the lower triangle index.
#![deny(missing_docs)]

mod accel;
pub mod apit;
pub mod brute;
mod counters;
mod error;
mod registry;

pub use accel::{intersect_batch, occluded_batch, Accel, AccelStats};
pub use apit::{ABuffer, Apit, ApitParams, Fragment};
pub use brute::Brute;
pub use counters::{Counter, NoCount, TraversalCounts};
pub use error::BuildError;
pub use registry::AccelKind;
