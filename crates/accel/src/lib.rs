//! Acceleration structures of dynray behind one interface, and the brute-force oracle.
//!
//! Every structure implements [`Accel`]: built from a [`TriangleMesh`](dynray_geom::TriangleMesh), it answers
//! closest-hit ([`Accel::intersect`]) and any-hit ([`Accel::occluded`]) queries that are
//! bit-identical to [`Brute`]'s, because all of them call the one triangle test of
//! `dynray-geom` and break `t` ties towards the lower triangle index.
//!
//! Many rays at once go through [`BatchQuery`], which every structure has; a structure
//! and its parameters can be named as text with [`AccelSpec`] (`"bih:max_prims=5"`).
//!
//! ```
//! use dynray_accel::{Accel, AccelSpec, BatchQuery, Bvh, BvhParams};
//! use dynray_geom::{Ray, TriangleMesh, Vec3};
//!
//! // A unit quad in the plane z = 0, as two triangles.
//! let mesh = TriangleMesh::new(
//!     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
//!     vec![[0, 1, 2], [0, 2, 3]],
//! );
//! let bvh = Bvh::build(&mesh, &BvhParams::default())?;
//! bvh.validate(&mesh)?;
//!
//! // One ray straight down onto the quad.
//! let hit = bvh.intersect(&Ray::new(Vec3::new(0.75, 0.25, 1.0), Vec3::new(0.0, 0.0, -1.0)));
//! assert_eq!(hit.prim, 0);
//! assert!((hit.t - 1.0).abs() < 1e-6);
//!
//! // A batch: answers in ray order, the second ray misses.
//! let rays = [
//!     Ray::new(Vec3::new(0.25, 0.75, 1.0), Vec3::new(0.0, 0.0, -1.0)),
//!     Ray::new(Vec3::new(2.0, 2.0, 1.0), Vec3::new(0.0, 0.0, -1.0)),
//! ];
//! let hits = bvh.intersect_batch(&rays);
//! assert_eq!(hits[0].prim, 1);
//! assert!(!hits[1].is_hit());
//! assert_eq!(bvh.occluded_batch(&rays), [true, false]);
//!
//! // The same through a structure named on a command line: same hits.
//! let bih = "bih:max_prims=1".parse::<AccelSpec>()?.build(&mesh, None)?;
//! assert!(bih.intersect_batch(&rays).iter().zip(&hits).all(|(a, b)| a.same_as(b)));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]
// Everything here is plain safe Rust, except the wide BVH's SIMD kernels (bvh/kernel_avx2.rs,
// bvh/kernel_avx512.rs, bvh/packet_avx2.rs, and the `#[target_feature]` entry points in bvh/traverse.rs,
// bvh/packet_traverse.rs and bvh/scan.rs), which allow `unsafe_code` item by item with
// the reason beside it.
#![deny(unsafe_code)]

mod accel;
pub mod apit;
pub mod batch;
pub mod bih;
pub mod brute;
pub mod bvh;
pub mod bvh2;
mod counters;
pub mod descriptor;
mod error;
pub mod grid;
mod huge_pages;
pub mod kdtree;
pub mod octree;
mod outline;
mod rebase;
mod registry;
mod spec;
pub mod structure_params;
pub mod two_level;
pub mod update;

pub use accel::{Accel, AccelStats, InvalidStructure, LeafSizes};
pub use apit::{ABuffer, Apit, ApitParams, Fragment};
pub use batch::{check_batch_lengths, BatchQuery, Coherent, BATCH_CHUNK};
pub use bih::{Bih, BihParams};
pub use brute::Brute;
pub use bvh::{Wbvh, WbvhParams};
pub use bvh2::{Bvh, BvhNode, BvhParams, ClosestPoint, InvalidBvh};
pub use counters::{Counter, NoCount, TraversalCounts};
pub use descriptor::{AccelDescriptor, DESCRIPTORS};
pub use error::BuildError;
pub use grid::{Grid, GridParams};
pub use kdtree::{KdTree, KdTreeParams, KdTreeRopes};
pub use octree::{Octree, OctreeDescent, OctreeParams};
pub use outline::OutlineBox;
pub use registry::AccelKind;
pub use spec::{AccelSpec, BruteParams};
pub use structure_params::{ParamKey, StructureParams};
pub use two_level::{ActorGeometry, ActorMotion, LiveScene, PartUpdates, SceneLayout, TwoLevel};
pub use update::{LiveAccel, PolicyState, PolicyTarget, UpdateAction, UpdatePolicy, UpdateReport};
