//! Writing an output whole or not at all: into a temporary sibling, synced, then renamed
//! over the destination, so a reader never sees half a file and a failed write leaves the
//! old file as it was. Every writer of dynray's outputs goes through [`write_atomic`]:
//!
//! - it refuses a destination that is one of the process's inputs ([`super::inputs`]);
//! - the temporary (`.NAME.PID.N.tmp`) is removed on every failure path, and is
//!   registered while it exists, so that a front end's SIGINT/SIGTERM handler removes it
//!   too ([`remove_temporaries`]): an interrupted run leaves nothing behind;
//! - the output gets ordinary permissions (0644 less the umask), being for other tools
//!   and people.

use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// Temporaries being written now.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Writes `path` through `fill`, which gets the temporary file, then syncs it and renames
/// it over `path`. On any failure the temporary is removed and `path` left as it was.
/// Failures of this function's own steps (refusing an input, creating, syncing,
/// renaming) become `E` through `io_error`; `fill`'s errors pass through unchanged.
pub fn write_atomic<E>(
    path: &Path,
    fill: impl FnOnce(&mut File) -> Result<(), E>,
    io_error: impl Fn(io::Error) -> E,
) -> Result<(), E> {
    super::inputs::check_output(path).map_err(&io_error)?;
    let tmp = Temporary::create(path).map_err(&io_error)?;
    let mut file = tmp.open().map_err(&io_error)?;
    fill(&mut file)?;
    file.sync_all().map_err(&io_error)?;
    drop(file);
    tmp.rename_to(path).map_err(&io_error)
}

/// Removes every temporary being written now: for a signal handler about to exit.
pub fn remove_temporaries() {
    remove_where(|_| true);
}

fn remove_where(pick: impl Fn(&Path) -> bool) {
    let live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
    for p in live.iter().filter(|p| pick(p)) {
        let _ = std::fs::remove_file(p);
    }
}

/// A registered temporary sibling of an output; removed (file and registration) when
/// dropped without having been renamed.
struct Temporary {
    path: PathBuf,
    renamed: bool,
}

impl Temporary {
    /// Registers the name first, then creates the file, so a signal in between finds
    /// nothing worse than a name without a file.
    fn create(dest: &Path) -> io::Result<Temporary> {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let name = dest.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        let path = dest.with_file_name(format!(".{name}.{}.{n}.tmp", std::process::id()));
        LIVE.lock().unwrap_or_else(|e| e.into_inner()).push(path.clone());
        let tmp = Temporary { path, renamed: false };
        let mut options = std::fs::OpenOptions::new();
        options.write(true).create_new(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt;
            options.mode(0o644);
        }
        options.open(&tmp.path)?;
        Ok(tmp)
    }

    fn open(&self) -> io::Result<File> {
        std::fs::OpenOptions::new().write(true).truncate(true).open(&self.path)
    }

    fn rename_to(mut self, dest: &Path) -> io::Result<()> {
        std::fs::rename(&self.path, dest)?;
        self.renamed = true;
        Ok(())
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if !self.renamed {
            let _ = std::fs::remove_file(&self.path);
        }
        let mut live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = live.iter().position(|p| p == &self.path) {
            live.swap_remove(i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("dynray-geom-atomic-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    }

    #[test]
    fn a_write_is_whole_and_leaves_no_temporary() {
        let d = scratch("whole");
        let out = d.join("out.txt");
        write_atomic(&out, |f| f.write_all(b"abc"), |e| e).unwrap();
        assert_eq!(std::fs::read(&out).unwrap(), b"abc");
        assert_eq!(entries(&d), ["out.txt"]);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&out).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode, 0o644 & !umask_bits(), "0644 less the umask, not 0600: {mode:o}");
        }
        let _ = std::fs::remove_dir_all(d);
    }

    #[cfg(unix)]
    fn umask_bits() -> u32 {
        // The umask of this process, read back from a file created with mode 0o777.
        let p = std::env::temp_dir().join(format!("dynray-umask-{}", std::process::id()));
        use std::os::unix::fs::{OpenOptionsExt, PermissionsExt};
        let _ = std::fs::OpenOptions::new().write(true).create(true).truncate(true).mode(0o777).open(&p);
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        let _ = std::fs::remove_file(p);
        !mode & 0o777
    }

    #[test]
    fn a_failed_fill_keeps_the_old_file_and_removes_the_temporary() {
        let d = scratch("failed");
        let out = d.join("out.txt");
        std::fs::write(&out, "old").unwrap();
        let e = write_atomic(
            &out,
            |f| {
                f.write_all(b"half")?;
                assert_eq!(LIVE.lock().unwrap().iter().filter(|p| p.starts_with(&d)).count(), 1, "registered");
                Err(io::Error::other("encoder failed"))
            },
            |e| e,
        )
        .unwrap_err();
        assert_eq!(e.to_string(), "encoder failed");
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "old");
        assert_eq!(entries(&d), ["out.txt"]);
        assert!(LIVE.lock().unwrap().iter().all(|p| !p.starts_with(&d)), "deregistered");
        let _ = std::fs::remove_dir_all(d);
    }

    #[test]
    fn remove_temporaries_removes_what_is_being_written() {
        let d = scratch("signal");
        let out = d.join("out.txt");
        write_atomic(
            &out,
            |f| {
                f.write_all(b"partial")?;
                // What a SIGTERM handler does mid-write (limited to this test's folder:
                // the other tests write at the same time).
                remove_where(|p| p.starts_with(&d));
                assert_eq!(entries(&d), Vec::<String>::new());
                Err(io::Error::other("interrupted"))
            },
            |e| e,
        )
        .unwrap_err();
        assert!(!out.exists());
        let _ = std::fs::remove_dir_all(d);
    }

    #[test]
    fn an_input_is_never_overwritten() {
        let d = scratch("input");
        let input = d.join("mesh.obj");
        std::fs::write(&input, "v 0 0 0\n").unwrap();
        crate::file::read(&input).unwrap();
        let e = write_atomic(&input, |f| f.write_all(b"x"), |e| e).unwrap_err();
        assert!(e.to_string().contains("one of the inputs"), "{e}");
        assert_eq!(std::fs::read_to_string(&input).unwrap(), "v 0 0 0\n");
        assert_eq!(entries(&d), ["mesh.obj"]);
        let _ = std::fs::remove_dir_all(d);
    }
}
