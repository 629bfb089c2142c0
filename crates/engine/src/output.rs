//! Writing output files the way every front end must: whole or not at all, never over an
//! input, no temporary left behind (DESIGN.md, "Errors and bad input";
//! [`dynray_geom::file::atomic`] does it), with errors that name the file.

use anyhow::Result;
use std::fs::File;
use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_with(path, |f| Ok(f.write_all(bytes)?))
}

/// Writes `path` atomically through `fill`; errors name the file.
pub fn write_with(path: &Path, fill: impl FnOnce(&mut File) -> Result<()>) -> Result<()> {
    dynray_geom::file::write_atomic(
        path,
        |f| fill(f).map_err(|e| e.context(format!("{}: write failed", path.display()))),
        |e| anyhow::Error::new(e).context(format!("{}: cannot write", path.display())),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_are_whole_and_readable_by_others() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.txt");
        write_atomic(&p, b"abc").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"abc");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&p).unwrap().permissions().mode();
            assert_ne!(mode & 0o044, 0, "group or others may read: {mode:o}");
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "no temporary file left");
    }

    #[test]
    fn a_failed_fill_names_the_file_and_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.gif");
        let e = write_with(&p, |f| {
            f.write_all(b"GIF8")?;
            anyhow::bail!("encoder failed")
        })
        .unwrap_err();
        assert_eq!(format!("{e:#}"), format!("{}: write failed: encoder failed", p.display()));
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
