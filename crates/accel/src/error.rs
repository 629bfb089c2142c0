//! Why a structure could not be built (or its parameters not read).

use dynray_geom::MeshError;

/// A build, update or parameter failure.
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
    #[error("{structure}: invalid parameter {name}: {message}")]
    Param {
        /// The structure (`bih`, …) whose parameter it is.
        structure: &'static str,
        /// Parameter name.
        name: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A `key=value` parameter the structure does not have.
    #[error("{structure}: unknown parameter `{key}` (known: {})", .known.join(", "))]
    UnknownParam {
        /// The structure.
        structure: &'static str,
        /// The key given.
        key: String,
        /// Every key it accepts.
        known: Vec<&'static str>,
    },
    /// A parameter whose text does not parse as its type.
    #[error("{structure}: parameter `{key}={value}`: expected {expected}")]
    BadValue {
        /// The structure.
        structure: &'static str,
        /// The key.
        key: String,
        /// The text given.
        value: String,
        /// What would have been accepted.
        expected: &'static str,
    },
    /// `preset=NAME` (or `NAME:preset`) with a preset the structure does not have.
    #[error("{structure}: unknown preset `{preset}` (known: {})", .known.join(", "))]
    UnknownPreset {
        /// The structure.
        structure: &'static str,
        /// The name given.
        preset: String,
        /// Its presets.
        known: Vec<&'static str>,
    },
    /// A structure name that `--accel` does not know.
    #[error("unknown structure `{name}` (expected one of: {})", .known.join(", "))]
    UnknownStructure {
        /// The name given.
        name: String,
        /// Every structure name.
        known: Vec<&'static str>,
    },
    /// A `NAME[:key=value,…]` specification that is not well formed.
    #[error("`{spec}`: {message}")]
    Spec {
        /// The specification as given.
        spec: String,
        /// What is wrong with it.
        message: String,
    },
    /// The structure would exceed a limit of its node encoding.
    #[error("{0}")]
    Limit(String),
}

impl BuildError {
    /// The same error naming `structure` (e.g. `kdtree-ropes` for an error of the
    /// `kdtree` parameters both kd-trees share).
    pub fn in_structure(mut self, name: &'static str) -> Self {
        match &mut self {
            BuildError::Param { structure, .. }
            | BuildError::UnknownParam { structure, .. }
            | BuildError::BadValue { structure, .. }
            | BuildError::UnknownPreset { structure, .. } => *structure = name,
            _ => {}
        }
        self
    }
}
