//! Mesh and scene-interchange formats, one file per format: each turns its file into a
//! [`crate::Scene`] (or, for PLY, a bare mesh) for [`crate::load_file_report`].
//!
//! The scene language of seed 003 is not here: it is a language (lexer, parser, include
//! resolution) rather than a format, and lives in [`crate::scn`].
//!
//! A new format goes in a file of its own here, with a `load(path)` entry point, plus one
//! arm in `load.rs` ([`crate::FileFormat`] and [`crate::load_file_report`]); scene files can
//! then reference it through `mesh { file "…" }` without further work.

pub mod aff;
pub mod gltf;
pub mod mitsuba;
pub(crate) mod mtl;
pub mod npz;
pub mod obj;
pub mod ply;
