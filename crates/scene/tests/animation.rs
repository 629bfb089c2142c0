//! Animation evaluation against hand-computed values: tracks (step, linear, slerp, glTF
//! cubic spline, Kochanek–Bartels), the node hierarchy, skinning, morphs, keyed vertices,
//! and a frame of a scene posed by all of them.

use dynray_geom::TriangleMesh;
use dynray_scene::animation::{
    Channel, ChannelTarget, Clip, Deformation, Interpolation, Morph, MorphTarget, Node, NodePose, Rig, Skin,
    SkinBinding, Track, TrackError, VertexKeys,
};
use dynray_scene::{Actor, Material, Motion, Scene, Timeline};
use glam::{Mat4, Quat, Vec3};

fn sample(track: &Track, t: f32) -> Vec<f32> {
    let mut v = vec![0.0; track.width()];
    track.sample_into(t, &mut v);
    v
}

fn close(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-5 * (1.0 + y.abs()))
}

#[test]
fn step_and_linear_hold_outside_and_interpolate_inside() {
    let step = Track::new(vec![0.0, 1.0, 3.0], 1, vec![10.0, 20.0, 40.0], Interpolation::Step).unwrap();
    assert_eq!(sample(&step, -5.0), [10.0]);
    assert_eq!(sample(&step, 0.99), [10.0]);
    assert_eq!(sample(&step, 1.0), [20.0]);
    assert_eq!(sample(&step, 2.5), [20.0]);
    assert_eq!(sample(&step, 9.0), [40.0]);
    let lin = Track::new(vec![0.0, 1.0, 3.0], 2, vec![0.0, 0.0, 2.0, -2.0, 6.0, 2.0], Interpolation::Linear).unwrap();
    assert_eq!(sample(&lin, 0.25), [0.5, -0.5]);
    // Halfway through the second (two-second) segment.
    assert_eq!(sample(&lin, 2.0), [4.0, 0.0]);
    assert_eq!(sample(&lin, 7.0), [6.0, 2.0]);
}

#[test]
fn linear_rotations_slerp_the_short_way() {
    let z90 = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    // The second key written as -q: the same rotation, which slerp must treat as such.
    let keys = [Quat::IDENTITY.to_array(), (-z90).to_array()].concat();
    let rot = Track::new(vec![0.0, 1.0], 4, keys, Interpolation::Linear).unwrap().into_rotation().unwrap();
    let q = sample(&rot, 0.5);
    let expected = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
    let q = Quat::from_slice(&q);
    assert!(q.dot(expected).abs() > 1.0 - 1e-6, "{q} vs {expected}");
}

#[test]
fn gltf_cubic_spline_matches_the_hermite_formula() {
    // One component, keys at t = 1 and t = 3 (dt = 2): values 0 and 4, out-tangent of the
    // first 1, in-tangent of the second -1 (per second). At s = 0.5, Hermite gives
    // h00 p0 + h10 dt m0 + h01 p1 + h11 dt m1 = 0 + 0.125·2·1 + 0.5·4 + (-0.125)·2·(-1) = 2.5.
    let triples = [9.0, 0.0, 1.0, -1.0, 4.0, 9.0];
    let track = Track::cubic_spline(vec![1.0, 3.0], 1, &triples).unwrap();
    assert!(close(&sample(&track, 2.0), &[2.5]));
    assert_eq!(sample(&track, 1.0), [0.0]);
    assert_eq!(sample(&track, 3.0), [4.0]);
}

#[test]
fn catmull_rom_and_tcb_follow_kochanek_bartels() {
    // Evenly spaced keys 0, 1, 4, 9 at t = 0..3 (y = t²). Catmull–Rom tangents at keys 1
    // and 2 are (4-0)/2 = 2 and (9-1)/2 = 4; at s = 0.5 of segment 1..2:
    // 0.5·1 + 0.125·2 + 0.5·4 - 0.125·4 = 2.25 = 1.5², the parabola's value.
    let cr = Track::new(vec![0.0, 1.0, 2.0, 3.0], 1, vec![0.0, 1.0, 4.0, 9.0], Interpolation::Tcb).unwrap();
    assert!(close(&sample(&cr, 1.5), &[2.25]));
    // Two keys: the end tangents are the chord, so the curve is a straight line.
    let two = Track::new(vec![0.0, 2.0], 1, vec![1.0, 5.0], Interpolation::Tcb).unwrap();
    assert!(close(&sample(&two, 0.5), &[2.0]));
    // Tension 1 everywhere: zero tangents, h00 p0 + h01 p1 = 0.5·1 + 0.5·4 at s = 0.5.
    let tense = Track::tcb(vec![0.0, 1.0, 2.0, 3.0], 1, vec![0.0, 1.0, 4.0, 9.0], vec![[1.0, 0.0, 0.0]; 4]).unwrap();
    assert!(close(&sample(&tense, 1.5), &[2.5]));
    // Bias +1 at key 1 (overshoot): its tangents weigh only the incoming chord.
    let biased = Track::tcb(
        vec![0.0, 1.0, 2.0, 3.0],
        1,
        vec![0.0, 1.0, 4.0, 9.0],
        vec![[0.0; 3], [0.0, 0.0, 1.0], [0.0; 3], [0.0; 3]],
    )
    .unwrap();
    // Outgoing at key 1: 0.5·(1+1)·(1-0) + 0.5·(1-1)·(4-1) = 1; incoming at key 2: 4.
    // s = 0.5: 0.5·1 + 0.125·1 + 0.5·4 - 0.125·4 = 2.125.
    assert!(close(&sample(&biased, 1.5), &[2.125]));
}

#[test]
fn uneven_key_spacing_scales_tangents() {
    // Keys at t = 0, 1, 3 with values 0, 1, 3 (a straight line y = t): with the spacing
    // correction the Catmull–Rom curve reproduces the line exactly.
    let t = Track::new(vec![0.0, 1.0, 3.0], 1, vec![0.0, 1.0, 3.0], Interpolation::Tcb).unwrap();
    for x in [0.25f32, 0.5, 1.5, 2.0, 2.75] {
        assert!(close(&sample(&t, x), &[x]), "at {x}: {:?}", sample(&t, x));
    }
}

#[test]
fn bad_tracks_are_refused() {
    assert_eq!(Track::new(vec![], 1, vec![], Interpolation::Linear), Err(TrackError::Empty));
    assert!(matches!(
        Track::new(vec![0.0, 0.0], 1, vec![1.0, 2.0], Interpolation::Linear),
        Err(TrackError::NotIncreasing { key: 1, .. })
    ));
    assert!(matches!(
        Track::new(vec![0.0, f32::NAN], 1, vec![1.0, 2.0], Interpolation::Linear),
        Err(TrackError::NonFiniteTime { key: 1 })
    ));
    assert!(matches!(Track::new(vec![0.0], 3, vec![1.0, 2.0], Interpolation::Linear), Err(TrackError::Length { .. })));
    assert!(matches!(Track::cubic_spline(vec![0.0], 1, &[1.0]), Err(TrackError::Length { .. })));
    let zero = Track::new(vec![0.0], 4, vec![0.0; 4], Interpolation::Linear).unwrap();
    assert_eq!(zero.into_rotation(), Err(TrackError::ZeroRotation { key: 0 }));
}

fn triangle() -> TriangleMesh {
    TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]])
}

fn translation_clip(node: u32, to: Vec3) -> Clip {
    let track = Track::new(vec![0.0, 1.0], 3, [[0.0; 3], to.to_array()].concat(), Interpolation::Linear).unwrap();
    Clip {
        name: Some("move".into()),
        channels: vec![Channel { node, target: ChannelTarget::Translation, track: track.into() }],
    }
}

#[test]
fn a_node_hierarchy_places_its_actor_at_any_time() {
    // Parent rotates 90° about z and is moved by the clip; the child is offset by +x.
    let mut s = Scene { materials: vec![Material::default()], ..Default::default() };
    s.animation.rig = Rig {
        nodes: vec![
            Node {
                name: Some("parent".into()),
                parent: None,
                rest: NodePose::Trs {
                    translation: Vec3::ZERO,
                    rotation: Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
                    scale: Vec3::ONE,
                },
                rest_weights: vec![],
            },
            Node {
                name: Some("child".into()),
                parent: Some(0),
                rest: NodePose::Matrix(Mat4::from_translation(Vec3::X)),
                rest_weights: vec![],
            },
        ],
        clips: vec![translation_clip(0, Vec3::new(0.0, 0.0, 10.0))],
        active_clip: 0,
        skins: vec![],
    };
    let mut a = Actor::new(None, triangle(), 0);
    a.node = Some(1);
    s.actors.push(a);
    s.validate_animation().unwrap();
    s.mark_moving_actors();
    assert_eq!(s.actors[0].motion, Motion::Dynamic);
    assert!(s.is_animated());
    let f = s.frame(0.5);
    // Vertex (1,0,0): child offset → (2,0,0), parent rotation → (0,2,0), translation z 5.
    let p = Vec3::from_array(f.mesh.positions[1]);
    assert!(p.distance(Vec3::new(0.0, 2.0, 5.0)) < 1e-5, "{p}");
    assert_eq!(f.time, 0.5);
}

#[test]
fn skinning_blends_joint_matrices_and_ignores_the_node() {
    // Two joints: joint 0 stays, joint 1 moves by +y·2 over the clip. Vertex 1 is half on
    // each, vertex 2 all on joint 1; the inverse bind of joint 1 undoes its rest offset x+1.
    let mut s = Scene { materials: vec![Material::default()], ..Default::default() };
    s.animation.rig = Rig {
        nodes: vec![
            Node { name: None, parent: None, rest: NodePose::IDENTITY, rest_weights: vec![] },
            Node {
                name: None,
                parent: None,
                rest: NodePose::Trs { translation: Vec3::X, rotation: Quat::IDENTITY, scale: Vec3::ONE },
                rest_weights: vec![],
            },
        ],
        clips: vec![Clip {
            name: None,
            channels: vec![Channel {
                node: 1,
                target: ChannelTarget::Translation,
                track: Track::new(vec![0.0, 1.0], 3, vec![1.0, 0.0, 0.0, 1.0, 2.0, 0.0], Interpolation::Linear)
                    .unwrap()
                    .into(),
            }],
        }],
        active_clip: 0,
        skins: vec![Skin {
            name: None,
            joints: vec![0, 1],
            inverse_bind: vec![Mat4::IDENTITY, Mat4::from_translation(-Vec3::X)],
        }],
    };
    let mut a = Actor::new(None, triangle(), 0)
        .with_transform(dynray_scene::Transform::new(Mat4::from_translation(Vec3::splat(100.0))));
    a.deform = Some(Deformation {
        skin: Some(SkinBinding {
            skin: 0,
            joints: vec![[0, 0, 0, 0], [0, 1, 0, 0], [1, 0, 0, 0]],
            weights: vec![[1.0, 0.0, 0.0, 0.0], [0.5, 0.5, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]],
        }),
        ..Default::default()
    });
    s.actors.push(a);
    s.validate_animation().unwrap();
    let f = s.frame(1.0);
    // Joint 1's skin matrix at t = 1 is translate(1,2,0)·translate(-1,0,0) = translate(0,2,0).
    assert_eq!(f.mesh.positions[0], [0.0, 0.0, 0.0]);
    assert_eq!(f.mesh.positions[1], [1.0, 1.0, 0.0]);
    assert_eq!(f.mesh.positions[2], [0.0, 3.0, 0.0]);
    // At rest (t = 0) the skin reproduces the bind pose.
    assert_eq!(s.frame(0.0).mesh.positions, triangle().positions);
}

#[test]
fn morph_weights_and_vertex_keys_move_vertices() {
    let mut s = Scene { materials: vec![Material::default()], ..Default::default() };
    s.animation.rig.nodes.push(Node {
        name: None,
        parent: None,
        rest: NodePose::IDENTITY,
        rest_weights: vec![0.0, 0.0],
    });
    s.animation.rig.clips.push(Clip {
        name: None,
        channels: vec![Channel {
            node: 0,
            target: ChannelTarget::Weights,
            track: Track::new(vec![0.0, 2.0], 2, vec![0.0, 0.0, 1.0, 0.5], Interpolation::Linear).unwrap().into(),
        }],
    });
    let mut a = Actor::new(None, triangle(), 0);
    a.deform = Some(Deformation {
        morph: Some(Morph {
            node: 0,
            targets: vec![
                MorphTarget { positions: vec![[0.0, 0.0, 2.0]; 3], normals: None },
                MorphTarget { positions: vec![[4.0, 0.0, 0.0], [0.0; 3], [0.0; 3]], normals: None },
            ],
        }),
        ..Default::default()
    });
    s.actors.push(a);
    let mut b = Actor::new(None, triangle(), 0);
    b.deform = Some(Deformation {
        keys: Some(VertexKeys {
            times: vec![0.0, 4.0],
            positions: vec![triangle().positions, vec![[0.0, 0.0, 8.0], [1.0, 0.0, 8.0], [0.0, 1.0, 8.0]]],
            normals: None,
        }),
        ..Default::default()
    });
    s.actors.push(b);
    s.validate_animation().unwrap();
    let f = s.frame(1.0);
    // Weights at t = 1: (0.5, 0.25): vertex 0 gets z 1 and x 1.
    assert_eq!(f.mesh.positions[0], [1.0, 0.0, 1.0]);
    assert_eq!(f.mesh.positions[1], [1.0, 0.0, 1.0]);
    // Keyed actor at t = 1: a quarter of the way to z = 8.
    assert_eq!(f.mesh.positions[3], [0.0, 0.0, 2.0]);
    assert_eq!(f.mesh.indices, vec![[0, 1, 2], [3, 4, 5]]);
}

#[test]
fn broken_animations_are_reported_not_evaluated() {
    let mut s = Scene { materials: vec![Material::default()], ..Default::default() };
    s.animation.rig.nodes.push(Node { name: None, parent: Some(0), rest: NodePose::IDENTITY, rest_weights: vec![] });
    assert!(s.validate_animation().unwrap_err().contains("parent 0 must be an earlier node"));
    s.animation.rig.nodes[0].parent = None;
    let mut a = Actor::new(Some("skinned".into()), triangle(), 0);
    a.deform = Some(Deformation {
        skin: Some(SkinBinding { skin: 3, joints: vec![[0; 4]; 3], weights: vec![[1.0, 0.0, 0.0, 0.0]; 3] }),
        ..Default::default()
    });
    s.actors.push(a);
    let e = s.validate_animation().unwrap_err();
    assert!(e.contains("actor 0 (skinned): skin 3 does not exist"), "{e}");
    s.animation.rig.skins.push(Skin { name: None, joints: vec![0], inverse_bind: vec![Mat4::IDENTITY] });
    s.actors[0].deform.as_mut().unwrap().skin.as_mut().unwrap().skin = 0;
    s.actors[0].deform.as_mut().unwrap().skin.as_mut().unwrap().joints[2] = [5, 0, 0, 0];
    let e = s.validate_animation().unwrap_err();
    assert!(e.contains("vertex 2 names joint 5 of a skin with 1"), "{e}");
}

#[test]
fn timelines_put_frames_where_each_format_says() {
    let t = Timeline { start: 0.0, frames: 48, frame_rate: 24.0 };
    assert_eq!(t.time_of(12), 0.5);
    // BART: `a 0 2 21` is 21 frames from 0 to 2 s inclusive.
    let bart = Timeline::spanning(0.0, 2.0, 21);
    assert_eq!(bart.time_of(0), 0.0);
    assert!((bart.time_of(20) - 2.0).abs() < 1e-6);
    assert!((bart.time_of(10) - 1.0).abs() < 1e-6);
    // A glTF clip of 2 s at 24 fps: frames 0..=48.
    assert_eq!(Timeline::covering(0.0, 2.0, 24.0).frames, 49);
}
