//! Image textures through every loader: glTF `baseColorTexture` (files, data URIs,
//! buffer views, samplers, `KHR_texture_transform`), OBJ/MTL `map_Kd`, the scene
//! language's `texture`, the shared models (Duck, CesiumMan, BART's PPMs), and the
//! warning a texture that cannot be read gives. Sampling itself is unit-tested in
//! `src/texture/`.

mod support;

use base64::Engine;
use dynray_scene::texture::{ColorSpace, Filter, Wrap};
use dynray_scene::{load_file_report, Color, LoadReport, Scene, Texture};
use glam::Vec2;
use std::path::{Path, PathBuf};
use support::{model, write};

/// A PNG of `w × h` RGB8 pixels (row 0 at the top).
fn png(w: u32, h: u32, rgb: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    image::RgbImage::from_raw(w, h, rgb.to_vec())
        .unwrap()
        .write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
        .unwrap();
    out
}

/// 2 × 2: top row red, green; bottom row blue, white.
fn quad_png() -> Vec<u8> {
    png(2, 2, &[255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255])
}

fn load(p: &Path) -> LoadReport {
    load_file_report(p).unwrap_or_else(|e| panic!("{e}"))
}

/// The texture colour the scene's first material shows at a mesh uv.
fn texel_at(s: &Scene, material: usize, uv: Vec2) -> Color {
    s.materials[material].diffuse_texel(&s.textures, uv)
}

// ---------------------------------------------------------------------------------------
// glTF

/// A one-triangle glTF with TEXCOORD_0 `(0,0) (1,0) (0,1)` in `tri.bin`; the material,
/// textures, images and samplers are `doc_extra` (spliced into the top-level object),
/// and the buffer may carry `image_bytes` after the geometry as buffer view 2.
fn textured_gltf(dir: &Path, name: &str, doc_extra: &str, image_bytes: &[u8]) -> PathBuf {
    let mut bin = Vec::new();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0] {
        bin.extend_from_slice(&v.to_le_bytes());
    }
    bin.extend_from_slice(image_bytes);
    write(dir, "tri.bin", &bin);
    let image_view = if image_bytes.is_empty() {
        String::new()
    } else {
        format!(r#",{{"buffer":0,"byteOffset":60,"byteLength":{}}}"#, image_bytes.len())
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1}},"material":0}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","max":[1,1,0],"min":[0,0,0]}},
                     {{"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":24}}{image_view}],
        "buffers":[{{"byteLength":{},"uri":"tri.bin"}}]{doc_extra}}}"#,
        bin.len()
    );
    write(dir, name, json.as_bytes())
}

/// `"materials"`/`"textures"`/`"images"`/`"samplers"` for one base colour texture.
fn material_json(image: &str, sampler: &str, info_extra: &str) -> String {
    format!(
        r#","materials":[{{"name":"tex","pbrMetallicRoughness":{{"baseColorFactor":[1,0.5,1,1],
        "baseColorTexture":{{"index":0{info_extra}}}}}}}],
        "textures":[{{"source":0,"sampler":0}}],"images":[{image}],"samplers":[{sampler}]"#
    )
}

#[test]
fn gltf_base_color_texture_from_a_file_flips_v_and_keeps_the_factor() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "quad.png", &quad_png());
    let p = textured_gltf(dir.path(), "t.gltf", &material_json(r#"{"uri":"quad.png"}"#, "{}", ""), &[]);
    let r = load(&p);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let s = &r.scene;
    assert_eq!(s.textures.len(), 1);
    assert_eq!((s.textures[0].width(), s.textures[0].height()), (2, 2));
    assert!(s.textures[0].name.ends_with("quad.png"), "{}", s.textures[0].name);
    let t = s.materials[0].diffuse_texture.expect("textured");
    assert_eq!((t.sampler.wrap_u, t.sampler.wrap_v, t.sampler.filter), (Wrap::Repeat, Wrap::Repeat, Filter::Bilinear));
    // The factor stays on the material: base colour = factor × texture.
    assert!((s.materials[0].diffuse.y / s.materials[0].diffuse.x - 0.5).abs() < 1e-6);
    // glTF uv (0, 0) is the image's top-left: stored as dynray (0, 1).
    let uvs = s.actors[0].mesh.uvs.as_ref().expect("TEXCOORD_0 read");
    assert_eq!(uvs, &vec![[0.0, 1.0], [1.0, 1.0], [0.0, 0.0]]);
    // So the vertex with glTF uv (0, 0) sees the top-left texel, red, and (0, 1) blue.
    let near = |uv: [f32; 2], d: [f32; 2]| Vec2::new(uv[0] + d[0], uv[1] + d[1]);
    assert_eq!(texel_at(s, 0, near(uvs[0], [0.25, -0.25])), Color::X);
    assert_eq!(texel_at(s, 0, near(uvs[2], [0.25, 0.25])), Color::Z);
}

#[test]
fn gltf_data_uri_image_with_nearest_clamp_and_texture_transform() {
    let dir = tempfile::tempdir().unwrap();
    let uri = format!(
        r#"{{"uri":"data:image/png;base64,{}"}}"#,
        base64::engine::general_purpose::STANDARD.encode(quad_png())
    );
    let sampler = r#"{"magFilter":9728,"wrapS":33071,"wrapT":33648}"#;
    let transform = r#","extensions":{"KHR_texture_transform":{"offset":[0.5,0],"scale":[0.5,1]}}"#;
    let p = textured_gltf(dir.path(), "d.gltf", &material_json(&uri, sampler, transform), &[]);
    let r = load(&p);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let t = r.scene.materials[0].diffuse_texture.expect("textured");
    assert_eq!(t.sampler.filter, Filter::Nearest);
    assert_eq!((t.sampler.wrap_u, t.sampler.wrap_v), (Wrap::ClampToEdge, Wrap::MirroredRepeat));
    // u' = 0.5 u + 0.5: the left half of the uv square shows the right column.
    assert_eq!(texel_at(&r.scene, 0, Vec2::new(0.1, 0.9)), Color::Y, "top-right texel, green");
    assert_eq!(texel_at(&r.scene, 0, Vec2::new(0.1, 0.1)), Color::ONE, "bottom-right texel, white");
    assert!(r.scene.textures[0].name.contains("d.gltf image 0"), "{}", r.scene.textures[0].name);
}

#[test]
fn gltf_image_in_a_buffer_view_as_glb_files_hold_them() {
    let dir = tempfile::tempdir().unwrap();
    let image = r#"{"bufferView":2,"mimeType":"image/png"}"#;
    let p = textured_gltf(dir.path(), "v.gltf", &material_json(image, "{}", ""), &quad_png());
    let r = load(&p);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    assert_eq!(texel_at(&r.scene, 0, Vec2::new(0.75, 0.25)), Color::ONE);
}

#[test]
fn gltf_missing_or_broken_image_warns_naming_it_and_leaves_the_material_untextured() {
    let dir = tempfile::tempdir().unwrap();
    let p = textured_gltf(dir.path(), "m.gltf", &material_json(r#"{"uri":"gone.png"}"#, "{}", ""), &[]);
    let r = load(&p);
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    let w = r.warnings[0].to_string();
    assert!(w.starts_with(&p.display().to_string()) && w.contains("gone.png") && w.contains("untextured"), "{w}");
    assert!(r.scene.materials[0].diffuse_texture.is_none());
    assert!(r.scene.textures.is_empty());

    write(dir.path(), "junk.png", b"this is no PNG");
    let p = textured_gltf(dir.path(), "j.gltf", &material_json(r#"{"uri":"junk.png"}"#, "{}", ""), &[]);
    let r = load(&p);
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    assert!(r.warnings[0].message.contains("junk.png"), "{}", r.warnings[0]);
    assert!(r.scene.materials[0].diffuse_texture.is_none());
}

#[test]
fn gltf_images_no_used_material_needs_are_not_decoded() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "quad.png", &quad_png());
    // Material 1 (unused) names an image that does not exist: no warning, since it is
    // never read. The used material 0 has its texture.
    let doc = r#","materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}},
        {"pbrMetallicRoughness":{"baseColorTexture":{"index":1}}}],
        "textures":[{"source":0},{"source":1}],"images":[{"uri":"quad.png"},{"uri":"nowhere.png"}]"#;
    let r = load(&textured_gltf(dir.path(), "u.gltf", doc, &[]));
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    assert_eq!(r.scene.textures.len(), 1);
}

#[test]
fn gltf_texture_on_another_uv_set_warns() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "quad.png", &quad_png());
    let p = textured_gltf(dir.path(), "s.gltf", &material_json(r#"{"uri":"quad.png"}"#, "{}", r#","texCoord":1"#), &[]);
    let r = load(&p);
    assert_eq!(r.warnings.len(), 1);
    assert!(r.warnings[0].message.contains("TEXCOORD_1"), "{}", r.warnings[0]);
    assert!(r.scene.materials[0].diffuse_texture.is_none());
}

#[test]
fn duck_loads_its_texture_from_gltf_and_glb() {
    let mut centres = Vec::new();
    for rel in ["Duck/glTF/Duck.gltf", "Duck/glTF-Binary/Duck.glb"] {
        let Some(p) = model(rel) else { return };
        let t0 = std::time::Instant::now();
        let r = load(&p);
        eprintln!("{rel}: loaded in {:.1} ms", t0.elapsed().as_secs_f64() * 1e3);
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        let s = &r.scene;
        assert_eq!(s.textures.len(), 1, "{rel}");
        assert!(s.materials[0].diffuse_texture.is_some(), "{rel}");
        assert!(s.actors[0].mesh.uvs.is_some(), "{rel}: TEXCOORD_0");
        let t = &s.textures[0];
        // The duck's texture is mostly yellow: red and green well above blue.
        let mean = (0..t.height())
            .flat_map(|y| (0..t.width()).map(move |x| (x, y)))
            .fold(Color::ZERO, |m, (x, y)| m + t.texel(x, y))
            / (t.width() * t.height()) as f32;
        assert!(mean.x > 2.0 * mean.z && mean.y > 1.5 * mean.z, "{rel}: mean texel {mean}");
        centres.push((t.width(), t.height(), t.texel(t.width() / 2, t.height() / 2)));
    }
    assert_eq!(centres[0], centres[1], "the .gltf's PNG and the .glb's embedded image agree");
}

#[test]
fn cesium_man_loads_its_jpeg_texture() {
    for rel in ["CesiumMan/glTF/CesiumMan.gltf", "CesiumMan/glTF-Binary/CesiumMan.glb"] {
        let Some(p) = model(rel) else { return };
        let t0 = std::time::Instant::now();
        let r = load(&p);
        eprintln!("{rel}: loaded in {:.1} ms", t0.elapsed().as_secs_f64() * 1e3);
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        assert_eq!(r.scene.textures.len(), 1, "{rel}");
        assert!(r.scene.materials[0].diffuse_texture.is_some());
        let t = &r.scene.textures[0];
        assert!(t.width() >= 256 && t.height() >= 256, "{rel}: {} × {}", t.width(), t.height());
        assert!(r.scene.actors[0].mesh.uvs.is_some());
    }
}

// ---------------------------------------------------------------------------------------
// BART

#[test]
fn bart_ppm_textures_decode() {
    let Some(p) = model("bart/kitchen/TextureFiles/wood.ppm") else { return };
    let t = Texture::load(&p, ColorSpace::Srgb).unwrap_or_else(|e| panic!("{e}"));
    // The file's header says P6 128 × 256.
    assert_eq!((t.width(), t.height()), (128, 256));
    let c = t.texel(64, 128);
    assert!(c.min_element() >= 0.0 && c.max_element() <= 1.0 && c.x > c.z, "wood is warm: {c}");
    // Every PPM of the three BART scenes decodes.
    let root = p.ancestors().nth(3).unwrap().to_path_buf();
    let mut n = 0;
    for scene in ["kitchen", "robot", "museum"] {
        let Ok(dir) = std::fs::read_dir(root.join(scene).join("TextureFiles")) else { continue };
        for e in dir {
            let f = e.unwrap().path();
            if f.extension().is_some_and(|x| x == "ppm") {
                Texture::load(&f, ColorSpace::Srgb).unwrap_or_else(|e| panic!("{e}"));
                n += 1;
            }
        }
    }
    assert!(n >= 10, "found {n} PPMs");
}

// ---------------------------------------------------------------------------------------
// OBJ/MTL

/// A unit quad with `vt` (0,0) at its bottom-left, using material `m` of `lib.mtl`.
const QUAD_OBJ: &str = "mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3 4/4\n";

#[test]
fn obj_map_kd_keeps_obj_uvs_and_applies_offset_and_scale() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("maps")).unwrap();
    write(dir.path(), "maps/quad.png", &quad_png());
    write(dir.path(), "lib.mtl", b"newmtl m\nKd 0.5 0.5 0.5\nmap_Kd maps/quad.png\n");
    let p = write(dir.path(), "q.obj", QUAD_OBJ.as_bytes());
    let r = load(&p);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let s = &r.scene;
    assert_eq!(s.textures.len(), 1);
    // OBJ's vt (0, 0) is the image's bottom-left, as in dynray: uvs are kept as written.
    assert_eq!(s.actors[0].mesh.uvs.as_ref().unwrap()[0], [0.0, 0.0]);
    assert_eq!(texel_at(s, 0, Vec2::new(0.25, 0.25)), Color::Z, "bottom-left texel, blue");
    assert_eq!(texel_at(s, 0, Vec2::new(0.25, 0.75)), Color::X, "top-left texel, red");
    assert_eq!(s.materials[0].diffuse, Color::splat(0.5), "Kd stays; the texture multiplies it");

    // -o and -s: uv × s + o; -clamp on clamps.
    write(dir.path(), "lib.mtl", b"newmtl m\nmap_Kd -s 0.5 0.5 -o 0.5 0 -clamp on maps/quad.png\n");
    let r = load(&p);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let t = r.scene.materials[0].diffuse_texture.unwrap();
    assert_eq!(t.sampler.wrap_u, Wrap::ClampToEdge);
    // (0.5, 0.5) -> (0.75, 0.25): the bottom-right texel.
    assert_eq!(texel_at(&r.scene, 0, Vec2::new(0.5, 0.5)), Color::ONE);
}

#[test]
fn obj_missing_texture_warns_with_the_mtl_line_and_renders_untextured() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "lib.mtl", b"newmtl m\nKd 1 0 0\n\nmap_Kd -bm 1 missing.png\n");
    let p = write(dir.path(), "q.obj", QUAD_OBJ.as_bytes());
    let r = load(&p);
    let msgs: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
    let mtl = dir.path().join("lib.mtl").display().to_string();
    let missing = msgs.iter().find(|m| m.contains("missing.png")).unwrap_or_else(|| panic!("{msgs:?}"));
    assert!(missing.starts_with(&format!("{mtl}:4: material `m`")), "{missing}");
    assert!(missing.contains("untextured"), "{missing}");
    assert!(msgs.iter().any(|m| m.starts_with(&format!("{mtl}:4: `map_Kd`: option `-bm`"))), "{msgs:?}");
    assert_eq!(msgs.len(), 2, "{msgs:?}");
    assert!(r.scene.materials[0].diffuse_texture.is_none());
    assert!(r.scene.textures.is_empty());
}

#[test]
fn obj_faces_without_vt_render_their_textured_material_untextured_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "quad.png", &quad_png());
    write(dir.path(), "lib.mtl", b"newmtl m\nmap_Kd quad.png\n");
    let p = write(dir.path(), "n.obj", b"mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
    let r = load(&p);
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    assert!(r.warnings[0].message.contains("no texture coordinates"), "{}", r.warnings[0]);
    let m = r.scene.actors[0].materials[0] as usize;
    assert!(r.scene.materials[m].diffuse_texture.is_none());
}

#[test]
fn obj_texture_shared_by_two_materials_is_decoded_once() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "quad.png", &quad_png());
    write(dir.path(), "lib.mtl", b"newmtl m\nmap_Kd quad.png\nnewmtl n\nKd 1 0 0\nmap_Kd quad.png\n");
    let obj = format!("{QUAD_OBJ}usemtl n\nf 1/1 3/3 4/4\n");
    let r = load(&write(dir.path(), "two.obj", obj.as_bytes()));
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    assert_eq!(r.scene.textures.len(), 1);
    let [a, b] = [0, 1].map(|i| r.scene.materials[i].diffuse_texture.unwrap().texture);
    assert_eq!(a, b);
}

// ---------------------------------------------------------------------------------------
// scene language

/// A camera and a light: a scene file without lights warns, which these tests would count.
const CAMERA: &str =
    "camera { perspective position <0, 0, 5> to <0, 0, 0> up <0, 1, 0> }\nlight { position <0, 5, 5> }\n";

#[test]
fn scn_texture_on_a_box_is_relative_to_the_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("scenes/maps")).unwrap();
    write(dir.path(), "scenes/maps/quad.png", &quad_png());
    let scn = format!(
        "{CAMERA}define tiles material {{ color rgb(1, 0.5, 1) texture \"maps/quad.png\" }}\n\
         box {{ center <0, 0, 0> orientation <0, 0, 0> scale <2, 2, 2> material tiles }}\n\
         box {{ center <3, 0, 0> orientation <0, 0, 0> scale <1, 1, 1> material tiles }}\n"
    );
    let p = write(dir.path(), "scenes/t.scn", scn.as_bytes());
    let r = load(&p);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let s = &r.scene;
    assert_eq!(s.textures.len(), 1, "one file, one texture");
    let m = &s.materials[s.actors[0].materials[0] as usize];
    assert!(m.diffuse_texture.is_some());
    // colour × finish as before; the texture multiplies on top.
    assert!((m.diffuse - Color::new(0.9, 0.45, 0.9)).abs().max_element() < 1e-6, "{}", m.diffuse);
    assert_eq!(m.diffuse_texel(&s.textures, Vec2::new(0.25, 0.75)), Color::X);
    let f = s.frame(0.0);
    assert!(f.mesh.uvs.is_some() && f.textures.len() == 1);
}

#[test]
fn scn_missing_texture_warns_with_the_line_and_loads_untextured() {
    let dir = tempfile::tempdir().unwrap();
    let scn = format!(
        "{CAMERA}box {{ center <0, 0, 0> orientation <0, 0, 0> scale <1, 1, 1>\n\
         material {{ color rgb(1, 1, 1)\n texture \"nope.png\" }} }}\n"
    );
    let p = write(dir.path(), "m.scn", scn.as_bytes());
    let r = load(&p);
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    let w = r.warnings[0].to_string();
    // Line 5: the camera and light take lines 1 and 2.
    assert!(w.starts_with(&format!("{}:5: texture: ", p.display())), "{w}");
    assert!(w.contains("nope.png") && w.contains("untextured"), "{w}");
    assert!(r.scene.materials[0].diffuse_texture.is_none());
    assert!(r.scene.textures.is_empty());
}

#[test]
fn scn_textures_of_unused_definitions_are_not_read() {
    let dir = tempfile::tempdir().unwrap();
    let scn = format!(
        "{CAMERA}define unused material {{ color rgb(1, 1, 1) texture \"nowhere.png\" }}\n\
         sphere {{ center <0, 0, 0> radius 1 }}\n"
    );
    let r = load(&write(dir.path(), "u.scn", scn.as_bytes()));
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    assert!(r.scene.textures.is_empty());
}

#[test]
fn scn_texture_on_a_sphere_warns_that_it_has_no_uvs() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "quad.png", &quad_png());
    let scn = format!(
        "{CAMERA}define ball material {{ color rgb(1, 1, 1) texture \"quad.png\" }}\n\
         sphere {{ center <0, 0, 0> radius 1 material ball }}\n"
    );
    let p = write(dir.path(), "s.scn", scn.as_bytes());
    let r = load(&p);
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    let w = r.warnings[0].to_string();
    assert!(w.contains("material `ball` has a texture but the mesh has no texture coordinates"), "{w}");
    assert!(r.scene.materials[r.scene.actors[0].materials[0] as usize].diffuse_texture.is_none());
}

#[test]
fn scn_mesh_files_keep_their_own_textures_beside_the_scene_files() {
    let dir = tempfile::tempdir().unwrap();
    // The scene's own texture is a plain green 1 × 1; the OBJ's is the quad.
    write(dir.path(), "green.png", &png(1, 1, &[0, 255, 0]));
    write(dir.path(), "quad.png", &quad_png());
    write(dir.path(), "lib.mtl", b"newmtl m\nmap_Kd quad.png\n");
    write(dir.path(), "q.obj", QUAD_OBJ.as_bytes());
    let scn = format!(
        "{CAMERA}box {{ center <0, 0, 0> orientation <0, 0, 0> scale <1, 1, 1>\n\
         material {{ color rgb(1, 1, 1) texture \"green.png\" }} }}\n\
         mesh {{ file \"q.obj\" }}\n"
    );
    let r = load(&write(dir.path(), "mix.scn", scn.as_bytes()));
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let s = &r.scene;
    assert_eq!(s.textures.len(), 2);
    let texel =
        |actor: usize, uv: Vec2| s.materials[s.actors[actor].materials[0] as usize].diffuse_texel(&s.textures, uv);
    assert_eq!(texel(0, Vec2::new(0.5, 0.5)), Color::Y, "the box shows the scene's texture");
    assert_eq!(texel(1, Vec2::new(0.25, 0.25)), Color::Z, "the OBJ shows its own, renumbered");
    // Replacing the mesh file's material drops its texture.
    let scn = format!("{CAMERA}mesh {{ file \"q.obj\" material {{ color rgb(1, 0, 0) }} }}\n");
    let r = load(&write(dir.path(), "plain.scn", scn.as_bytes()));
    assert!(r.scene.materials.iter().all(|m| m.diffuse_texture.is_none()));
    assert!(r.scene.textures.is_empty(), "the OBJ's texture is no longer used");
}

#[test]
fn scn_texture_given_twice_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let scn = format!("{CAMERA}sphere {{ center <0, 0, 0> radius 1 material {{ color rgb(1, 1, 1) texture \"a.png\" texture \"b.png\" }} }}\n");
    let e = load_file_report(&write(dir.path(), "d.scn", scn.as_bytes())).unwrap_err().to_string();
    assert!(e.contains("duplicated parameter `texture`"), "{e}");
}

#[test]
fn gltf_images_without_a_source_or_mime_type_warn_instead_of_panicking() {
    let dir = tempfile::tempdir().unwrap();
    for (image, why) in [("{}", "neither a uri nor a bufferView"), (r#"{"bufferView":1}"#, "no mimeType")] {
        let p = textured_gltf(dir.path(), "bad.gltf", &material_json(image, "{}", ""), &[]);
        let r = load(&p);
        assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
        assert!(r.warnings[0].message.contains(why), "{}", r.warnings[0]);
        assert!(r.scene.materials[0].diffuse_texture.is_none());
    }
}
