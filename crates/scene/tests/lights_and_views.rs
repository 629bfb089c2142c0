//! Lights that files bring and the view a file without a camera gets (issue 17):
//! OBJ emitters through a scene file's `mesh { file }`, glTF `KHR_lights_punctual`, the
//! warning for a scene without lights, and the default cameras.

mod support;

use dynray_scene::{load_file, load_file_report, parse_scn_str, Camera, Color, LightKind};
use glam::Vec3;
use std::f32::consts::PI;
use support::*;

fn cornell() -> Option<std::path::PathBuf> {
    model("cornell-box/mcguire-obj/CornellBox-Original.obj")
}

#[test]
fn obj_lamp_placed_through_a_scene_file_keeps_its_light_moved_with_it() {
    let Some(obj) = cornell() else { return };
    let direct = load_file(&obj).unwrap();
    assert_eq!(direct.lights.len(), 1, "the Cornell box's lamp");
    let LightKind::Point { position: lamp, .. } = direct.lights[0].kind else { panic!("a point light") };
    let dir = tempfile::tempdir().unwrap();
    let scn = format!(
        "camera {{ perspective position <0, 1, 4> to <0, 1, 0> up <0, 1, 0> angle 40 }}\n\
         mesh {{ file \"{}\" transform {{ translate <10, 0, 0> }} }}\n\
         mesh {{ file \"{}\" }}\n",
        obj.display(),
        obj.display()
    );
    let r = load_file_report(&write(dir.path(), "two.scn", scn.as_bytes())).unwrap();
    assert_eq!(r.scene.lights.len(), 2, "each placed box brings its lamp, no default light");
    let moved: Vec<Vec3> = r
        .scene
        .lights
        .iter()
        .map(|l| match l.kind {
            LightKind::Point { position, .. } => position,
            _ => panic!("a point light"),
        })
        .collect();
    assert!((moved[0] - (lamp + Vec3::new(10.0, 0.0, 0.0))).length() < 1e-5, "{moved:?} vs {lamp}");
    assert_eq!(moved[1], lamp);
    assert_eq!(r.scene.lights[0].color, direct.lights[0].color);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
}

/// The lamp's stand-in stays one through a scene file (the lamp still emits there, for the
/// path tracer), unless a `material` modifier replaces the lamp's material: then nothing
/// emits and the point light is an ordinary light, which the path tracer samples too.
#[test]
fn obj_lamp_stand_in_is_kept_while_the_lamp_emits() {
    let Some(obj) = cornell() else { return };
    let dir = tempfile::tempdir().unwrap();
    let scn = format!(
        "camera {{ perspective position <0, 1, 4> to <0, 1, 0> up <0, 1, 0> angle 40 }}\n\
         mesh {{ file \"{}\" }}\n\
         mesh {{ file \"{}\" material {{ color rgb(1, 1, 1) }} transform {{ translate <10, 0, 0> }} }}\n",
        obj.display(),
        obj.display()
    );
    let s = load_file(&write(dir.path(), "two.scn", scn.as_bytes())).unwrap();
    let stand_in: Vec<bool> = s.lights.iter().map(|l| l.emitter_stand_in).collect();
    assert_eq!(stand_in, [true, false]);
    let f = s.frame(0.0);
    let lamp_x: Vec<f32> = (0..f.mesh.triangle_count())
        .filter(|&t| f.materials[f.materials_of[t] as usize].emission.max_element() > 0.0)
        .map(|t| f.mesh.triangle(t).p0.x)
        .collect();
    assert_eq!(lamp_x.len(), 2, "one lamp (two triangles) emits: {lamp_x:?}");
    assert!(lamp_x.iter().all(|&x| x < 5.0), "the first box's, not the repainted one's: {lamp_x:?}");
}

#[test]
fn a_bare_mesh_placed_in_a_scene_file_brings_no_default_light() {
    let dir = tempfile::tempdir().unwrap();
    let p = gltf_triangle(dir.path(), "t.gltf", 3, "", "");
    let scn = write(dir.path(), "s.scn", b"mesh { file \"t.gltf\" }\n");
    let r = load_file_report(&scn).unwrap();
    assert!(r.scene.lights.is_empty());
    // …so the scene has no light, and says so.
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    let w = r.warnings[0].to_string();
    assert!(w.contains("s.scn") && w.contains("no lights") && w.contains("ambient"), "{w}");
    // The mesh file on its own gets the default light.
    assert_eq!(load_file(&p).unwrap().lights.len(), 1);
}

#[test]
fn scene_with_a_light_does_not_warn() {
    let dir = tempfile::tempdir().unwrap();
    let scn = write(
        dir.path(),
        "lit.scn",
        b"light { position <0, 5, 0> color rgb(1, 1, 1) }\nsphere { center <0, 0, 0> radius 1 }\n",
    );
    assert!(load_file_report(&scn).unwrap().warnings.is_empty());
    // A file of definitions only (for `include`) has nothing to light: no warning either.
    let defs = write(dir.path(), "defs.scn", b"define red material { color rgb(1, 0, 0) }\n");
    assert!(load_file_report(&defs).unwrap().warnings.is_empty());
}

/// The one-triangle glTF with three light nodes: a point light moved by its node, a spot
/// turned to look down, and a directional light turned likewise.
fn gltf_with_lights(dir: &std::path::Path) -> std::path::PathBuf {
    let lights = r#","extensionsUsed":["KHR_lights_punctual"],
        "extensions":{"KHR_lights_punctual":{"lights":[
            {"type":"point","color":[1,0.5,0.25],"intensity":10},
            {"type":"spot","intensity":2,"spot":{"innerConeAngle":0.2,"outerConeAngle":0.5}},
            {"type":"directional","color":[0,1,0],"intensity":3.14159265}]}}"#;
    let p = gltf_triangle(dir, "lights.gltf", 3, "", lights);
    // -90° about x (quaternion [-sin 45°, 0, 0, cos 45°]) turns the node's -z to -y.
    let turned = "[-0.70710678,0,0,0.70710678]";
    let json = std::fs::read_to_string(&p).unwrap().replace(
        r#""scenes":[{"nodes":[0]}],
        "nodes":[{"mesh":0,"translation":[0,0,5]}]"#,
        &format!(
            r#""scenes":[{{"nodes":[0,1,2]}}],
        "nodes":[{{"mesh":0,"translation":[0,0,5]}},
                 {{"translation":[1,2,3],"children":[3]}},
                 {{"rotation":{turned},"extensions":{{"KHR_lights_punctual":{{"light":2}}}}}},
                 {{"translation":[0,1,0],"rotation":{turned},"extensions":{{"KHR_lights_punctual":{{"light":1}}}}}}]"#
        ),
    );
    // Node 1 has no light of its own; its child (node 3) is the spot. The point light
    // goes on node 0, the mesh node.
    let json = json.replace(
        r#"{"mesh":0,"translation":[0,0,5]}"#,
        r#"{"mesh":0,"translation":[0,0,5],"extensions":{"KHR_lights_punctual":{"light":0}}}"#,
    );
    assert!(json.contains(r#""light":0"#), "the test's JSON splice must apply");
    write(dir, "lights.gltf", json.as_bytes())
}

#[test]
fn gltf_punctual_lights_are_placed_by_their_nodes() {
    let dir = tempfile::tempdir().unwrap();
    let r = load_file_report(&gltf_with_lights(dir.path())).unwrap();
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let lights = &r.scene.lights;
    assert_eq!(lights.len(), 3, "the file's lights, no default one: {lights:?}");
    // Walk order: node 0 (point), node 1 → child 3 (spot), node 2 (directional).
    let LightKind::Point { position, falloff } = lights[0].kind else { panic!("{:?}", lights[0]) };
    assert_eq!((position, falloff), (Vec3::new(0.0, 0.0, 5.0), 2));
    assert!((lights[0].color - Vec3::new(1.0, 0.5, 0.25) * 10.0 / PI).length() < 1e-5);
    let LightKind::Spot { position, direction, cos_inner, cos_outer, falloff } = lights[1].kind else {
        panic!("{:?}", lights[1])
    };
    assert!((position - Vec3::new(1.0, 3.0, 3.0)).length() < 1e-5, "{position}");
    assert!((direction - Vec3::NEG_Y).length() < 1e-5, "{direction}");
    assert_eq!((cos_inner, cos_outer, falloff), (0.2f32.cos(), 0.5f32.cos(), 2));
    assert!((lights[1].color - Vec3::splat(2.0 / PI)).length() < 1e-6, "white by default");
    let LightKind::Directional { direction } = lights[2].kind else { panic!("{:?}", lights[2]) };
    assert!((direction - Vec3::NEG_Y).length() < 1e-5, "{direction}");
    assert!((lights[2].color - Vec3::Y).length() < 1e-5, "3.14159 lux / π");
}

#[test]
fn gltf_light_index_out_of_range_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let p = gltf_with_lights(dir.path());
    let json = std::fs::read_to_string(&p).unwrap().replace(r#"{"light":2}"#, r#"{"light":9}"#);
    let msg = error_of(&write(dir.path(), "bad.gltf", json.as_bytes()));
    assert!(msg.contains("bad.gltf"), "{msg}");
}

#[test]
fn spot_cone_is_full_inside_dark_outside_and_smooth_between() {
    let spot = LightKind::Spot {
        position: Vec3::ZERO,
        direction: Vec3::NEG_Y,
        cos_inner: 0.2f32.cos(),
        cos_outer: 0.4f32.cos(),
        falloff: 2,
    };
    let at = |angle: f32| spot.cone_factor(Vec3::new(angle.sin(), -angle.cos(), 0.0));
    assert_eq!(at(0.0), 1.0);
    assert_eq!(at(0.19), 1.0);
    assert_eq!(at(0.41), 0.0);
    let mid = at(0.3);
    assert!(mid > 0.0 && mid < 1.0 && at(0.25) > mid && mid > at(0.35), "{mid}");
    assert_eq!(LightKind::Point { position: Vec3::ZERO, falloff: 0 }.cone_factor(Vec3::X), 1.0);
}

#[test]
fn cornell_box_is_seen_head_on_through_its_open_side() {
    let Some(obj) = cornell() else { return };
    let s = load_file(&obj).unwrap();
    let cam = s.camera.expect("a loaded mesh gets a camera");
    let c = s.bounds().center();
    assert_eq!(cam.look_at, c);
    let view = (cam.look_at - cam.position).normalize();
    assert!((view - Vec3::NEG_Z).length() < 1e-6, "looks along -z into the box: {view}");
    assert!(cam.position.z > s.bounds().max.z, "from outside the open front");
}

#[test]
fn a_solid_model_is_seen_from_the_front_three_quarter_view() {
    let Some(bunny) = model("bunny/bun_zipper.ply") else { return };
    let s = load_file(&bunny).unwrap();
    assert_eq!(s.camera, Some(Camera::framing(&s.bounds())), "the centre ray is blocked from every side");
}

#[test]
fn a_scene_file_camera_is_kept() {
    let s = parse_scn_str(
        "x.scn",
        "camera { perspective position <0, 1, 4> to <0, 1, 0> up <0, 1, 0> angle 40 }\nsphere { center <0, 0, 0> radius 1 }\n",
        std::path::Path::new("."),
    );
    let cam = s.unwrap().camera.unwrap();
    assert_eq!(cam.position, Vec3::new(0.0, 1.0, 4.0));
}

#[test]
fn gltf_emissive_materials_emit_their_factor_times_strength() {
    let dir = tempfile::tempdir().unwrap();
    let materials = r#","extensionsUsed":["KHR_materials_emissive_strength"],
        "materials":[{"emissiveFactor":[1,0.5,0.25],"extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":4}}},
                     {"emissiveFactor":[0.2,0.3,0.4]},
                     {"name":"dull"}]"#;
    for (index, want) in [(0, Color::new(4.0, 2.0, 1.0)), (1, Color::new(0.2, 0.3, 0.4)), (2, Color::ZERO)] {
        let name = format!("emissive{index}.gltf");
        let p = gltf_triangle(dir.path(), &name, 3, &format!(r#","material":{index}"#), materials);
        let s = load_file(&p).unwrap();
        let m = &s.materials[s.actors[0].materials[0] as usize];
        assert_eq!(m.emission, want, "material {index}");
    }
}
