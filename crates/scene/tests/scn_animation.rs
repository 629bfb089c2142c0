//! The scene language's animation (docs/scene-language.md §5.3, §9): `settings { frames
//! frame_rate }`, `animate { … }` on objects, lights and the camera, `motion`, and every
//! error path, checked through the language against values computed by hand here.

use dynray_scene::animation::ChannelTarget;
use dynray_scene::{parse_scn_str, Animation, LightKind, LoadError, Motion, Scene, Timeline, Transform};
use glam::Vec3;
use std::path::Path;

fn parse(text: &str) -> Scene {
    parse_scn_str("test.scn", text, Path::new(".")).unwrap_or_else(|e| panic!("unexpected error:\n{e}"))
}

/// The error of `text`: (line, column, message, rendered).
fn fail(text: &str) -> (usize, usize, String, String) {
    match parse_scn_str("test.scn", text, Path::new(".")) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(LoadError::Scene { line, column, message, rendered, .. }) => (line, column, message, rendered),
        Err(e) => panic!("expected a scene diagnostic, got {e:?}"),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

/// Vertex `i` of the frame at `t`.
fn vertex(s: &Scene, t: f32, i: usize) -> Vec3 {
    Vec3::from_array(s.frame(t).mesh.positions[i])
}

/// A one-second animation (25 frames at 24 a second) of one triangle, whose vertex 0
/// is its local origin and vertex 1 is `(1, 0, 0)`.
const SETTINGS: &str = "settings { frames 25 frame_rate 24 }";
const TRI: &str = "mesh { vertices { 3 <0,0,0> <1,0,0> <0,1,0> } triangles { 1 <0,1,2> }";

/// The triangle animated by `body` (the lines inside `animate { … }`; its first line is
/// line 4 of the file).
fn animated(body: &str) -> String {
    format!("{SETTINGS}\n{TRI}\nanimate {{\n{body}\n}} }}")
}

// ---- timeline ---------------------------------------------------------------------------

#[test]
fn settings_frames_and_frame_rate_make_the_timeline() {
    let s = parse(&format!("settings {{ frames 48 frame_rate 30 }}\n{TRI} }}"));
    assert_eq!(s.animation.timeline, Timeline { start: 0.0, frames: 48, frame_rate: 30.0 });
    assert_eq!(s.animation.timeline.time_of(15), 0.5);
    // Defaults: one frame, 24 a second.
    let s = parse(&format!("{TRI} }}"));
    assert_eq!(s.animation.timeline, Timeline { start: 0.0, frames: 1, frame_rate: 24.0 });
}

// ---- objects ----------------------------------------------------------------------------

#[test]
fn linear_translation_at_a_mid_time() {
    let s = parse(&animated("  key 0 { translate <0,0,0> }\n  key 1 { translate <2,4,-6> }"));
    let a = &s.actors[0];
    assert_eq!(a.motion, Motion::Dynamic);
    let node = a.node.expect("an animated actor has a node");
    let clip = &s.animation.rig.clips[0];
    assert_eq!(clip.name.as_deref(), Some("scene"));
    assert_eq!(clip.channels.len(), 1);
    assert_eq!((clip.channels[0].node, clip.channels[0].target), (node, ChannelTarget::Translation));
    // A quarter of the way: a quarter of the translation.
    assert!(close(vertex(&s, 0.25, 0), Vec3::new(0.5, 1.0, -1.5)), "{}", vertex(&s, 0.25, 0));
    assert!(close(vertex(&s, 0.25, 1), Vec3::new(1.5, 1.0, -1.5)));
    // Outside its keys a track holds: at the end and past it, the last key.
    assert!(close(vertex(&s, 1.0, 0), Vec3::new(2.0, 4.0, -6.0)));
    assert!(close(vertex(&s, 5.0, 0), Vec3::new(2.0, 4.0, -6.0)));
    // The actor's transform is its placement at time 0.
    assert_eq!(a.transform, Transform::new(glam::Mat4::IDENTITY));
}

#[test]
fn frame_keys_are_at_k_over_the_frame_rate() {
    // frame 12 of 24 a second is 0.5 s: halfway at 0.25 s.
    let s = parse(&animated("  frame 0 { translate <0,0,0> }\n  frame 12 { translate <4,0,0> }"));
    assert!(close(vertex(&s, 0.25, 0), Vec3::new(2.0, 0.0, 0.0)));
    assert!(close(vertex(&s, 0.75, 0), Vec3::new(4.0, 0.0, 0.0)));
}

#[test]
fn step_interpolation_holds_each_key() {
    let s = parse(&animated("  interpolation step\n  key 0 { translate <0,0,0> }\n  key 0.5 { translate <3,0,0> }"));
    assert!(close(vertex(&s, 0.49, 0), Vec3::ZERO));
    assert!(close(vertex(&s, 0.5, 0), Vec3::new(3.0, 0.0, 0.0)));
}

#[test]
fn rotations_slerp() {
    // rotate_y 0 -> rotate_y 90: at 0.5 s, 45° about +y, which takes +x to (cos 45°, 0, -sin 45°).
    let h = std::f32::consts::FRAC_1_SQRT_2;
    for body in [
        "  key 0 { rotate_y 0 }\n  key 1 { rotate_y 90 }",
        "  key 0 { rotate <0,1,0> 0 }\n  key 1 { rotate <0,2,0> 90 }",
    ] {
        let s = parse(&animated(body));
        assert!(close(vertex(&s, 0.5, 1), Vec3::new(h, 0.0, -h)), "{body}: {}", vertex(&s, 0.5, 1));
        // A third of the way: 30°.
        let (sin, cos) = 30f32.to_radians().sin_cos();
        assert!(close(vertex(&s, 1.0 / 3.0, 1), Vec3::new(cos, 0.0, -sin)));
    }
    // Rotations of one key compose in written order: +x -> +y (z 90) -> +y (y 90 keeps it).
    let s = parse(&animated("  key 0 { rotate_z 90 rotate_y 90 }"));
    assert!(close(vertex(&s, 0.0, 1), Vec3::new(0.0, 1.0, 0.0)), "{}", vertex(&s, 0.0, 1));
}

#[test]
fn smooth_through_three_keys_is_catmull_rom() {
    let s = parse(&animated(
        "  interpolation smooth\n  key 0 { translate <0,0,0> }\n  key 0.5 { translate <1,0,0> }\n  key 1 { translate <4,2,0> }",
    ));
    // Catmull–Rom by hand, per segment in units of the segment (keys evenly spaced): the
    // tangent at an inner key is half the chord between its neighbours, at an end key the
    // chord to its one neighbour (a zero-length outer chord, as the Track does; BART's
    // AFF tracks follow other rules, crates/scene/tests/bart_reference.rs).
    let hermite = |p0: f32, m0: f32, p1: f32, m1: f32, s: f32| {
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * p0 + (s3 - 2.0 * s2 + s) * m0 + (-2.0 * s3 + 3.0 * s2) * p1 + (s3 - s2) * m1
    };
    let (x, y) = ([0.0, 1.0, 4.0], [0.0, 0.0, 2.0]);
    let at = |p: [f32; 3], seg: usize, u: f32| {
        let m = [p[1] - p[0], (p[2] - p[0]) / 2.0, p[2] - p[1]];
        hermite(p[seg], m[seg], p[seg + 1], m[seg + 1], u)
    };
    // By hand: segment 0 at its middle: 0/2 + 1/8 + 1/2 - 2/8 = 0.375.
    assert_eq!(at(x, 0, 0.5), 0.375);
    for (t, seg, u) in [(0.25, 0, 0.5), (0.1, 0, 0.2), (0.75, 1, 0.5), (0.9, 1, 0.8)] {
        let want = Vec3::new(at(x, seg, u), at(y, seg, u), 0.0);
        assert!(close(vertex(&s, t, 0), want), "t {t}: {} vs {want}", vertex(&s, t, 0));
    }
    // Through the keys.
    assert!(close(vertex(&s, 0.5, 0), Vec3::new(1.0, 0.0, 0.0)));
}

#[test]
fn smooth_takes_kochanek_bartels_parameters_per_key() {
    // Tension 1 at the middle key flattens its tangent: the curve there is a Hermite
    // with a zero tangent at the middle key.
    let s = parse(&animated(
        "  interpolation smooth\n  key 0 { translate <0,0,0> }\n  key 0.5 { translate <1,0,0> tension 1 }\n  key 1 { translate <4,0,0> }",
    ));
    // Segment 0, u = 0.5: 0 + (1/8)·1 + (1/2)·1 + (-1/8)·0 = 0.625.
    assert!(close(vertex(&s, 0.25, 0), Vec3::new(0.625, 0.0, 0.0)), "{}", vertex(&s, 0.25, 0));
}

#[test]
fn smooth_rotations_stay_rotations() {
    let s = parse(&animated(
        "  interpolation smooth\n  key 0 { rotate_y 0 }\n  key 0.5 { rotate_y 60 }\n  key 1 { rotate_y 120 }",
    ));
    // Evenly spaced equal steps: the curve passes the middle key and keeps vertex 1 on
    // the unit circle in between (normalised quaternions).
    let p = vertex(&s, 0.5, 1);
    let (sin, cos) = 60f32.to_radians().sin_cos();
    assert!(close(p, Vec3::new(cos, 0.0, -sin)), "{p}");
    for t in [0.1, 0.3, 0.7, 0.9] {
        let p = vertex(&s, t, 1);
        assert!((p.length() - 1.0).abs() < 1e-5 && p.y.abs() < 1e-6, "t {t}: {p}");
    }
}

#[test]
fn scale_keys_take_a_vector_or_one_factor() {
    let s = parse(&animated("  key 0 { scale 1 }\n  key 1 { scale <3,1,1> }"));
    assert!(close(vertex(&s, 0.5, 1), Vec3::new(2.0, 0.0, 0.0)));
    assert!(close(vertex(&s, 0.5, 2), Vec3::new(0.0, 1.0, 0.0)));
}

#[test]
fn transforms_before_and_after_animate_compose_in_written_order() {
    let s = parse(&format!(
        "{SETTINGS}\n{TRI} transform {{ translate <1,0,0> }}\n\
         animate {{ key 0 {{ rotate_y 0 }} key 1 {{ rotate_y 90 }} }}\n\
         transform {{ translate <0,5,0> }} }}"
    ));
    // Vertex 0: (1, 0, 0) by the first transform, (0, 0, -1) by the quarter turn, then up 5.
    assert!(close(vertex(&s, 1.0, 0), Vec3::new(0.0, 5.0, -1.0)), "{}", vertex(&s, 1.0, 0));
    // At time 0: just the two translations, which is also the actor's transform.
    assert!(close(vertex(&s, 0.0, 0), Vec3::new(1.0, 5.0, 0.0)));
    let t0 = s.actors[0].transform;
    assert!(close(Vec3::from_array(t0.point([0.0; 3])), Vec3::new(1.0, 5.0, 0.0)));
    // Three nodes: the fixed `after`, the animated one, the fixed `before`.
    assert_eq!(s.animation.rig.nodes.len(), 3);
}

#[test]
fn a_defined_animated_object_moves_wherever_it_is_placed() {
    let s = parse(&format!(
        "{SETTINGS}\ndefine bob {TRI} animate {{ key 0 {{ translate <0,0,0> }} key 1 {{ translate <0,2,0> }} }} }}\n\
         object bob\nobject {{ bob transform {{ translate <10,0,0> }} }}"
    ));
    assert_eq!(s.actors.len(), 2);
    assert_ne!(s.actors[0].node, s.actors[1].node);
    let f = s.frame(0.5);
    assert!(close(Vec3::from_array(f.mesh.positions[0]), Vec3::new(0.0, 1.0, 0.0)));
    assert!(close(Vec3::from_array(f.mesh.positions[3]), Vec3::new(10.0, 1.0, 0.0)));
}

#[test]
fn channels_use_only_the_keys_that_set_them() {
    // Translation keyed at 0 and 1, rotation only at 0.5 (held throughout).
    let s = parse(&animated("  key 0 { translate <0,0,0> }\n  key 0.5 { rotate_z 90 }\n  key 1 { translate <2,0,0> }"));
    assert_eq!(s.animation.rig.clips[0].channels.len(), 2);
    // At 0.5: translated by 1, vertex 1 turned to +y.
    assert!(close(vertex(&s, 0.5, 1), Vec3::new(1.0, 1.0, 0.0)), "{}", vertex(&s, 0.5, 1));
}

// ---- lights and camera ------------------------------------------------------------------

#[test]
fn an_animated_light_moves_with_its_node() {
    let s = parse(&format!(
        "{SETTINGS}\n{TRI} }}\nlight {{ position <0,1,0> color rgb(1,1,1)\n\
           animate {{ key 0 {{ translate <0,0,0> }} key 1 {{ translate <4,0,0> }} }} }}\n\
         light {{ direction <0,-1,0> animate {{ key 0 {{ rotate_z 0 }} key 1 {{ rotate_z 90 }} }} }}"
    ));
    assert_eq!(s.animation.light_nodes.len(), 2);
    let f = s.frame(0.5);
    match f.lights[0].kind {
        LightKind::Point { position, .. } => assert!(close(position, Vec3::new(2.0, 1.0, 0.0)), "{position}"),
        k => panic!("{k:?}"),
    }
    // (0, -1, 0) turned 90° about +z at the end: (1, 0, 0).
    match s.frame(1.0).lights[1].kind {
        LightKind::Directional { direction } => assert!(close(direction, Vec3::X), "{direction}"),
        k => panic!("{k:?}"),
    }
    // The scene's own lights stay as written (the rest pose, in node space).
    assert!(matches!(s.lights[0].kind, LightKind::Point { position, .. } if position == Vec3::Y));
    // The mesh does not move, so it stays static.
    assert_eq!(s.actors[0].motion, Motion::Static);
    assert!(s.is_animated());
}

#[test]
fn an_animated_camera_orbits() {
    let s = parse(&format!(
        "{SETTINGS}\n{TRI} }}\ncamera {{ perspective position <0,0,5> to <0,0,0> up <0,1,0>\n\
           animate {{ key 0 {{ rotate_y 0 }} key 1 {{ rotate_y 90 }} }} }}"
    ));
    assert!(s.animation.camera_node.is_some());
    let c = s.frame(1.0).camera;
    assert!(close(c.position, Vec3::new(5.0, 0.0, 0.0)), "{}", c.position);
    assert!(close(c.look_at, Vec3::ZERO) && close(c.up, Vec3::Y));
    let h = 5.0 * std::f32::consts::FRAC_1_SQRT_2;
    assert!(close(s.frame(0.5).camera.position, Vec3::new(h, 0.0, h)));
    // A defined animated camera keeps its animation.
    let s = parse(&format!(
        "{SETTINGS}\n{TRI} }}\ndefine cam camera {{ perspective position <0,0,5> to <0,0,0> up <0,1,0>\n\
           animate {{ key 0 {{ translate <0,0,0> }} key 1 {{ translate <0,3,0> }} }} }}\ncamera cam"
    ));
    assert!(close(s.frame(1.0).camera.position, Vec3::new(0.0, 3.0, 5.0)));
}

// ---- motion -----------------------------------------------------------------------------

#[test]
fn motion_is_dynamic_exactly_when_animated_unless_written() {
    let s = parse(&format!(
        "{SETTINGS}\n{TRI} }}\n{TRI} motion dynamic }}\n{TRI} motion static }}\n\
         {TRI} animate {{ key 0 {{ translate <0,0,0> }} key 1 {{ translate <1,0,0> }} }} motion dynamic }}\n\
         define d sphere {{ center <0,0,0> radius 1 }}\nobject {{ d motion dynamic }}"
    ));
    let m: Vec<Motion> = s.actors.iter().map(|a| a.motion).collect();
    use Motion::{Dynamic, Static};
    assert_eq!(m, [Static, Dynamic, Static, Dynamic, Dynamic]);
    // Marking does not place: the non-animated ones keep the identity and no node.
    for a in [0, 1, 2, 4] {
        assert_eq!(s.actors[a].transform, Transform::IDENTITY, "actor {a}");
        assert_eq!(s.actors[a].node.is_some(), a == 3);
    }
    assert_eq!(s.actors[3].node, Some(0));
}

#[test]
fn motion_static_on_an_animated_object_is_an_error() {
    let (line, col, msg, rendered) =
        fail(&format!("{SETTINGS}\n{TRI}\nanimate {{ key 0 {{ translate <0,0,0> }} }}\nmotion static }}"));
    assert_eq!((line, col), (4, 8), "{rendered}");
    assert!(msg.contains("`motion static` on an animated object"), "{msg}");
    assert!(rendered.contains("animated here"), "{rendered}");
    let (line, col, msg, rendered) = fail(&format!("{TRI} motion fast }}"));
    assert_eq!((line, col), (1, 78), "{rendered}");
    assert!(msg.contains("unknown motion `fast`"), "{msg}");
}

// ---- still scenes -----------------------------------------------------------------------

#[test]
fn a_scene_without_animation_is_the_same_at_every_time() {
    let s = parse(
        "settings { frames 10 }\nsphere { center <0,1,0> radius 1 transform { rotate_y 30 translate <1,0,0> } }\n\
         box { center <0,0,0> orientation <0,0,0> scale <4,0.1,4> }\nlight { position <0,5,5> }\n\
         camera { perspective position <0,2,8> to <0,0,0> up <0,1,0> }",
    );
    assert_eq!(s.animation.rig, Default::default());
    assert!(s.animation.light_nodes.is_empty() && s.animation.camera_node.is_none());
    assert_eq!(
        s.animation,
        Animation { timeline: Timeline { frames: 10, ..Timeline::default() }, ..Default::default() }
    );
    assert!(!s.is_animated());
    assert!(s.actors.iter().all(|a| a.motion == Motion::Static && a.node.is_none()));
    assert_eq!(s.actors[1].transform, Transform::IDENTITY);
    let f0 = s.frame(0.0);
    for t in [0.2, 0.375, 7.5, -3.0] {
        let mut f = s.frame(t);
        assert_eq!(f.time, t);
        f.time = 0.0;
        assert!(f == f0, "the frame at {t} differs from frame 0");
    }
}

// ---- errors -----------------------------------------------------------------------------

/// `(body, line, column, message part)` of each bad `animate` body.
const BAD_KEYS: &[(&str, usize, usize, &str)] = &[
    (
        "  key 0.5 { translate <1,0,0> }\n  key 0.25 { translate <0,0,0> }",
        5,
        3,
        "key at 0.25 s comes after a key at 0.5 s",
    ),
    ("  key 0.5 { translate <1,0,0> }\n  frame 12 { translate <0,0,0> }", 5, 3, "duplicate key at 0.5 s"),
    ("  key 0 { translate <1,0,0> }\n  key 0 { translate <0,0,0> }", 5, 3, "duplicate key at 0 s"),
    ("  key 0 { translate <1,0,0> }\n  key 2 { translate <0,0,0> }", 5, 3, "key at 2 s is outside the animation"),
    ("  frame 30 { translate <0,0,0> }", 4, 3, "is outside the animation"),
    ("  key -0.5 { translate <0,0,0> }", 4, 3, "key at -0.5 s is outside the animation"),
    ("  interpolation cubic\n  key 0 { translate <0,0,0> }", 4, 17, "unknown interpolation `cubic`"),
    ("  key 0 { rotate <0,0,0> 90 }", 4, 18, "rotation axis is the zero vector"),
    ("  key 0 { rotate <1,0,0> <0,1,0> 90 }", 4, 18, "a key's `rotate` takes an axis and an angle, not a base point"),
    ("  key 0 { rotate <0,1,0> <1,1,1> }", 4, 18, "not a base point"),
    ("  key 0 { rotate <0,1,0> rgb(1,0,0) }", 4, 26, "rotation angle (degrees) must be a finite real, found a colour"),
    ("  key 0 { rotate_y <0,1,0> }", 4, 20, "type mismatch: rotate_y angle (degrees) must be a real"),
    ("  key 0 { scale <1,0,1> }", 4, 17, "scale factors"),
    ("  key 0 { translate 3 }", 4, 21, "key translation must be a vector"),
    ("  key 0 { spin 3 }", 4, 11, "unknown parameter `spin` in `key`"),
    ("  key 0 { }", 4, 9, "this key sets nothing"),
    ("  key 0 { translate <0,0,0> translate <1,0,0> }", 4, 29, "duplicated parameter `translate` in `key`"),
    ("  key 0 { translate <0,0,0> tension 0.5 }", 4, 29, "`tension` applies only to `interpolation smooth`"),
    (
        "  interpolation smooth\n  key 0 { translate <0,0,0> bias 2 }",
        5,
        34,
        "key bias is 2, but it must lie in [-1, 1]",
    ),
    ("  interpolation smooth\n  interpolation step", 5, 3, "duplicated parameter `interpolation` in `animate`"),
];

#[test]
fn each_bad_key_is_reported_at_its_place() {
    for &(body, line, col, want) in BAD_KEYS {
        let (l, c, msg, rendered) = fail(&animated(body));
        assert!(msg.contains(want), "{body}: message {msg:?} lacks {want:?}\n{rendered}");
        assert_eq!((l, c), (line, col), "{body}:\n{rendered}");
        assert!(rendered.contains(&format!("test.scn:{line}:{col}")), "{rendered}");
    }
}

#[test]
fn a_key_past_the_default_single_frame_says_how_to_lengthen_the_animation() {
    let (line, col, msg, rendered) =
        fail(&format!("{TRI}\n  animate {{ key 0 {{ translate <0,0,0> }} key 1 {{ scale 2 }} }} }}"));
    assert_eq!((line, col), (2, 41), "{rendered}");
    assert!(msg.contains("key at 1 s is outside the animation"), "{msg}");
    assert!(
        rendered.contains("1 frame(s) at 24 frames a second") && rendered.contains("settings { frames N"),
        "{rendered}"
    );
}

#[test]
fn an_animate_without_keys_is_an_error() {
    let (line, col, msg, _) = fail(&format!("{TRI} animate {{ interpolation step }} }}"));
    assert_eq!((line, col), (1, 79));
    assert!(msg.contains("`animate` has no keys"), "{msg}");
}

#[test]
fn a_second_animate_is_an_error() {
    // In one block …
    let (line, col, msg, _) =
        fail(&format!("{TRI} animate {{ key 0 {{ scale 1 }} }} animate {{ key 0 {{ scale 2 }} }} }}"));
    assert_eq!((line, col), (1, 101));
    assert!(msg.contains("duplicated parameter `animate`"), "{msg}");
    // … and over a definition and its use.
    let (line, col, msg, rendered) = fail(&format!(
        "define a {TRI} animate {{ key 0 {{ scale 1 }} }} }}\nobject {{ a animate {{ key 0 {{ scale 2 }} }} }}"
    ));
    assert_eq!((line, col), (2, 12), "{rendered}");
    assert!(msg.contains("a second `animate` for one object") && rendered.contains("the first is here"), "{msg}");
}

#[test]
fn bad_timelines_are_reported() {
    for (text, col, want) in [
        ("settings { frames 0 }", 19, "frames is 0, outside 1..=1000000"),
        ("settings { frames 2.5 }", 19, "frames must be an integer"),
        ("settings { frame_rate 0 }", 23, "frame_rate is 0, but a frame rate must be positive"),
        ("settings { frame_rate -24 }", 23, "frame_rate is -24, but a frame rate must be positive"),
    ] {
        let (line, c, msg, rendered) = fail(text);
        assert_eq!((line, c), (1, col), "{text}:\n{rendered}");
        assert!(msg.contains(want), "{text}: {msg}");
    }
}

#[test]
fn light_and_camera_keys_are_checked_too() {
    let (line, col, msg, _) = fail(&format!(
        "{SETTINGS}\nlight {{ position <0,1,0>\n  animate {{ key 0 {{ translate <0,0,0> }} key 3 {{ translate <1,0,0> }} }} }}"
    ));
    assert_eq!((line, col), (3, 41));
    assert!(msg.contains("key at 3 s is outside"), "{msg}");
    let (line, col, msg, _) = fail(&format!(
        "{SETTINGS}\ncamera {{ perspective position <0,0,5> to <0,0,0> up <0,1,0>\n  animate {{ interpolation smoth key 0 {{ rotate_y 3 }} }} }}"
    ));
    assert_eq!((line, col), (3, 27));
    assert!(msg.contains("unknown interpolation `smoth`"), "{msg}");
}

// ---- the example ------------------------------------------------------------------------

#[test]
fn the_animated_example_loads_and_moves() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/animated.scn");
    let s = dynray_scene::load_scn(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.animation.timeline, Timeline { start: 0.0, frames: 48, frame_rate: 24.0 });
    let motion: Vec<Motion> = s.actors.iter().map(|a| a.motion).collect();
    assert_eq!(motion, [Motion::Static, Motion::Dynamic, Motion::Dynamic, Motion::Dynamic]);
    assert_eq!(s.animation.light_nodes.len(), 1);
    assert!(s.animation.camera_node.is_some() && s.is_animated());
    let first = s.frame(0.0);
    let mid = s.frame(s.animation.timeline.time_of(12));
    assert_ne!(first.camera, mid.camera);
    assert_ne!(first.lights, mid.lights);
    // The floor's triangles stay put; the rest move.
    let floor = first.actor_ranges[0].clone();
    let floor_vertices = s.actors[0].mesh.vertex_count();
    assert_eq!(first.mesh.positions[..floor_vertices], mid.mesh.positions[..floor_vertices]);
    assert_ne!(first.mesh.positions[floor_vertices..], mid.mesh.positions[floor_vertices..]);
    assert_eq!(floor, mid.actor_ranges[0]);
}
