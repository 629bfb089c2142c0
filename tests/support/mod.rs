//! Helpers shared by the root package's integration tests: paths, running the binary,
//! and comparing a film with a golden PNG (the rule of the render crate's golden test).
#![allow(dead_code)] // each test file uses a different subset

use dynray_render::Film;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The root package's directory (the checkout).
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `examples/` in the checkout.
pub fn examples_dir() -> PathBuf {
    root().join("examples")
}

/// The test models: `$DYNRAY_SCENES`, else `../shared/scenes` beside the checkout.
pub fn scenes_dir() -> PathBuf {
    std::env::var_os("DYNRAY_SCENES").map(PathBuf::from).unwrap_or_else(|| root().join("../shared/scenes"))
}

/// Runs the `dynray` binary with `args` from the checkout's root, so relative paths
/// such as `examples/whitted.scn` resolve as they do in the README.
pub fn dynray(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dynray")).current_dir(root()).args(args).output().expect("run dynray")
}

/// Fails with the command's stderr when it did not exit successfully.
#[track_caller]
pub fn ok(o: Output) -> Output {
    assert!(o.status.success(), "dynray failed: {}\n{}", o.status, String::from_utf8_lossy(&o.stderr));
    o
}

/// True when the goldens are to be rewritten (`DYNRAY_BLESS=1`).
pub fn blessing() -> bool {
    std::env::var_os("DYNRAY_BLESS").is_some_and(|v| v == "1")
}

/// How an 8-bit image differs from another of the same size.
#[derive(Clone, Copy, Debug)]
pub struct Diff {
    /// Mean absolute difference over all channels, in 8-bit levels.
    pub mean: f64,
    /// Channels that differ by more than 16 levels.
    pub large: usize,
    /// Largest channel difference.
    pub max: u8,
    /// Channels compared.
    pub channels: usize,
}

impl Diff {
    /// Compares two equally long channel arrays.
    pub fn of(got: &[u8], want: &[u8]) -> Diff {
        assert_eq!(got.len(), want.len(), "images of different sizes");
        let diffs: Vec<u8> = got.iter().zip(want).map(|(a, b)| a.abs_diff(*b)).collect();
        let mean = diffs.iter().map(|&d| d as f64).sum::<f64>() / diffs.len().max(1) as f64;
        let large = diffs.iter().filter(|&&d| d > 16).count();
        let max = diffs.iter().copied().max().unwrap_or(0);
        Diff { mean, large, max, channels: diffs.len() }
    }

    /// The render crate's rule: mean below one level (1/255) and at most 0.2 % of
    /// channels off by more than 16 levels (a silhouette or shadow-edge pixel may flip
    /// under another compiler's float code; a real shading change moves far more).
    pub fn within_tolerance(&self) -> bool {
        self.mean < 1.0 && self.large * 500 <= self.channels
    }
}

/// Compares `film` with the golden PNG `tests/golden/<name>`, or writes it when
/// [`blessing`]. Returns a description of the failure instead of panicking, so a test
/// over several scenes can report all of them.
pub fn check_golden(film: &Film, name: &str) -> Result<(), String> {
    let path = root().join("tests/golden").join(name);
    if blessing() {
        dynray_render::write_image(film, &path).map_err(|e| format!("{}: {e}", path.display()))?;
        eprintln!("wrote {}", path.display());
        return Ok(());
    }
    let want =
        image::open(&path).map_err(|e| format!("{}: {e} (regenerate with DYNRAY_BLESS=1)", path.display()))?.to_rgb8();
    let size = (film.width(), film.height());
    if want.dimensions() != size {
        return Err(format!("{}: golden is {:?}, render is {size:?}", path.display(), want.dimensions()));
    }
    let d = Diff::of(&film.to_srgb8(), want.as_raw());
    if d.within_tolerance() {
        Ok(())
    } else {
        Err(format!(
            "{name} differs from golden: mean {:.3} levels, {} of {} channels off by > 16, max {}",
            d.mean, d.large, d.channels, d.max
        ))
    }
}

/// Whether `dynray info --gpu` finds an adapter; without one the GPU tests skip, saying
/// which package to install — unless `DYNRAY_REQUIRE_GPU=1` (CI), where that fails.
pub fn gpu_present() -> bool {
    let info = dynray(&["info", "--gpu"]);
    if info.status.success() {
        return true;
    }
    let why = String::from_utf8_lossy(&info.stderr).to_string();
    assert!(why.contains("mesa-vulkan-drivers"), "{why}");
    assert!(std::env::var("DYNRAY_REQUIRE_GPU").map_or(true, |v| v != "1"), "no GPU: {why}");
    skipped(why.trim());
    false
}

/// Says that the running test skipped, and why, where a plain `cargo test` shows it (a
/// `SKIPPED` line beside the `ok`): libtest captures the print macros' output, not writes
/// to the stderr handle.
pub fn skipped(why: &str) {
    use std::io::Write;
    let test = std::thread::current().name().unwrap_or("a test").to_string();
    let _ = writeln!(std::io::stderr(), "SKIPPED {test}: {why}");
}

/// Every channel of the first layer of an EXR (channel after channel, each row-major).
pub fn read_exr_channels(path: &Path) -> Vec<f32> {
    let image =
        exr::prelude::read_all_flat_layers_from_file(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    image.layer_data[0].channel_data.list.iter().flat_map(|c| c.sample_data.values_as_f32()).collect()
}

/// The largest absolute difference between two equally long images' values.
pub fn max_abs_difference(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len(), "images of different sizes");
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max)
}

/// Asserts a clean failure: exit 1, one `dynray:` message mentioning `needle`, no panic.
#[track_caller]
pub fn fails_with(o: Output, needle: &str) {
    exits_with(o, 1, needle);
}

/// Asserts an option (or combination) refused as a usage error before any work: exit 2,
/// as for clap's own, with a `dynray:` message mentioning `needle`.
#[track_caller]
pub fn refused_as_usage(o: Output, needle: &str) {
    exits_with(o, 2, needle);
}

#[track_caller]
fn exits_with(o: Output, code: i32, needle: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "expected exit {code}, got {:?}: {err}", o.status);
    assert!(err.contains("dynray: "), "message should say `dynray: `: {err}");
    assert!(err.contains(needle), "message should mention {needle:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// Writes rays as the (N, 8) float32 `.npy` that `trace-rays --rays` reads.
pub fn write_rays_npy(path: &Path, rows: &[[f32; 8]]) {
    use npyz::WriterBuilder;
    let mut w = npyz::WriteOptions::<f32>::new()
        .default_dtype()
        .shape(&[rows.len() as u64, 8])
        .writer(std::fs::File::create(path).unwrap())
        .begin_nd()
        .unwrap();
    w.extend(rows.iter().flatten().copied()).unwrap();
    w.finish().unwrap();
}
