//! Textures through the binary: an OBJ + MTL with a generated PNG renders the texture's
//! colour (the `albedo` AOV exactly, the image in hue), a texture that cannot be found
//! is one warning naming it and the `.mtl` line while the render still succeeds, and
//! `info` counts a scene's textures.

mod support;

use dynray_scene::texture::srgb_to_linear;
use std::path::Path;
use support::{dynray, ok, scenes_dir};

/// The sRGB colour of the generated texture: a warm orange no untextured material has.
const ORANGE: [u8; 3] = [200, 60, 20];

/// Writes `quad.obj` (a square facing +z, with `vt`), `lib.mtl` naming `texture` with
/// `Kd 1 1 1`, and a 4 × 4 PNG of [`ORANGE`] as `orange.png`.
fn write_quad(dir: &Path, texture: &str) {
    let obj = "mtllib lib.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
               vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3 4/4\n";
    std::fs::write(dir.join("quad.obj"), obj).unwrap();
    std::fs::write(dir.join("lib.mtl"), format!("newmtl m\nKd 1 1 1\nmap_Kd {texture}\n")).unwrap();
    let pixels: Vec<u8> = ORANGE.repeat(16);
    image::RgbImage::from_raw(4, 4, pixels).unwrap().save(dir.join("orange.png")).unwrap();
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn obj_map_kd_renders_the_texture_colour() {
    let dir = tempfile::tempdir().unwrap();
    write_quad(dir.path(), "orange.png");
    let obj = dir.path().join("quad.obj");
    let exr = dir.path().join("albedo.exr");
    let o = ok(dynray(&[
        "render",
        obj.to_str().unwrap(),
        "--aov",
        "albedo",
        "-o",
        exr.to_str().unwrap(),
        "--width",
        "32",
        "--height",
        "24",
    ]));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    let image = exr::prelude::read_all_flat_layers_from_file(&exr).unwrap();
    let layer = &image.layer_data[0];
    let channel = |name: &str| -> Vec<f32> {
        let c = layer.channel_data.list.iter().find(|c| c.name.to_string() == name).unwrap();
        c.sample_data.values_as_f32().collect()
    };
    let centre = 12 * 32 + 16;
    let got = [channel("R")[centre], channel("G")[centre], channel("B")[centre]];
    // Kd 1 × the texel, decoded from sRGB: the MTL's colour is the image's.
    let want = ORANGE.map(|c| srgb_to_linear(c as f32 / 255.0));
    for k in 0..3 {
        assert!((got[k] - want[k]).abs() < 1e-5, "albedo at the centre is {got:?}, the texture's colour is {want:?}");
    }

    let png = dir.path().join("quad.png");
    ok(dynray(&["render", obj.to_str().unwrap(), "-o", png.to_str().unwrap(), "--width", "32", "--height", "24"]));
    let img = image::open(&png).unwrap().to_rgb8();
    let p = img.get_pixel(16, 12).0;
    assert!(p[0] > p[1] && p[1] > p[2] && p[0] > 2 * p[1], "the shaded quad is orange: {p:?}");
}

#[test]
fn a_missing_texture_is_one_warning_naming_it_and_the_render_succeeds() {
    let dir = tempfile::tempdir().unwrap();
    write_quad(dir.path(), "textures/gone.png");
    let obj = dir.path().join("quad.obj");
    let png = dir.path().join("quad.png");
    let o =
        ok(dynray(&["render", obj.to_str().unwrap(), "-o", png.to_str().unwrap(), "--width", "32", "--height", "24"]));
    let err = stderr(&o);
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("dynray: warning: ")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    let mtl = dir.path().join("lib.mtl");
    assert!(warnings[0].contains(&format!("{}:3: material `m`", mtl.display())), "{err}");
    assert!(warnings[0].contains("gone.png") && warnings[0].contains("untextured"), "{err}");
    // Untextured: Kd 1 1 1 renders grey, not orange.
    let p = image::open(&png).unwrap().to_rgb8().get_pixel(16, 12).0;
    assert!(p[0].abs_diff(p[2]) < 3, "untextured grey: {p:?}");
}

#[test]
fn info_counts_textures() {
    let dir = tempfile::tempdir().unwrap();
    write_quad(dir.path(), "orange.png");
    let o = ok(dynray(&["info", dir.path().join("quad.obj").to_str().unwrap()]));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("textures    1 ("), "{out}");
    let duck = scenes_dir().join("Duck/glTF-Binary/Duck.glb");
    if duck.is_file() {
        let o = ok(dynray(&["info", duck.to_str().unwrap()]));
        assert!(String::from_utf8_lossy(&o.stdout).contains("textures    1 ("));
    }
    let o = ok(dynray(&["info", "examples/whitted.scn"]));
    assert!(String::from_utf8_lossy(&o.stdout).contains("textures    0\n"));
}
