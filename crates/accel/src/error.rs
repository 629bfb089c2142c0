//! Why a structure could not be built.

use dynray_geom::MeshError;

/// A build or update failure.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The mesh breaks an invariant every structure relies on.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// `update` got a mesh whose triangles differ from the one the structure was built on.
    #[error("update needs the same triangles as the build ({built} then, {given} now)")]
    TopologyChanged {
        /// Triangles at build time.
        built: usize,
        /// Triangles in the new mesh.
        given: usize,
    },
    /// A parameter is outside its useful range.
    #[error("invalid parameter {name}: {message}")]
    Param {
        /// Parameter name.
        name: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The structure would exceed a limit of its node encoding.
    #[error("{0}")]
    Limit(String),
}
