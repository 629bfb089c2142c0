//! `LiveAccel` under every update policy: after each frame of a deforming dragon (its
//! 11k-triangle decimation, so every structure builds quickly), every
//! structure answers exactly as brute force on that frame (so refits, rebuilds and
//! `auto`'s mix of both trace each frame identically to a fresh build), and the policy
//! does what it says (`rebuild` rebuilds, `refit` refits where the structure can, `auto`
//! rebuilds once the refit tree's SAH cost drifts past the bound, an unchanged frame is
//! kept).

mod support;

use dynray_accel::{AccelKind, AccelSpec, LiveAccel, UpdateAction, UpdatePolicy};
use dynray_geom::Vec3;
use support::*;

#[test]
fn every_structure_and_policy_traces_each_frame_like_brute_force() {
    let base = load("dragon/dragon_vrip_res3.ply.gz");
    let policies = [UpdatePolicy::Rebuild, UpdatePolicy::Refit, UpdatePolicy::default()];
    for &kind in AccelKind::ALL {
        for policy in policies {
            let spec = AccelSpec::new(kind);
            let eye = Some(base.bounds().center() + Vec3::new(0.0, 0.0, 0.5));
            let (mut live, _) = LiveAccel::build(&spec, policy, &base, eye).expect("build");
            for f in 1..4 {
                let mesh = wave(&base, 0.004 * f as f32, f as f32);
                let report = live.update(&mesh, eye).expect("update");
                let refits = live.accel().update_refits();
                match policy {
                    UpdatePolicy::Rebuild => assert_eq!(report.action, UpdateAction::Rebuilt, "{kind:?}"),
                    UpdatePolicy::Refit if refits => assert_eq!(report.action, UpdateAction::Refit, "{kind:?}"),
                    _ => assert_ne!(report.action, UpdateAction::Kept, "{kind:?}"),
                }
                let rays = random_rays(&mesh, 1500, 40 + f);
                assert_matches_oracle(live.accel(), &mesh, &rays, &format!("{kind:?} {policy} frame {f}"));
            }
        }
    }
}

#[test]
fn an_unchanged_frame_keeps_the_structure() {
    let base = bunny();
    for policy in [UpdatePolicy::Rebuild, UpdatePolicy::Refit, UpdatePolicy::default()] {
        let (mut live, _) = LiveAccel::build(&AccelSpec::new(AccelKind::Bvh2), policy, &base, None).unwrap();
        assert_eq!(live.update(&base, None).unwrap().action, UpdateAction::Kept, "{policy}");
    }
}

#[test]
fn auto_rebuilds_once_the_refit_cost_drifts_past_its_bound() {
    let base = bunny();
    let spec = AccelSpec::new(AccelKind::Bvh2);
    // A tight bound: a strong wave makes the refit tree worse than 1 % over a fresh one.
    let (mut live, _) = LiveAccel::build(&spec, UpdatePolicy::Auto { max_cost_ratio: 1.01 }, &base, None).unwrap();
    let strong = wave(&base, 0.05, 2.0);
    let r = live.update(&strong, None).unwrap();
    assert_eq!(r.action, UpdateAction::Rebuilt);
    assert_eq!(r.cost_ratio, Some(1.0));
    // A loose bound keeps refitting the same deformation, and reports its drift.
    let (mut live, _) = LiveAccel::build(&spec, UpdatePolicy::Auto { max_cost_ratio: 1000.0 }, &base, None).unwrap();
    let r = live.update(&strong, None).unwrap();
    assert_eq!(r.action, UpdateAction::Refit);
    assert!(r.cost_ratio.unwrap() > 1.01, "{r:?}");
}

#[test]
fn policies_parse_and_print() {
    for s in ["rebuild", "refit", "auto", "auto:1.5"] {
        assert_eq!(s.parse::<UpdatePolicy>().unwrap().to_string(), s);
    }
    assert!("auto:0.5".parse::<UpdatePolicy>().unwrap_err().contains("above 1"));
    assert!("sometimes".parse::<UpdatePolicy>().unwrap_err().contains("unknown update policy"));
}

#[test]
fn every_structure_follows_a_skinned_animation_exactly() {
    // CesiumMan's walk (glTF skin): frames posed by the scene crate, the structure
    // updated by `auto`, every answer brute force's on that frame.
    let path = scenes_dir().join("CesiumMan/glTF-Binary/CesiumMan.glb");
    let scene = dynray_scene::load_file(&path).expect("CesiumMan loads");
    assert!(scene.is_animated());
    let tl = scene.animation.timeline;
    let first = scene.frame(tl.time_of(0));
    for &kind in AccelKind::ALL {
        let eye = Some(first.camera.position);
        let (mut live, _) = LiveAccel::build(&AccelSpec::new(kind), UpdatePolicy::default(), &first.mesh, eye).unwrap();
        for k in [6, 19, 33, 48] {
            let frame = scene.frame(tl.time_of(k));
            live.update(&frame.mesh, Some(frame.camera.position)).unwrap();
            let rays = random_rays(&frame.mesh, 800, k as u64);
            assert_matches_oracle(live.accel(), &frame.mesh, &rays, &format!("{kind:?} CesiumMan frame {k}"));
        }
    }
}
