//! The demo scene against a stored image, with a tolerance.
//!
//! The golden is `tests/golden/demo_160x120.png`: the demo scene with sphere detail 8
//! (so brute force renders it in seconds) at 160 × 120. After a deliberate change to the
//! integrator or the scene, look at the new image and regenerate the golden with
//!
//! ```text
//! DYNRAY_BLESS=1 cargo test -p dynray-render --test golden
//! ```
//!
//! Tolerance: the mean absolute difference over all 8-bit channels must stay below one
//! level (1/255), and at most 0.2 % of channels may differ by more than 16 levels (a
//! silhouette or shadow-edge pixel can flip under a different compiler's float code;
//! a real shading change moves far more).

mod common;

use dynray_scene::demo::demo_scene_with;
use std::path::Path;

#[test]
fn demo_scene_matches_golden_image() {
    let mut frame = demo_scene_with(8).frame(0.0);
    frame.settings.width = 160;
    frame.settings.height = 120;
    let (film, stats) = common::render_brute(&frame);
    assert!(stats.secondary_rays > 0 && stats.shadow_rays > 0, "{stats:?}");
    let got = film.to_srgb8();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/demo_160x120.png");
    if std::env::var_os("DYNRAY_BLESS").is_some_and(|v| v == "1") {
        dynray_render::write_image(&film, &path).unwrap();
        eprintln!("wrote {}", path.display());
        return;
    }
    let want = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (regenerate with DYNRAY_BLESS=1)", path.display()))
        .to_rgb8();
    assert_eq!(want.dimensions(), (160, 120));
    let want = want.into_raw();
    let diffs: Vec<u8> = got.iter().zip(&want).map(|(a, b)| a.abs_diff(*b)).collect();
    let mean = diffs.iter().map(|&d| d as f64).sum::<f64>() / diffs.len() as f64;
    let large = diffs.iter().filter(|&&d| d > 16).count();
    let max = diffs.iter().copied().max().unwrap_or(0);
    assert!(
        mean < 1.0 && large * 500 <= diffs.len(),
        "demo differs from golden: mean {mean:.3} levels, {large} channels off by > 16, max {max}"
    );
}
