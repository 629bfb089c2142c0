//! Point-based animation (seed 000 §2.10, after Müller, Keiser, Nealen, Pauly, Gross and
//! Alexa, "Point Based Animation of Elastic, Plastic and Melting Objects", SCA 2004):
//! meshless elastic and plastic bodies whose phyxels deform the scene's meshes every
//! frame. docs/physics.md is the reference (model, equations, units, stability bound).
//!
//! One concept per file: `sampling.rs` (phyxels inside a closed mesh), `hash.rs` (the
//! spatial hash), `kernel.rs` and `mls.rs` (the kernel and the MLS gradient),
//! `material.rs`, `elastic.rs` (strain, stress, forces), `plastic.rs`, `contact.rs`
//! (floor and static geometry), `integrator.rs` (the stable step), `surface.rs` (mesh
//! vertices following the phyxels), `body.rs`, `world.rs` and `checkpoint.rs` (a
//! world's state saved and restored).
//!
//! ```
//! use dynray_scene::parse_scn_str;
//! use dynray_sim::World;
//!
//! let scene = parse_scn_str(
//!     "doc",
//!     "physics { ground 0 substeps 4 } settings { frames 3 frame_rate 24 }
//!      box { center <0, 1, 0> orientation <0, 0, 0> scale <0.5, 0.5, 0.5>
//!            elastic { young 2e4 phyxels 64 } }",
//!     std::path::Path::new("."),
//! )?;
//! let mut world = World::from_scene(&scene)?.expect("one elastic body");
//! let y0 = world.bodies()[0].centre_of_mass().y;
//! world.advance_to(2.0 / 24.0)?;
//! assert!(world.bodies()[0].centre_of_mass().y < y0, "it falls");
//! let mut frame = scene.frame(2.0 / 24.0);
//! world.write_into(&mut frame)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod body;
mod checkpoint;
pub mod contact;
pub mod elastic;
mod error;
pub mod hash;
pub mod integrator;
pub mod kernel;
pub mod material;
pub mod mls;
pub mod plastic;
pub mod sampling;
pub mod surface;
pub mod world;

pub use body::Body;
pub use error::SimError;
pub use material::Material;
pub use world::World;
