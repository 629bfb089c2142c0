//! Shared geometry of dynray: rays, hits, boxes, triangle meshes, smooth vertex normals
//! for meshes without them, and the one ray–triangle test every acceleration structure
//! calls.
//!
//! Nothing here knows about trees. Because every structure intersects triangles
//! through [`Triangle::intersect`] with the same [`PreparedRay`], the closest hit of
//! any structure is bit-identical to brute force (same `t` bits, same triangle).
#![deny(missing_docs)]
// Everything here is plain safe Rust (SIMD, where it comes, through safe wrappers).
#![forbid(unsafe_code)]

mod aabb;
pub mod budget;
pub mod file;
mod hit;
mod mesh;
mod normals;
mod overlap;
mod ray;
mod triangle;

pub use aabb::{Aabb, SLAB_MARGIN};
pub use glam::{Vec2, Vec3};
pub use hit::Hit;
pub use mesh::{MeshError, TriangleMesh};
pub use normals::{SmoothNormals, MAX_EXACT_CORNERS};
pub use overlap::triangle_box_overlap;
pub use ray::{PreparedRay, Ray};
pub use triangle::Triangle;
