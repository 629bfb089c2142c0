//! The scene language of seed 003 (its Appendix A): parser, evaluator and diagnostics.
//! The reference is `docs/scene-language.md`.
//!
//! A file is read in one pass, as the seed's `SceneReader` did: `lexer.rs` makes tokens
//! with byte spans, `parser.rs` reads statements through a generic block reader (unknown
//! and duplicated parameters are errors), `expr.rs` evaluates typed expressions in place,
//! `objects.rs`, `blocks.rs`, `transform.rs` and `animate.rs` (keyframes) read the
//! productions, and `build.rs` turns the result into a [`Scene`] (with its rig and timeline). Every error is rendered by `codespan-reporting`
//! into [`LoadError::Scene`] (file:line:col, source line, caret, what was expected).

mod animate;
mod blocks;
mod build;
mod diag;
mod expr;
mod field;
mod lexer;
mod mesh_file;
mod objects;
mod parser;
mod physics;
mod textures;
mod transform;
mod value;

pub use animate::MAX_FRAMES;
pub use blocks::{DEFAULT_ANGLE_DEG, MAX_FALLOFF, MAX_IMAGE_SIDE, MAX_RECURSION};
pub use build::{auto_sphere_detail, MAX_SPHERE_DETAIL, MIN_SPHERE_DETAIL, SILHOUETTE_TOLERANCE_PX};
pub use objects::MAX_CREASE_DEG;
pub use physics::{MAX_PHYXELS, MAX_SUBSTEPS, MIN_PHYXELS};
pub use transform::{rotate_about, scale_about};
pub use value::{BinOp, Value};

use crate::{LoadError, LoadReport, Scene, Warning};
use parser::{Parser, State};
use std::path::Path;

/// Deepest expression nesting accepted: each parenthesis, unary sign, vector `<…>` or
/// `rgb(…)` around a sub-expression is one level. The parser recurses once per level, so
/// this bounds its stack use (about 1 MiB at this depth in an unoptimised build, a tenth
/// of that optimised).
pub const MAX_EXPR_DEPTH: usize = 100;

/// Stack of the thread the parser runs on. The recursion is bounded by
/// [`MAX_EXPR_DEPTH`] and [`MAX_INCLUDE_DEPTH`], but an unoptimised build needs more than
/// a test thread's 2 MiB at those depths, and a caller's thread may be smaller still;
/// a thread of its own makes the bound safe wherever the loader is called from.
const PARSER_STACK_BYTES: usize = 32 << 20;

/// Deepest chain of `include`s accepted.
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// Loads a `.scn` file. Includes and mesh files are found relative to the file naming them.
/// Warnings of the mesh files it reads are dropped; [`load_scn_report`] returns them.
pub fn load_scn(path: &Path) -> Result<Scene, LoadError> {
    load_scn_report(path).map(|r| r.scene)
}

/// Loads a `.scn` file with the warnings of the mesh files it reads (a missing `.mtl`, a
/// skipped glTF primitive), each naming the mesh file, in reading order. A mesh file read
/// twice warns once.
/// Each actor's shading (a mesh's `shading` parameter, §4 of the reference) is applied.
pub fn load_scn_report(path: &Path) -> Result<LoadReport, LoadError> {
    let mut report = load_scn_unshaded(path)?;
    report.scene.apply_shading().map_err(|source| LoadError::Mesh { path: path.to_path_buf(), source })?;
    Ok(report)
}

/// [`load_scn_report`] without applying the actors' shading
/// ([`crate::load_file_unshaded`] for `.scn` files).
pub(crate) fn load_scn_unshaded(path: &Path) -> Result<LoadReport, LoadError> {
    let text = dynray_geom::file::read_to_string(path).map_err(|e| LoadError::io(path, e))?;
    let canon = path.canonicalize().map_err(|e| LoadError::io(path, e))?;
    let dir = canon.parent().map(Path::to_path_buf).unwrap_or_default();
    on_parser_stack(|| parse(path.display().to_string(), text, &dir, Some(canon)))
}

/// Parses scene text, and applies each actor's shading. `name` labels diagnostics;
/// `base_dir` is where relative includes and mesh files are looked up. Mesh-file
/// warnings are dropped (see [`load_scn_report`]).
pub fn parse_scn_str(name: &str, text: &str, base_dir: &Path) -> Result<Scene, LoadError> {
    let mut scene = on_parser_stack(|| parse(name.to_string(), text.to_string(), base_dir, None))?.scene;
    scene.apply_shading().map_err(|source| LoadError::Mesh { path: name.into(), source })?;
    Ok(scene)
}

/// Runs `f` on a thread with [`PARSER_STACK_BYTES`] of stack, or on this one if no
/// thread can be started.
fn on_parser_stack<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    let mut f = Some(f);
    let slot = &mut f;
    let spawned = std::thread::scope(|s| {
        let h = std::thread::Builder::new()
            .name("scn-parser".into())
            .stack_size(PARSER_STACK_BYTES)
            .spawn_scoped(s, move || slot.take().map(|f| f()));
        match h {
            Ok(h) => Some(h.join().unwrap_or_else(|p| std::panic::resume_unwind(p))),
            Err(_) => None,
        }
    });
    match spawned.flatten() {
        Some(v) => v,
        None => (f.take().expect("the closure runs at most once"))(),
    }
}

fn parse(name: String, text: String, dir: &Path, canon: Option<std::path::PathBuf>) -> Result<LoadReport, LoadError> {
    let text = without_bom(text);
    let mut st = State::default();
    let file = st.sources.add(name.clone(), canon.clone().unwrap_or_else(|| name.clone().into()), text);
    st.include_stack.extend(canon);
    let result = Parser::new(&mut st, file, dir.to_path_buf()).and_then(|mut p| p.file());
    if let Err(d) = result {
        return Err(d.into_error(&st.sources));
    }
    let sources = std::mem::take(&mut st.sources);
    let mut warnings: Vec<Warning> = Vec::new();
    for w in std::mem::take(&mut st.warnings) {
        if !warnings.contains(&w) {
            warnings.push(w);
        }
    }
    let mut scene = build::build(st, &mut warnings).map_err(|d| d.into_error(&sources))?;
    crate::texture::untexture_where_no_uvs(&mut scene, Path::new(&name), &mut warnings);
    Ok(LoadReport { scene, warnings })
}

/// Evaluates one expression (`"<1,2,3> * 2"`) with no definitions: what the property
/// tests and the documentation examples use to check the expression language.
pub fn eval_expr(text: &str) -> Result<Value, LoadError> {
    on_parser_stack(|| {
        let mut st = State::default();
        let file = st.sources.add("<expr>".into(), "<expr>".into(), text.to_string());
        let r = Parser::new(&mut st, file, Default::default()).and_then(|mut p| p.expr_to_end());
        r.map_err(|d| d.into_error(&st.sources))
    })
}

/// The text without a UTF-8 byte-order mark at its start (editors on Windows write one;
/// it is no character of the language).
pub(crate) fn without_bom(text: String) -> String {
    match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    }
}
