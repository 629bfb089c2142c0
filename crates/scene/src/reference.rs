//! A model's references to other files — glTF buffers and images, OBJ `mtllib` and MTL
//! maps, Mitsuba includes, shapes and textures, AFF includes and textures — stay inside
//! the model's own folder tree (issue 43): a downloaded model must not make dynray read
//! `/etc/passwd`, `../../../home/me/.ssh/…` or `file:///…`, nor quote such a file in an
//! error.
//!
//! Each loader names its **root**, the folder of the file the user gave it (AFF adds
//! BART's `TextureFiles/` beside an `aff/` folder), and checks every reference against it
//! after links and `..` are resolved. A reference to a file that does not exist passes
//! (its reader then says it is missing, which reveals nothing). The scene language is
//! not checked: a `.scn` is the user's own composition of models from anywhere, as a
//! Makefile is.
//!
//! `DYNRAY_ALLOW_OUTSIDE_REFERENCES=1`, or [`allow_outside`] (the command line's
//! `--allow-outside-references`), lifts the rule for models the user trusts.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU8, Ordering};

/// The environment variable that lifts the rule.
pub const ALLOW_ENV: &str = "DYNRAY_ALLOW_OUTSIDE_REFERENCES";

/// 0: not decided yet (read the environment); 1: contained; 2: allowed.
static ALLOWED: AtomicU8 = AtomicU8::new(0);

/// Lets models reference files outside their folder tree, for this process.
pub fn allow_outside(allow: bool) {
    ALLOWED.store(if allow { 2 } else { 1 }, Ordering::Relaxed);
}

fn outside_allowed() -> bool {
    match ALLOWED.load(Ordering::Relaxed) {
        0 => {
            let allow = std::env::var(ALLOW_ENV).is_ok_and(|v| v == "1");
            allow_outside(allow);
            allow
        }
        v => v == 2,
    }
}

/// The folders a model's references must stay in.
#[derive(Clone, Debug)]
pub struct Root {
    /// The model's folder as given (named in errors).
    folder: PathBuf,
    /// Canonical folders (those that exist).
    folders: Vec<PathBuf>,
}

impl Root {
    /// The folder of the model file `model`, plus `extra` folders (BART's `TextureFiles/`).
    pub fn of(model: &Path, extra: &[PathBuf]) -> Root {
        Root::folder(model.parent().unwrap_or(Path::new("")), extra)
    }

    /// The folder `dir` (a model's), plus `extra` folders.
    pub fn folder(dir: &Path, extra: &[PathBuf]) -> Root {
        let dir = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
        let folders = std::iter::once(dir.to_path_buf())
            .chain(extra.iter().cloned())
            .filter_map(|d| d.canonicalize().ok())
            .collect();
        Root { folder: dir.to_path_buf(), folders }
    }

    /// `path` (a reference as resolved by the loader) if it stays inside the root or does
    /// not exist; otherwise an error that names the reference and the rule, never the
    /// file's content.
    pub fn check(&self, path: &Path) -> Result<PathBuf, String> {
        if outside_allowed() {
            return Ok(path.to_path_buf());
        }
        let Ok(real) = path.canonicalize() else {
            return Ok(path.to_path_buf());
        };
        if self.folders.iter().any(|f| real.starts_with(f)) {
            return Ok(path.to_path_buf());
        }
        Err(format!(
            "{} is outside {}, the folder of the model that names it: a model's references must stay \
             inside its folder (set {ALLOW_ENV}=1 or pass --allow-outside-references to allow it)",
            path.display(),
            self.folder.display()
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_stay_inside_the_model_folder() {
        let tmp = std::env::temp_dir().join(format!("dynray-reference-{}", std::process::id()));
        let model_dir = tmp.join("model");
        std::fs::create_dir_all(model_dir.join("textures")).unwrap();
        std::fs::create_dir_all(tmp.join("TextureFiles")).unwrap();
        for f in ["model/textures/a.png", "secret.txt", "TextureFiles/t.ppm"] {
            std::fs::write(tmp.join(f), "x").unwrap();
        }
        let model = model_dir.join("m.gltf");
        let root = Root::of(&model, &[]);
        assert!(root.check(&model_dir.join("textures/a.png")).is_ok());
        assert!(root.check(&model_dir.join("missing.bin")).is_ok(), "missing: the reader says so");
        let e = root.check(&model_dir.join("../secret.txt")).unwrap_err();
        assert!(e.contains("secret.txt") && e.contains("the folder of the model") && e.contains(ALLOW_ENV), "{e}");
        assert!(root.check(Path::new("/etc/hostname")).is_err() || !Path::new("/etc/hostname").exists());
        #[cfg(unix)]
        {
            let link = model_dir.join("innocent.png");
            let _ = std::fs::remove_file(&link);
            std::os::unix::fs::symlink(tmp.join("secret.txt"), &link).unwrap();
            assert!(root.check(&link).is_err(), "a link out of the folder");
        }
        let bart = Root::of(&model, &[tmp.join("TextureFiles")]);
        assert!(bart.check(&model_dir.join("../TextureFiles/t.ppm")).is_ok());
        let _ = std::fs::remove_dir_all(tmp);
    }
}
