//! glTF animation read by the loader, checked against poses computed here, independently:
//! the JSON parsed with serde_json, buffers read by hand, node TRS sampled with this
//! file's own lerp/slerp, joint matrices and skinning (or morph sums) done in f64. Then
//! stability across frames, clip selection, a static model that stays bit-identical, and
//! one broken file per error path.

#[path = "support/gltf_ref.rs"]
mod gltf_ref;
mod support;

use dynray_scene::{load_file, load_file_report, Motion, Scene};
use glam::{DMat4, DVec3};
use gltf_ref::{sample_linear, Doc};
use serde_json::{json, Value};
use std::path::Path;
use support::{error_of, model, write};

fn assert_close(what: &str, got: &[[f32; 3]], want: &[DVec3]) {
    assert_eq!(got.len(), want.len(), "{what}: vertex count");
    for (v, (g, w)) in got.iter().zip(want).enumerate() {
        let g = DVec3::new(g[0] as f64, g[1] as f64, g[2] as f64);
        let err = (g - *w).length();
        assert!(err <= 1e-4 * w.length().max(0.1), "{what}: vertex {v} at {g}, expected {w} (error {err:e})");
    }
}

// ---------------------------------------------------------------------------------------
// CesiumMan: one clip, one skin.

/// CesiumMan's vertices skinned at `t`, computed from the file alone.
fn cesium_man_expected(doc: &Doc, t: f64) -> Vec<DVec3> {
    let worlds = doc.worlds(t);
    let skin = &doc.json["skins"][0];
    let joints: Vec<usize> = skin["joints"].as_array().unwrap().iter().map(Doc::usize).collect();
    let ibm = doc.read(Doc::usize(&skin["inverseBindMatrices"]));
    let joint_mats: Vec<DMat4> = joints
        .iter()
        .enumerate()
        .map(|(j, &n)| worlds[n] * DMat4::from_cols_slice(&ibm[16 * j..16 * j + 16]))
        .collect();
    let attrs = &doc.json["meshes"][0]["primitives"][0]["attributes"];
    let pos = doc.read(Doc::usize(&attrs["POSITION"]));
    let js = doc.read(Doc::usize(&attrs["JOINTS_0"]));
    let ws = doc.read(Doc::usize(&attrs["WEIGHTS_0"]));
    (0..pos.len() / 3)
        .map(|v| {
            let p = DVec3::from_slice(&pos[3 * v..3 * v + 3]);
            (0..4).map(|k| ws[4 * v + k] * joint_mats[js[4 * v + k] as usize].transform_point3(p)).sum()
        })
        .collect()
}

#[test]
fn cesium_man_is_skinned_as_the_file_says_at_any_time() {
    let Some(gltf) = model("CesiumMan/glTF/CesiumMan.gltf") else { return };
    let doc = Doc::open(&gltf);
    let glb = model("CesiumMan/glTF-Binary/CesiumMan.glb");
    for p in std::iter::once(gltf.clone()).chain(glb) {
        let what = p.display().to_string();
        let s = load_file(&p).unwrap();
        assert_eq!(s.animation.rig.clips.len(), 1, "{what}");
        assert_eq!(s.animation.rig.skins.len(), 1, "{what}");
        assert_eq!(s.animation.rig.nodes.len(), 22, "{what}: every node of the scene");
        assert!(s.is_animated(), "{what}");
        assert_eq!(s.actors[0].motion, Motion::Dynamic);
        assert!(s.actors[0].deform.as_ref().is_some_and(|d| d.skin.is_some()));
        // The clip's keys run from 0 to 2 s: 49 frames at 24 fps.
        assert_eq!((s.animation.timeline.start, s.animation.timeline.frames), (0.0, 49), "{what}");
        for t in [1.0f32, 0.37, 1.9] {
            let f = s.frame(t);
            assert_close(&format!("{what} at t = {t}"), &f.mesh.positions, &cesium_man_expected(&doc, t as f64));
        }
        // Frame 0 is posed, not the bind pose; bounds stay those of a 1.5-unit man.
        let bind = s.actors[0].world_mesh().positions;
        let f0 = s.frame(0.0);
        let moved = f0.mesh.positions.iter().zip(&bind).map(|(a, b)| dist(*a, *b)).fold(0.0f32, f32::max);
        assert!(moved > 1e-3, "{what}: frame 0 equals the bind pose (max move {moved})");
        let first = s.frame(0.0);
        for k in 0..s.animation.timeline.frames {
            let f = s.frame(s.animation.timeline.time_of(k));
            let e = f.mesh.bounds().extent();
            assert!(e.is_finite() && e.max_element() > 1.0 && e.max_element() < 2.5, "{what}: frame {k} extent {e}");
            assert_eq!(f.mesh.indices, first.mesh.indices, "{what}: frame {k} triangles");
            assert_eq!(f.materials_of, first.materials_of, "{what}: frame {k} materials");
            assert_eq!(f.actor_ranges, first.actor_ranges);
        }
    }
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    glam::Vec3::from_array(a).distance(glam::Vec3::from_array(b))
}

#[test]
fn select_clip_names_the_clips_there_are() {
    let Some(p) = model("CesiumMan/glTF/CesiumMan.gltf") else { return };
    let mut s = load_file(&p).unwrap();
    let e = s.select_clip("Dance").unwrap_err();
    assert!(e.contains("no clip named `Dance`") && e.contains("#0 (unnamed)"), "{e}");
    let Some(p) = model("AnimatedMorphCube/glTF/AnimatedMorphCube.gltf") else { return };
    let mut s = load_file(&p).unwrap();
    let e = s.select_clip("Round").unwrap_err();
    assert!(e.contains("(clips: Square)"), "{e}");
    s.select_clip("Square").unwrap();
}

// ---------------------------------------------------------------------------------------
// AnimatedMorphCube: weights over time.

#[test]
fn animated_morph_cube_adds_weighted_targets() {
    let Some(p) = model("AnimatedMorphCube/glTF/AnimatedMorphCube.gltf") else { return };
    let doc = Doc::open(&p);
    let s = load_file(&p).unwrap();
    assert!(s.is_animated());
    assert_eq!(s.animation.rig.clips[0].name.as_deref(), Some("Square"));
    let prim = &doc.json["meshes"][0]["primitives"][0];
    let base = doc.read(Doc::usize(&prim["attributes"]["POSITION"]));
    let deltas: Vec<Vec<f64>> =
        prim["targets"].as_array().unwrap().iter().map(|t| doc.read(Doc::usize(&t["POSITION"]))).collect();
    let anim = &doc.json["animations"][0]["samplers"][0];
    let times = doc.read(Doc::usize(&anim["input"]));
    let weights = doc.read(Doc::usize(&anim["output"]));
    let node = doc.worlds(0.0)[0];
    let mut seen = Vec::new();
    for t in [0.0f64, 0.5, 1.3, 2.05, 3.9] {
        let w = sample_linear(&times, &weights, deltas.len(), t, false);
        seen.push(w.clone());
        let want: Vec<DVec3> = (0..base.len() / 3)
            .map(|v| {
                let mut p = DVec3::from_slice(&base[3 * v..3 * v + 3]);
                for (d, wt) in deltas.iter().zip(&w) {
                    p += DVec3::from_slice(&d[3 * v..3 * v + 3]) * *wt;
                }
                node.transform_point3(p)
            })
            .collect();
        let f = s.frame(t as f32);
        assert_close(&format!("morph cube at t = {t}"), &f.mesh.positions, &want);
        assert!(f.mesh.normals.as_ref().unwrap().iter().all(|n| n.iter().all(|x| x.is_finite())));
        assert_eq!(f.mesh.indices, s.frame(0.0).mesh.indices);
    }
    assert!(seen.windows(2).any(|w| w[0] != w[1]), "the weights should change over time: {seen:?}");
    assert_ne!(s.frame(1.3).mesh.positions, s.frame(0.0).mesh.positions);
}

// ---------------------------------------------------------------------------------------
// A static model stays static.

#[test]
fn duck_is_not_animated_and_every_frame_is_frame_zero() {
    let Some(p) = model("Duck/glTF-Binary/Duck.glb") else { return };
    let s: Scene = load_file(&p).unwrap();
    assert!(!s.is_animated());
    assert!(s.actors.iter().all(|a| a.motion == Motion::Static && a.node.is_some() && a.deform.is_none()));
    assert_eq!(s.animation.timeline.frames, 1);
    let f0 = s.frame(0.0);
    for t in [0.5f32, 3.7, -2.0] {
        let f = s.frame(t);
        let bits = |v: &[[f32; 3]]| v.iter().map(|p| p.map(f32::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&f.mesh.positions), bits(&f0.mesh.positions), "t = {t}");
        assert_eq!(f.mesh.normals.as_deref().map(bits), f0.mesh.normals.as_deref().map(bits));
        assert_eq!(f.mesh.indices, f0.mesh.indices);
    }
}

// ---------------------------------------------------------------------------------------
// Small hand-made files: a triangle on node 0, one animation, optionally a skin.

fn base64(bytes: &[u8]) -> String {
    const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            out.push(if k <= c.len() { A[(n >> (18 - 6 * k) & 63) as usize] as char } else { '=' });
        }
    }
    out
}

/// Buffer: positions (3 × vec3, bytes 0..36), key times (36..44), translations
/// (2 × vec3, 44..68), JOINTS_0 (3 × u8 vec4, 68..80), WEIGHTS_0 (3 × f32 vec4, 80..128),
/// rotations (2 × i16 vec4 normalised, 128..144).
fn buffer(times: [f32; 2], joint: u8) -> Vec<u8> {
    let mut b = Vec::new();
    let f = |b: &mut Vec<u8>, v: &[f32]| v.iter().for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    f(&mut b, &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    f(&mut b, &times);
    f(&mut b, &[0.0, 0.0, 0.0, 0.0, 0.0, 2.0]);
    b.extend_from_slice(&[0, 0, 0, 0, joint, 0, 0, 0, 0, 0, 0, 0]);
    f(&mut b, &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    // Identity, then 90° about z (sin 45° · 32767 = 23170).
    for q in [[0i16, 0, 0, 32767], [0, 0, 23170, 23170]] {
        q.iter().for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
    }
    b
}

fn file(times: [f32; 2], joint: u8) -> Value {
    let b = buffer(times, joint);
    let view = |o: usize, l: usize| json!({"buffer": 0, "byteOffset": o, "byteLength": l});
    json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [0.0, 0.0, 0.0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "animations": [{
            "name": "slide",
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
            "samplers": [{"input": 1, "output": 2, "interpolation": "LINEAR"}]
        }],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [1.0]},
            {"bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3"},
            {"bufferView": 3, "componentType": 5121, "count": 3, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5126, "count": 3, "type": "VEC4"},
            {"bufferView": 5, "componentType": 5122, "normalized": true, "count": 2, "type": "VEC4"}
        ],
        "bufferViews": [view(0, 36), view(36, 8), view(44, 24), view(68, 12), view(80, 48), view(128, 16)],
        "buffers": [{"byteLength": b.len(), "uri": format!("data:application/octet-stream;base64,{}", base64(&b))}]
    })
}

/// The file with a skin of one joint (node 1, a child of node 0's sibling) on node 0.
fn skinned(joint: u8) -> Value {
    let mut j = file([0.0, 1.0], joint);
    j["scenes"][0]["nodes"] = json!([0, 1]);
    j["nodes"][0]["skin"] = json!(0);
    j["nodes"].as_array_mut().unwrap().push(json!({"translation": [0.0, 0.0, 0.0]}));
    j["meshes"][0]["primitives"][0]["attributes"] = json!({"POSITION": 0, "JOINTS_0": 3, "WEIGHTS_0": 4});
    j["skins"] = json!([{"name": "rig", "joints": [1]}]);
    j["animations"][0]["channels"][0]["target"]["node"] = json!(1);
    j
}

fn save(dir: &Path, name: &str, j: &Value) -> std::path::PathBuf {
    write(dir, name, serde_json::to_string(j).unwrap().as_bytes())
}

#[test]
fn a_hand_made_file_animates_translation_rotation_and_skin() {
    let dir = tempfile::tempdir().unwrap();
    let s = load_file(&save(dir.path(), "ok.gltf", &file([0.0, 1.0], 0))).unwrap();
    assert!(s.is_animated());
    assert_eq!(s.frame(0.5).mesh.positions[0], [0.0, 0.0, 1.0]);
    assert_eq!(s.animation.timeline.frames, 25);
    // Rotation from normalised shorts: (1,0,0) turns to (0,1,0) at t = 1.
    let mut rot = file([0.0, 1.0], 0);
    rot["animations"][0]["channels"][0]["target"]["path"] = json!("rotation");
    rot["animations"][0]["samplers"][0]["output"] = json!(5);
    let s = load_file(&save(dir.path(), "rot.gltf", &rot)).unwrap();
    let p = s.frame(1.0).mesh.positions[1];
    assert!(dist(p, [0.0, 1.0, 0.0]) < 1e-4, "{p:?}");
    // Skinned: the joint (node 1) moves, so the skinned triangle does.
    let s = load_file(&save(dir.path(), "skin.gltf", &skinned(0))).unwrap();
    assert_eq!(s.frame(1.0).mesh.positions[2], [0.0, 1.0, 2.0]);
    assert_eq!(s.frame(0.0).mesh.positions[2], [0.0, 1.0, 0.0]);
}

#[test]
fn a_channel_on_a_node_outside_the_scene_is_ignored_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let mut j = file([0.0, 1.0], 0);
    j["nodes"].as_array_mut().unwrap().push(json!({"translation": [0.0, 0.0, 0.0]}));
    j["animations"][0]["channels"][0]["target"]["node"] = json!(1);
    let r = load_file_report(&save(dir.path(), "outside.gltf", &j)).unwrap();
    assert!(!r.scene.is_animated());
    let w: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
    assert!(w.iter().any(|w| w.contains("animation 0 (\"slide\") channel 0: node 1 is not in the scene")), "{w:?}");
}

/// Each broken variant fails with a message naming the file (checked by `error_of`)
/// and the place.
#[test]
fn broken_animation_files_are_errors_that_name_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let cases: Vec<(&str, Value, &[&str])> = vec![
        (
            "sampler.gltf",
            {
                let mut j = file([0.0, 1.0], 0);
                j["animations"][0]["channels"][0]["sampler"] = json!(4);
                j
            },
            &["animation 0 (\"slide\") channel 0: sampler 4 does not exist"],
        ),
        (
            "node.gltf",
            {
                let mut j = file([0.0, 1.0], 0);
                j["animations"][0]["channels"][0]["target"]["node"] = json!(9);
                j
            },
            &["channel 0: target node 9 does not exist"],
        ),
        (
            "input_type.gltf",
            {
                let mut j = file([0.0, 1.0], 0);
                j["animations"][0]["samplers"][0]["input"] = json!(2);
                j
            },
            &["channel 0: key times (input): accessor 2 is Vec3"],
        ),
        ("times.gltf", file([1.0, 0.5], 0), &["animation 0 (\"slide\") channel 0: key 1 at time 0.5 is not after"]),
        (
            "count.gltf",
            {
                let mut j = file([0.0, 1.0], 0);
                j["accessors"][2]["count"] = json!(1);
                j
            },
            &["channel 0: values (output) accessor 2 has 1 elements for 2 key times (expected 2)"],
        ),
        (
            "cubic.gltf",
            {
                let mut j = file([0.0, 1.0], 0);
                j["animations"][0]["samplers"][0]["interpolation"] = json!("CUBICSPLINE");
                j
            },
            &["has 2 elements for 2 key times (expected 6, three per key for CUBICSPLINE)"],
        ),
        (
            "lying.gltf",
            {
                let mut j = file([0.0, 1.0], 0);
                j["accessors"][1]["count"] = json!(1000);
                j
            },
            &["channel 0: key times (input): accessor 1 (1000 elements) runs past its buffer view"],
        ),
        (
            "joint_node.gltf",
            {
                let mut j = skinned(0);
                j["skins"][0]["joints"] = json!([0, 7]);
                j
            },
            &["skin 0 (\"rig\"): joint 1 names node 7, which does not exist"],
        ),
        (
            "joints.gltf",
            skinned(3),
            &["mesh 0 primitive 0: JOINTS_0 of vertex 1 names joint 3, but skin 0 has 1 joints"],
        ),
        (
            "ibm.gltf",
            {
                let mut j = skinned(0);
                j["skins"][0]["inverseBindMatrices"] = json!(4);
                j["accessors"][4]["type"] = json!("MAT4");
                j
            },
            &["skin 0 (\"rig\"): inverseBindMatrices: accessor 4"],
        ),
        (
            "matrix.gltf",
            {
                let mut j = file([0.0, 1.0], 0);
                j["nodes"][0] = json!({"mesh": 0, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]});
                j
            },
            &["channel 0: node 0 has a matrix"],
        ),
    ];
    for (name, j, wanted) in cases {
        let msg = error_of(&save(dir.path(), name, &j));
        for w in wanted {
            assert!(msg.contains(w), "{name}: {msg}\n  should contain: {w}");
        }
    }
}

#[test]
fn sparse_morph_targets_leave_the_base_shape_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let mut j = file([0.0, 1.0], 0);
    j["accessors"].as_array_mut().unwrap().push(json!({
        "componentType": 5126, "count": 3, "type": "VEC3",
        "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5125}, "values": {"bufferView": 0}}
    }));
    j["meshes"][0]["primitives"][0]["targets"] = json!([{"POSITION": 6}]);
    let r = load_file_report(&save(dir.path(), "sparse.gltf", &j)).unwrap();
    assert!(r.scene.actors[0].deform.is_none());
    let w: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
    assert!(w.iter().any(|w| w.contains("mesh 0 primitive 0: a morph target accessor is sparse")), "{w:?}");
    // The translation channel still plays.
    assert_eq!(r.scene.frame(1.0).mesh.positions[0], [0.0, 0.0, 2.0]);
}
