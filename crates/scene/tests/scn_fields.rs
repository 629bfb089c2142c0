//! The scene language's `adf { … }` block (docs/scene-language.md §4.6): where the file
//! is looked for, the material and transform it gets, and its errors.

use dynray_scene::{parse_scn_str, LoadError, Material, Scene};
use glam::{Mat4, Vec3};
use std::path::Path;

fn parse(text: &str, dir: &Path) -> Scene {
    parse_scn_str("test.scn", text, dir).unwrap_or_else(|e| panic!("unexpected error:\n{e}"))
}

fn fail(text: &str, dir: &Path) -> (usize, String) {
    match parse_scn_str("test.scn", text, dir) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(LoadError::Scene { line, message, .. }) => (line, message),
        Err(e) => panic!("expected a scene diagnostic, got {e:?}"),
    }
}

#[test]
fn fields_are_placed_with_their_file_material_and_transforms_in_order() {
    let dir = tempfile::tempdir().unwrap();
    // The parser checks only that the file exists; its contents are the renderer's.
    std::fs::write(dir.path().join("a.adf"), b"").unwrap();
    let text = "define red material { color rgb(1, 0, 0) }\n\
                sphere { center <0, 0, 0> radius 1 }\n\
                adf { file \"a.adf\" }\n\
                adf { file \"a.adf\" material red transform { scale <0, 0, 0> <2, 2, 2> } transform { translate <1, 0, 0> } }\n";
    let scene = parse(text, dir.path());
    assert_eq!(scene.actors.len(), 1, "a field is no actor");
    let [plain, placed] = &scene.distance_fields[..] else { panic!("{:?}", scene.distance_fields) };
    assert_eq!(plain.file, dir.path().join("a.adf"));
    assert!(plain.transform.is_identity());
    // Without a material the field shares the scene's default one with the sphere.
    assert_eq!(plain.material, scene.actors[0].materials[0]);
    assert_eq!(scene.materials[plain.material as usize], Material::default());
    assert_ne!(placed.material, plain.material);
    assert_ne!(scene.materials[placed.material as usize], Material::default());
    // Scale first, then translate: the field's origin lands at x = 1, its unit x at 3.
    let m: Mat4 = placed.transform.matrix();
    assert_eq!(m.transform_point3(Vec3::ZERO), Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(m.transform_point3(Vec3::X), Vec3::new(3.0, 0.0, 0.0));
    assert_eq!(scene.frame(0.0).distance_fields, scene.distance_fields);
}

#[test]
fn missing_files_and_keys_are_errors_at_the_statement() {
    let dir = tempfile::tempdir().unwrap();
    let (line, msg) = fail("sphere { center <0, 0, 0> radius 1 }\nadf { file \"nowhere.adf\" }\n", dir.path());
    assert_eq!(line, 2);
    assert!(msg.contains("nowhere.adf"), "{msg}");
    let (line, msg) = fail("\nadf { material { color rgb(1, 1, 1) } }\n", dir.path());
    assert_eq!(line, 2);
    assert!(msg.contains("missing parameter `file`"), "{msg}");
    std::fs::write(dir.path().join("a.adf"), b"").unwrap();
    let (_, msg) = fail("adf { file \"a.adf\" animate { } }\n", dir.path());
    assert!(msg.contains("unknown parameter `animate`"), "{msg}");
    let (_, msg) = fail("adf { file \"a.adf\" file \"a.adf\" }\n", dir.path());
    assert!(msg.contains("duplicated parameter `file`"), "{msg}");
}
