//! Files the way every reader and writer of dynray must handle them (DESIGN.md, "Errors
//! and bad input").
//!
//! - Reading: regular files only. A device (`/dev/zero` behind a `bunny.ply` link), a
//!   named pipe or a socket would hang a reader or feed it without end, and a directory
//!   has nothing to parse, so each is refused before it is opened, with an error that
//!   says what it is. Every file read is remembered ([`inputs`]).
//! - Writing ([`atomic`]): whole or not at all, never over a file this process read as
//!   input, and no temporary left behind by a failure or by SIGINT/SIGTERM.

pub mod atomic;
pub mod inputs;

pub use atomic::{remove_temporaries, write_atomic};

use std::io;
use std::path::Path;

/// Fails unless `path` (after following links) is a regular file; a regular file is
/// remembered as an input of this process ([`inputs`]).
pub fn check_regular(path: &Path) -> io::Result<()> {
    let meta = regular(path)?;
    inputs::record(path, &meta);
    Ok(())
}

/// Reads back a file the command itself writes and maintains (animate's timings and
/// physics checkpoints): a regular file like any input, but not remembered as one, since
/// the command may write it again.
pub fn read_back(path: &Path) -> io::Result<Vec<u8>> {
    regular(path)?;
    std::fs::read(path)
}

/// [`read_back`] as UTF-8 text.
pub fn read_back_to_string(path: &Path) -> io::Result<String> {
    regular(path)?;
    std::fs::read_to_string(path)
}

/// `path`'s metadata when it is a regular file (after following links), else an error
/// that says what it is.
fn regular(path: &Path) -> io::Result<std::fs::Metadata> {
    let meta = std::fs::metadata(path)?;
    if meta.is_file() {
        return Ok(meta);
    }
    let what = if meta.is_dir() { "a directory" } else { kind_of_special(&meta) };
    Err(io::Error::new(io::ErrorKind::InvalidInput, format!("not a regular file ({what})")))
}

#[cfg(unix)]
fn kind_of_special(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_fifo() {
        "a named pipe"
    } else if t.is_socket() {
        "a socket"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else {
        "not a file"
    }
}

#[cfg(not(unix))]
fn kind_of_special(_: &std::fs::Metadata) -> &'static str {
    "not a file"
}

/// The whole of the regular file `path`.
pub fn read(path: &Path) -> io::Result<Vec<u8>> {
    check_regular(path)?;
    std::fs::read(path)
}

/// The whole of the regular file `path` as UTF-8 text.
pub fn read_to_string(path: &Path) -> io::Result<String> {
    check_regular(path)?;
    std::fs::read_to_string(path)
}

/// The regular file `path`, opened for reading.
pub fn open(path: &Path) -> io::Result<std::fs::File> {
    check_regular(path)?;
    std::fs::File::open(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_directories_and_pipes_are_refused_before_any_read() {
        let dir = std::env::temp_dir();
        let e = read(&dir).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert!(e.to_string().contains("a directory"), "{e}");
        #[cfg(unix)]
        {
            let e = read(Path::new("/dev/zero")).unwrap_err();
            assert!(e.to_string().contains("a device"), "{e}");
            let d = tempfile_dir();
            let fifo = d.join("f.ply");
            let made = std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success());
            if made {
                // Opening a pipe with no writer would block forever: refused first.
                let e = read_to_string(&fifo).unwrap_err();
                assert!(e.to_string().contains("a named pipe"), "{e}");
            }
            let _ = std::fs::remove_dir_all(d);
        }
        let missing = read(Path::new("/no/such/file.ply")).unwrap_err();
        assert_eq!(missing.kind(), io::ErrorKind::NotFound);
    }

    #[test]
    fn regular_files_read_as_before() {
        let d = tempfile_dir();
        let p = d.join("a.txt");
        std::fs::write(&p, "abc").unwrap();
        assert_eq!(read(&p).unwrap(), b"abc");
        assert_eq!(read_to_string(&p).unwrap(), "abc");
        assert!(open(&p).is_ok());
        let _ = std::fs::remove_dir_all(d);
    }

    /// A fresh folder under the temporary directory (geom has no tempfile dependency).
    fn tempfile_dir() -> std::path::PathBuf {
        use std::sync::atomic::{AtomicU32, Ordering};
        static N: AtomicU32 = AtomicU32::new(0);
        let d = std::env::temp_dir().join(format!(
            "dynray-geom-file-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&d).unwrap();
        d
    }
}
