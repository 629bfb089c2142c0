//! The crate's errors: building a field ([`AdfError`]) and reading or writing a file
//! ([`FileError`]).

use std::path::PathBuf;

/// Why a distance field could not be built.
#[derive(Debug, thiserror::Error)]
pub enum AdfError {
    /// `max_level` outside what the format addresses.
    #[error("max level {level} is outside 1..={max} (the 4-byte cell identifiers hold 10-bit key components)")]
    LevelOutOfRange {
        /// The level asked for.
        level: u32,
        /// The deepest level the format addresses ([`crate::MAX_LEVEL`]).
        max: u32,
    },
    /// The tolerance is not a positive finite number.
    #[error("epsilon {0} must be a positive finite number (a fraction of the cube's edge)")]
    BadEpsilon(f32),
    /// The mesh has no triangles or an empty box.
    #[error("the mesh has no triangles to build a distance field of")]
    EmptyMesh,
    /// The BVH behind the closest-point and sign queries could not be built.
    #[error("cannot build the BVH of the mesh")]
    Accel(#[from] dynray_accel::BuildError),
    /// The field's bounds are empty or not finite.
    #[error("the field's bounds {0:?} are empty or not finite")]
    BadBounds(dynray_geom::Aabb),
    /// More internal cells than the 32-bit block addresses hold.
    #[error("{cells} internal cells: more than the format's 32-bit block addresses hold")]
    TooManyCells {
        /// Internal cells the build produced.
        cells: usize,
    },
    /// The perfect-hash generator found no injective table within its retry budget.
    #[error("no perfect hash found for {cells} cells in {attempts} attempts (offset tables up to {largest}^3)")]
    HashNotFound {
        /// Keys to hash.
        cells: usize,
        /// Attempts made over all offset-table sizes.
        attempts: u32,
        /// Edge of the largest offset table tried.
        largest: u32,
    },
}

/// Why a `.adf` file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The operating system refused to read or write it.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file does not start with the `.adf` magic.
    #[error("{}: not a dynray distance field (bad magic)", path.display())]
    NotAdf {
        /// The file.
        path: PathBuf,
    },
    /// A version this build does not read.
    #[error(
        "{}: format version {found}, this dynray reads version {supported} (rebuild it with `dynray adf build`)",
        path.display()
    )]
    Version {
        /// The file.
        path: PathBuf,
        /// Version in the file.
        found: u32,
        /// The version this build reads and writes.
        supported: u32,
    },
    /// Shorter or longer than its header says.
    #[error("{}: {found} bytes where the header promises {expected} (truncated or padded)", path.display())]
    Length {
        /// The file.
        path: PathBuf,
        /// Bytes the header's sizes add up to.
        expected: u64,
        /// Bytes in the file.
        found: u64,
    },
    /// The header or the tables are inconsistent, or the checksum does not match.
    #[error("{}: corrupt distance field: {what}", path.display())]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        what: String,
    },
}
