//! What dynray's fuzz targets share (docs/fuzzing.md): a fuzz input split into the files
//! of a small scene folder, that folder written under a scratch directory of this
//! process, and the checks every loaded scene goes through.
//!
//! # Bundles
//! A scene file names other files (includes, material libraries, meshes, buffers,
//! textures), so the targets for such formats read their input as a *bundle*: the main
//! file's bytes, then any number of further files, each introduced by a line
//! `@@@ NAME` (the marker is [`SEPARATOR`], newline included on both sides):
//!
//! ```text
//! include "part.scn"
//! @@@ part.scn
//! sphere { center <0, 0, 0> radius 1 }
//! ```
//!
//! A name is one to three `/`-separated parts of `[A-Za-z0-9_.-]`, none starting with a
//! dot (so never `..`): every file lands inside the scratch folder, whatever the input.
//! A section with any other name is dropped. Readable seeds follow from this, and the
//! fuzzer's mutations (splicing two seeds, copying a name it saw compared) reach the
//! includes.
//!
//! # What counts as a finding
//! Every target treats an `Err` as the right answer to a bad file; only a panic (a
//! failed assertion or overflow check included), an abort, a timeout or memory past
//! libFuzzer's `-rss_limit_mb` is a finding.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The line that starts each further file of a bundle (module docs).
pub const SEPARATOR: &[u8] = b"\n@@@ ";

/// Most files one bundle writes; further sections are dropped.
pub const MAX_FILES: usize = 16;

/// A bundle (module docs) as `(name, bytes)` pairs, the main file first under `main`.
pub fn split_bundle<'a>(data: &'a [u8], main: &str) -> Vec<(String, &'a [u8])> {
    let mut files = Vec::new();
    let mut rest = data;
    let mut name = Some(main.to_string());
    loop {
        let (body, next) = match find(rest, SEPARATOR) {
            Some(i) => (&rest[..i], Some(&rest[i + SEPARATOR.len()..])),
            None => (rest, None),
        };
        if let Some(n) = name.take() {
            if files.len() < MAX_FILES {
                files.push((n, body));
            }
        }
        let Some(next) = next else { break };
        let (line, after) = match find(next, b"\n") {
            Some(i) => (&next[..i], &next[i + 1..]),
            None => (next, &next[next.len()..]),
        };
        name = std::str::from_utf8(line).ok().map(str::trim).filter(|n| safe_name(n)).map(str::to_string);
        rest = after;
    }
    files
}

/// True for a relative name that stays inside its folder (module docs).
pub fn safe_name(name: &str) -> bool {
    let parts: Vec<&str> = name.split('/').collect();
    parts.len() <= 3
        && parts.iter().all(|p| {
            !p.is_empty()
                && p.len() <= 64
                && !p.starts_with('.')
                && p.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-' || b == b'.')
        })
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// This process's scratch folder: under `$TMPDIR` (run.sh points it at a folder it
/// removes afterwards), made once.
pub fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("dynray-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("cannot create the fuzz scratch folder");
        dir
    })
}

/// Writes `files` into a fresh `case` folder under [`scratch`] (the previous input's
/// folder removed first) and returns the folder.
pub fn write_case(files: &[(String, &[u8])]) -> PathBuf {
    let dir = scratch().join("case");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("cannot create the fuzz case folder");
    for (name, bytes) in files {
        let path = dir.join(name);
        if let Some(parent) = path.parent() {
            // A name may be both a file and a folder (`a` and `a/b`): the later one
            // fails to write and is left out, as a real folder could not hold both.
            if std::fs::create_dir_all(parent).is_err() {
                continue;
            }
        }
        if let Ok(mut f) = std::fs::File::create(&path) {
            f.write_all(bytes).expect("cannot write a fuzz case file");
        }
    }
    dir
}

/// Writes a bundle (module docs) with its main file named `main` and loads that file
/// the way `dynray render` does ([`dynray_scene::load_file_report`]), then poses the
/// scene ([`check_scene`]). An error is a fine answer.
pub fn load_bundle(data: &[u8], main: &str) {
    let files = split_bundle(data, main);
    let dir = write_case(&files);
    if let Ok(report) = dynray_scene::load_file_report(&dir.join(main)) {
        check_scene(&report.scene);
    }
}

/// What a loaded scene must survive: posing at its first, middle and last frames
/// ([`dynray_scene::Scene::frame`]; `validate_animation` is there so that this never
/// panics), and a mesh that passes its own validation.
pub fn check_scene(scene: &dynray_scene::Scene) {
    let tl = scene.animation.timeline;
    let last = tl.frames.saturating_sub(1);
    for k in [0, last / 2, last] {
        let frame = scene.frame(tl.time_of(k));
        let n = frame.mesh.positions.len();
        assert!(
            frame.mesh.indices.iter().flatten().all(|&i| (i as usize) < n),
            "frame {k}: a triangle names a vertex past the {n} vertices"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bundles_split_into_named_files_inside_the_folder() {
        let data = b"main text\n@@@ a.scn\nA\n@@@ sub/b.obj\nB\n@@@ ../evil\nC\n@@@ /abs\nD\n@@@ .hidden\nE";
        let files = split_bundle(data, "main.scn");
        let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["main.scn", "a.scn", "sub/b.obj"]);
        assert_eq!(files[0].1, b"main text");
        assert_eq!(files[1].1, b"A");
        assert_eq!(files[2].1, b"B");
        assert_eq!(split_bundle(b"", "m.aff"), vec![("m.aff".to_string(), &b""[..])]);
        assert!(!safe_name("a/b/c/d"));
        assert!(!safe_name("a//b"));
        assert!(safe_name("TextureFiles/wood.ppm"));
    }
}
