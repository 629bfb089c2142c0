//! What a loader hands back besides the scene: the problems that did not stop it.
//! Every loader (formats/, scn/) builds these, and [`crate::load_file_report`] returns them.

use crate::Scene;
use std::fmt;
use std::path::{Path, PathBuf};

/// A problem that did not stop loading; the scene was completed with a documented default.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// The file the problem is in (the `.mtl` for a material library problem).
    pub path: PathBuf,
    /// 1-based line, for text formats.
    pub line: Option<usize>,
    /// What happened and what was used instead.
    pub message: String,
}

impl Warning {
    /// A warning about `path` at `line`.
    pub fn new(path: &Path, line: Option<usize>, message: impl Into<String>) -> Self {
        Self { path: path.to_path_buf(), line, message: message.into() }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        write!(f, ": {}", self.message)
    }
}

/// A loaded scene and the warnings met while loading it.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadReport {
    /// The scene.
    pub scene: Scene,
    /// Problems that did not stop loading, in the order they were found.
    pub warnings: Vec<Warning>,
}
