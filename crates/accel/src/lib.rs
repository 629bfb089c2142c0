//! Acceleration structures of dynray behind one interface, and the brute-force oracle.
//!
//! Every structure implements [`Accel`]: built from a [`TriangleMesh`], it answers
//! closest-hit ([`Accel::intersect`]) and any-hit ([`Accel::occluded`]) queries that are
//! bit-identical to [`Brute`]'s, because all of them call the one triangle test of
//! `dynray-geom` and break `t` ties towards the lower triangle index.
#![deny(missing_docs)]

mod accel;
pub mod apit;
pub mod batch;
pub mod bih;
pub mod brute;
pub mod bvh;
mod counters;
mod error;
pub mod grid;
pub mod kdtree;
pub mod octree;
mod registry;
mod spec;
pub mod structure_params;

pub use accel::{Accel, AccelStats};
pub use apit::{ABuffer, Apit, ApitParams, Fragment};
pub use batch::{BatchQuery, BATCH_CHUNK};
pub use bih::{Bih, BihParams};
pub use brute::Brute;
pub use bvh::{Bvh, BvhParams};
pub use counters::{Counter, NoCount, TraversalCounts};
pub use error::BuildError;
pub use grid::{Grid, GridParams};
pub use kdtree::{KdTree, KdTreeParams, KdTreeRopes};
pub use octree::{Octree, OctreeDescent, OctreeParams};
pub use registry::AccelKind;
pub use spec::{AccelSpec, BruteParams};
pub use structure_params::{ParamKey, StructureParams};
