//! A-PIT (seed 004): six A-buffers on the faces of a cube around an observer, one
//! pseudo-interval tree per pixel, and a ray walk through the pixel frustums.
//!
//! Every pixel of every face is an infinite pyramid (frustum) from the observer. Each
//! triangle is conservatively rasterised into every frustum it touches, as a fragment
//! holding its depth interval there (`raster.rs`); a ray visits the frustums it crosses
//! in order (`walk.rs`) and tests the fragments whose depth interval meets its own in
//! that frustum, found by scanning the pixel's list ([`ABuffer`], the seed's baseline)
//! or by querying the pixel's pseudo-interval tree ([`Apit`], `pit.rs`). The walk stops
//! once the next frustum starts beyond the best hit, so hits equal brute force's.
//!
//! Departures from the seed, each explained where it is made: depth is the distance
//! along the face axis (linear along rays); pixels are dilated and triangles near the
//! observer are kept in a list tested by every ray (projection is singular there); the
//! walk is clipped to the mesh bounds instead of a "negligible light" distance; tree
//! insertion order is pseudo-random instead of rasterisation order.

// NaN-safe comparisons are written `!(a <= b)` on purpose: a NaN must take the
// conservative branch, which `a > b` would not.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod abuffer;
mod build;
mod cube;
mod node;
mod outline;
mod params;
pub mod pit;
mod query;
mod raster;
mod tree;
mod validate;
mod walk;

pub use abuffer::ABuffer;
pub use node::{Fragment, PitNode, NONE};
pub use params::{ApitParams, Observer};
pub use pit::{IntervalForest, TreeShape};
pub use tree::Apit;
