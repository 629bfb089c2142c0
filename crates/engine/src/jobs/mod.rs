//! Validated jobs built from plain option structs: each checks every option
//! combination before any work, then runs through the frame step and the tracer seam.

pub mod animate;
mod animate_merge;
mod checkpoints;
pub mod live;
mod preview;
pub mod render;
pub mod shard;
pub mod trace;
