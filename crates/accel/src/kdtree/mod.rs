//! SAH kd-tree, seed 000's baseline, with two traversals: the standard stack traversal
//! ([`KdTree`], "Standard") and the stackless rope traversal ([`KdTreeRopes`], "Ropes++").
//!
//! Build: exact SAH over clipped triangle bounds ("perfect splits"), O(N log N) by event
//! sorting (build.rs). Both traversals return exactly brute force's hit although
//! straddling triangles live in several leaves (traverse.rs explains the rule).
//!
//! Files: params.rs (presets), node.rs (8-byte node, rope record), clip.rs (polygon
//! clipping), build.rs, tree.rs (the arrays), traverse.rs (stack), ropes.rs (rope
//! construction), traverse_ropes.rs (stackless walk), validate.rs (checks and stats),
//! standard.rs and stackless.rs (the two `Accel` types), outline.rs (the viewer's cells).

mod build;
mod clip;
mod node;
mod outline;
mod params;
mod ropes;
mod stackless;
mod standard;
mod traverse;
mod traverse_ropes;
mod tree;
mod validate;

pub use node::{KdNode, LeafRopes, NO_ROPE};
pub use params::{KdTreeParams, MAX_DEPTH_LIMIT};
pub use stackless::KdTreeRopes;
pub use standard::KdTree;
