//! The point-based physics blocks of the scene language (docs/scene-language.md §9.1):
//! `physics { … }` and an object's `elastic { … }`, their defaults, and every error path.

use dynray_scene::{parse_scn_str, ElasticParams, LoadError, Motion, PhysicsSettings, Scene};
use glam::Vec3;
use std::path::Path;

fn parse(text: &str) -> Scene {
    parse_scn_str("test.scn", text, Path::new(".")).unwrap_or_else(|e| panic!("unexpected error:\n{e}"))
}

/// (line, column, message) of the error of `text`.
fn fail(text: &str) -> (usize, usize, String) {
    match parse_scn_str("test.scn", text, Path::new(".")) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(LoadError::Scene { line, column, message, .. }) => (line, column, message),
        Err(e) => panic!("expected a scene diagnostic, got {e:?}"),
    }
}

const BOX: &str = "box { center <0, 1, 0> orientation <0, 0, 0> scale <1, 1, 1>";

#[test]
fn physics_block_reads_every_key() {
    let s = parse("physics { gravity <0, -9.81, 0> ground 0 substeps 16 }");
    assert_eq!(
        s.physics,
        Some(PhysicsSettings { gravity: Vec3::new(0.0, -9.81, 0.0), ground: Some(0.0), substeps: 16 })
    );
    let s = parse("physics { gravity <1, 2, 3> * 2 }");
    assert_eq!(s.physics.unwrap().gravity, Vec3::new(2.0, 4.0, 6.0));
    assert_eq!(s.physics.unwrap().ground, None, "no ground unless given");
    assert_eq!(s.physics.unwrap().substeps, 1);
    assert_eq!(parse("sphere { center <0,0,0> radius 1 }").physics, None);
}

#[test]
fn elastic_block_reads_every_key_and_makes_the_actor_dynamic() {
    let s = parse(&format!(
        "{BOX} elastic {{ young 5e4 poisson 0.3 density 1000 damping 0.02 phyxels 2000 velocity <0, 1, 0>
           volume 1e4 yield 0.01 creep 5 max_plastic 0.5 }} }}"
    ));
    let e = s.actors[0].elastic.unwrap();
    assert_eq!(
        e,
        ElasticParams {
            young: 5e4,
            poisson: 0.3,
            density: 1000.0,
            damping: 0.02,
            phyxels: 2000,
            velocity: Vec3::Y,
            volume: Some(1e4),
            plastic_yield: 0.01,
            plastic_creep: 5.0,
            plastic_max: 0.5,
        }
    );
    assert_eq!(s.actors[0].motion, Motion::Dynamic);
    assert!(s.is_animated());
    // An elastic box is subdivided so that it can bend: 12 × 4⁴ triangles.
    assert_eq!(s.actors[0].mesh.triangle_count(), 12 * 256);
    let plain = parse(&format!("{BOX} }}"));
    assert_eq!(plain.actors[0].elastic, None);
    assert_eq!(plain.actors[0].motion, Motion::Static);
    assert_eq!(plain.actors[0].mesh.triangle_count(), 12);
}

#[test]
fn elastic_defaults_and_the_other_primitives() {
    let s = parse("sphere { center <0,0,0> radius 1 elastic { } } mesh { vertices { 4 <0,0,0> <1,0,0> <0,1,0> <0,0,1> } triangles { 4 <0,2,1> <0,1,3> <0,3,2> <1,2,3> } elastic { phyxels 8 } }");
    assert_eq!(s.actors[0].elastic, Some(ElasticParams::default()));
    assert_eq!(s.actors[1].elastic.unwrap().phyxels, 8);
    assert!(s.actors.iter().all(|a| a.motion == Motion::Dynamic));
    // A defined elastic object keeps its block where it is placed.
    let s = parse(&format!("define soft {BOX} elastic {{ young 1e3 }} }} object soft"));
    assert_eq!(s.actors[0].elastic.unwrap().young, 1e3);
}

#[test]
fn bad_values_are_errors_at_the_value() {
    let cases = [
        ("young 0", "Young's modulus `young` is 0, but it must be positive (Pa)"),
        ("young -3", "Young's modulus `young` is -3, but it must be positive (Pa)"),
        ("poisson 0.5", "Poisson's ratio `poisson` is 0.5, but it must lie in [0, 0.5)"),
        ("density 0", "elastic density is 0, but it must be positive (kg/m³)"),
        ("damping 1.5", "elastic damping is 1.5, but it must lie in [0, 1]"),
        ("phyxels 4", "the number of phyxels is 4, outside 8..=1000000"),
        ("phyxels 10.5", "the number of phyxels must be an integer, found 10.5"),
        ("velocity 3", "type mismatch: elastic velocity must be a vector, found a real"),
        ("creep -1", "plastic `creep` is -1, but it must not be negative (1/s)"),
        ("volume -1", "volume stiffness `volume` is -1, but it must not be negative (Pa)"),
    ];
    for (body, want) in cases {
        let (line, col, msg) = fail(&format!("{BOX}\n  elastic {{ {body} }} }}"));
        assert_eq!(msg, want, "for `{body}`");
        assert_eq!(line, 2, "for `{body}`");
        let key_len = body.split(' ').next().unwrap().len();
        assert_eq!(col, 13 + key_len + 1, "column of the value of `{body}`");
    }
    let (line, col, msg) = fail("physics {\n  substeps 0 }");
    assert_eq!((line, col, msg.as_str()), (2, 12, "physics substeps is 0, outside 1..=100000"));
    let (_, _, msg) = fail("physics { ground <0, 1, 0> }");
    assert_eq!(msg, "type mismatch: physics ground must be a real, found a vector");
}

#[test]
fn unknown_and_repeated_keys_are_errors() {
    let (line, col, msg) = fail(&format!("{BOX}\n elastic {{ youngs 5 }} }}"));
    assert_eq!((line, col), (2, 12));
    assert_eq!(msg, "unknown parameter `youngs` in `elastic`");
    let (_, _, msg) = fail("physics { gravity <0,0,0> gravity <0,0,0> }");
    assert_eq!(msg, "duplicated parameter `gravity` in `physics`");
    let (_, _, msg) = fail("physics { friction 1 }");
    assert_eq!(msg, "unknown parameter `friction` in `physics`");
    let (line, _, msg) = fail("physics { }\nphysics { }");
    assert_eq!((line, msg.as_str()), (2, "a second `physics` statement"));
    let (_, _, msg) = fail(&format!("{BOX} elastic {{ }} elastic {{ }} }}"));
    assert_eq!(msg, "duplicated parameter `elastic` in `box`");
}

#[test]
fn an_elastic_body_cannot_be_animated_or_static() {
    let (_, _, msg) = fail(&format!("{BOX} elastic {{ }} animate {{ key 0 {{ translate <-3, 0, 0> }} }} }}"));
    assert_eq!(msg, "an `elastic` body cannot also be keyframe-animated");
    let (_, _, msg) = fail(&format!("{BOX} motion static elastic {{ }} }}"));
    assert_eq!(msg, "`motion static` on an `elastic` body");
    // `elastic` belongs to a primitive (its phyxels fill that primitive's mesh), not to
    // the modifiers of `object { name … }`.
    let (_, _, msg) = fail(&format!("define soft {BOX} }} object {{ soft elastic {{ }} }}"));
    assert!(msg.starts_with("expected `material`, `transform` or `}` to close"), "{msg}");
}
