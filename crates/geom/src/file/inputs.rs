//! The files this process has read as input, by identity, so that no output ever replaces
//! one (issue 43: `render -o` naming the scene's own texture, `trace-rays -o` naming the
//! input mesh, `animate --export-meshes` into the folder of a `mesh_0000.obj` input).
//!
//! Identity is the file itself, not its spelling: device and inode on Unix, so a link, a
//! `./` or a `..` detour still name the same input; elsewhere the canonical path.

use std::collections::HashSet;
use std::fs::Metadata;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// What makes two paths the same file.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Identity {
    #[cfg(unix)]
    Inode { dev: u64, ino: u64 },
    #[cfg_attr(unix, allow(dead_code))]
    Path(PathBuf),
}

fn identity(path: &Path, meta: &Metadata) -> Option<Identity> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let _ = path;
        Some(Identity::Inode { dev: meta.dev(), ino: meta.ino() })
    }
    #[cfg(not(unix))]
    {
        let _ = meta;
        std::fs::canonicalize(path).ok().map(Identity::Path)
    }
}

/// Every input read so far (a set: a long Python session loads the same files again).
static READ: Mutex<Option<HashSet<Identity>>> = Mutex::new(None);

/// Remembers the regular file `path` (whose metadata is `meta`) as read.
pub(crate) fn record(path: &Path, meta: &Metadata) {
    if let Some(id) = identity(path, meta) {
        READ.lock().unwrap_or_else(|e| e.into_inner()).get_or_insert_with(HashSet::new).insert(id);
    }
}

/// True when `path` exists and is a file this process has read as input.
pub fn was_read(path: &Path) -> bool {
    let Ok(meta) = std::fs::metadata(path) else {
        return false;
    };
    let Some(id) = identity(path, &meta) else {
        return false;
    };
    READ.lock().unwrap_or_else(|e| e.into_inner()).as_ref().is_some_and(|set| set.contains(&id))
}

/// Fails when writing `path` would replace a file this process read as input.
pub fn check_output(path: &Path) -> io::Result<()> {
    if was_read(path) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "this file is one of the inputs (the scene, or a file it references); writing it would \
             destroy it: choose another output",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_read_file_is_an_input_under_any_spelling() {
        let dir = std::env::temp_dir().join(format!("dynray-geom-inputs-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let mesh = dir.join("mesh.obj");
        std::fs::write(&mesh, "v 0 0 0\n").unwrap();
        let other = dir.join("out.obj");
        std::fs::write(&other, "").unwrap();
        assert!(check_output(&mesh).is_ok(), "not read yet");
        crate::file::read(&mesh).unwrap();
        let e = check_output(&mesh).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert!(e.to_string().contains("one of the inputs"), "{e}");
        assert!(check_output(&dir.join("sub/../mesh.obj")).is_err(), "another spelling");
        #[cfg(unix)]
        {
            let link = dir.join("link.obj");
            let _ = std::fs::remove_file(&link);
            std::os::unix::fs::symlink(&mesh, &link).unwrap();
            assert!(check_output(&link).is_err(), "a link to the input");
        }
        assert!(check_output(&other).is_ok(), "a file never read");
        assert!(check_output(&dir.join("new.obj")).is_ok(), "a file that does not exist");
        let _ = std::fs::remove_dir_all(dir);
    }
}
