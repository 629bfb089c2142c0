//! Image files: formats by extension, round trips, and failures that leave no partial
//! file and name the path.

use dynray_render::{write_image, Film, RenderError};
use dynray_scene::Color;
use std::path::{Path, PathBuf};

/// A fresh directory under cargo's per-target temporary directory.
fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("render-output-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn gradient() -> Film {
    let mut f = Film::new(5, 3);
    for y in 0..3 {
        for x in 0..5 {
            f.set(x, y, Color::new(x as f32 / 4.0, y as f32 / 2.0, 2.5));
        }
    }
    f
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

#[test]
fn png_and_bmp_round_trip_as_srgb8() {
    let dir = scratch("roundtrip");
    let film = gradient();
    for name in ["a.png", "b.BMP"] {
        let p = dir.join(name);
        write_image(&film, &p).unwrap();
        let img = image::open(&p).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (5, 3));
        assert_eq!(img.into_raw(), film.to_srgb8(), "{name}");
    }
    assert_eq!(entries(&dir), ["a.png", "b.BMP"], "no temporary files are left behind");
}

#[test]
fn exr_keeps_linear_floats() {
    let dir = scratch("exr");
    let p = dir.join("hdr.exr");
    write_image(&gradient(), &p).unwrap();
    let bytes = std::fs::read(&p).unwrap();
    // OpenEXR magic number 20000630, little-endian.
    assert_eq!(&bytes[..4], &[0x76, 0x2f, 0x31, 0x01]);
    // Values above 1 survive: read the file back.
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        &p,
        |res: Vec2<usize>, _| vec![[0f32; 3]; res.width() * res.height()],
        |px: &mut Vec<[f32; 3]>, pos, (r, g, b, _a): (f32, f32, f32, f32)| px[pos.y() * 5 + pos.x()] = [r, g, b],
    )
    .unwrap();
    let px = &image.layer_data.channel_data.pixels;
    assert_eq!(px[2 * 5 + 4], [1.0, 1.0, 2.5]);
    assert_eq!(px[0], [0.0, 0.0, 2.5]);
}

#[test]
fn unknown_extension_is_an_error_naming_the_file() {
    let dir = scratch("unknown");
    for name in ["picture.jpg", "no_extension"] {
        let p = dir.join(name);
        let err = write_image(&gradient(), &p).unwrap_err();
        assert!(matches!(err, RenderError::UnknownFormat { .. }), "{err:?}");
        assert!(err.to_string().contains(name), "{err}");
    }
    assert!(entries(&dir).is_empty());
}

#[test]
fn unwritable_path_is_an_error_naming_the_path() {
    let dir = scratch("unwritable");
    let p = dir.join("missing-dir").join("out.png");
    let err = write_image(&gradient(), &p).unwrap_err();
    assert!(matches!(err, RenderError::Io { .. }), "{err:?}");
    assert!(err.to_string().contains(&p.display().to_string()), "{err}");
    assert!(entries(&dir).is_empty());
}

#[test]
fn failed_write_leaves_the_target_untouched_and_no_temporary() {
    let dir = scratch("failed");
    // A directory where the image should go: the rename over it fails.
    let target = dir.join("taken.png");
    std::fs::create_dir(&target).unwrap();
    let err = write_image(&gradient(), &target).unwrap_err();
    assert!(err.to_string().contains("taken.png"), "{err}");
    assert!(target.is_dir());
    assert_eq!(entries(&dir), ["taken.png"]);
    // An empty film cannot be written; an existing file keeps its content.
    let old = dir.join("old.png");
    std::fs::write(&old, b"previous").unwrap();
    let err = write_image(&Film::new(0, 4), &old).unwrap_err();
    assert!(matches!(err, RenderError::EmptyImage { .. }), "{err:?}");
    assert_eq!(std::fs::read(&old).unwrap(), b"previous");
    assert_eq!(entries(&dir), ["old.png", "taken.png"]);
}
