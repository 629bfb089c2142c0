//! Errors of the scene loaders: each names the file and, where there is one, the line.

use dynray_geom::MeshError;
use std::path::{Path, PathBuf};

/// Why a scene or mesh file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be opened or read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The extension names no format dynray reads.
    #[error("{}: unknown file type (expected .obj, .ply, .ply.gz, .gltf, .glb, .npz, .aff, .nff, .scn or Mitsuba's .xml)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The content is malformed; `line` is 1-based when the format has lines.
    #[error("{}{}: {message}", path.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line, for text formats.
        line: Option<usize>,
        /// What is wrong, and what was expected.
        message: String,
    },
    /// The file parsed but its geometry is unusable (empty, NaN, index out of range).
    #[error("{}: {source}", path.display())]
    Mesh {
        /// The file.
        path: PathBuf,
        /// What is wrong with the mesh.
        source: MeshError,
    },
    /// A scene-language (`.scn`) file has a lexical, syntax, type, name-resolution or
    /// file error. `rendered` is the full report (`file:line:col`, the source line with a
    /// caret under the offending text, what was expected) and is what `Display` prints.
    #[error("{rendered}")]
    Scene {
        /// The file the error is in (an included file when the error is there).
        path: PathBuf,
        /// 1-based line of the error.
        line: usize,
        /// 1-based column (in characters) of the error.
        column: usize,
        /// The one-line message, without location.
        message: String,
        /// The rendered diagnostic.
        rendered: String,
    },
}

impl LoadError {
    /// A parse error at `line` (1-based) of `path`.
    pub fn parse(path: &Path, line: Option<usize>, message: impl Into<String>) -> Self {
        LoadError::Parse { path: path.to_path_buf(), line, message: message.into() }
    }

    /// An I/O error on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        LoadError::Io { path: path.to_path_buf(), source }
    }
}
