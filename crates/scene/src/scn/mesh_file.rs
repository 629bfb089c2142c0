//! `mesh { file "…" }`: the one place that turns a mesh file into parts. It reads PLY
//! (`.ply`, `.ply.gz`) through `crate::ply`; other formats give a clear error until the
//! general loader dispatcher (`crate::load::load_file`) is merged, when this function
//! should be re-pointed to it (every format it reads then works in scene files).

use crate::{LoadError, Material};
use dynray_geom::TriangleMesh;
use std::path::Path;

/// Reads a mesh file as (mesh, material from the file, if any) parts.
pub(crate) fn load_mesh_file(path: &Path) -> Result<Vec<(TriangleMesh, Option<Material>)>, LoadError> {
    let name = path.to_string_lossy().to_ascii_lowercase();
    if name.ends_with(".ply") || name.ends_with(".ply.gz") {
        return Ok(vec![(crate::ply::load(path)?, None)]);
    }
    Err(LoadError::UnknownFormat { path: path.to_path_buf() })
}
