//! Two-level layouts on real animated scenes: BART's robots (221 rigidly moving parts
//! over 23 distinct meshes, a static room) and CesiumMan (a skin). Every structure, in
//! every layout, frame after frame through `LiveScene::update`, against its oracle:
//! brute force over the frame for the split layout (bit for bit, as for one structure),
//! brute force over each instance's local triangles with the mapped ray for the instanced
//! one (bit for bit), and, across layouts, the same triangle as the flat frame's.

use dynray_accel::{Accel, AccelKind, AccelSpec, Brute, LiveScene, SceneLayout, UpdateAction, UpdatePolicy};
use dynray_geom::{Hit, Ray, Vec3};
use dynray_render::{actor_geometry, build_live_scene};
use dynray_scene::Scene;
use std::path::PathBuf;

fn scene(rel: &str) -> Scene {
    let dir = std::env::var_os("DYNRAY_SCENES")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes"));
    let path = dir.join(rel);
    assert!(path.is_file(), "{} is missing: the test models live in ../shared/scenes", path.display());
    dynray_scene::load_file(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Rays from the camera through a grid of the image, and from random points of the
/// scene's box towards others (seeded): surfaces, edges, inside the robots' parts.
fn rays(frame: &dynray_scene::Frame, n: usize) -> Vec<Ray> {
    let b = frame.mesh.bounds();
    let cam = dynray_render::CameraRays::new(&frame.camera, 40, 30);
    let mut out: Vec<Ray> =
        (0..30).flat_map(|y| (0..40).map(move |x| (x, y))).map(|(x, y)| cam.primary(x, y)).collect();
    let mut s = 0x9e37_79b9_u32;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s as f32 / u32::MAX as f32
    };
    let mut point = || b.min + (b.max - b.min) * Vec3::new(next(), next(), next());
    while out.len() < n {
        let (o, t) = (point(), point());
        out.push(Ray::new(o, t - o));
    }
    out
}

/// Frames 0, 7, 14 of the file's own timeline.
const FRAMES: [u32; 3] = [0, 7, 14];

#[test]
fn split_layouts_of_the_robots_equal_brute_force_on_every_frame_for_every_structure() {
    let scene = scene("bart/robot/aff/Robot.aff");
    let tl = scene.animation.timeline;
    for &kind in AccelKind::ALL {
        let spec = AccelSpec::new(kind);
        let mut frame = scene.frame(tl.time_of(FRAMES[0]));
        let (mut live, _) = build_live_scene(&spec, UpdatePolicy::Refit, SceneLayout::Split, &scene, &frame).unwrap();
        assert!(live.two_level().is_some(), "{kind:?}: the robots move, two levels expected");
        for &k in &FRAMES {
            scene.frame_into(tl.time_of(k), &mut frame);
            let report =
                live.update(&actor_geometry(&scene, &frame), &frame.mesh, Some(frame.camera.position)).unwrap();
            if k != FRAMES[0] {
                assert_ne!(report.action, UpdateAction::Kept, "{kind:?} frame {k}: the robots moved");
            }
            live.accel().validate(&frame.mesh).unwrap_or_else(|e| panic!("{kind:?} frame {k}: {e}"));
            let brute = Brute::build(&frame.mesh).unwrap();
            let rays = rays(&frame, 2400);
            let mut hits = 0;
            for r in &rays {
                let (a, b) = (live.accel().intersect(r), brute.intersect(r));
                assert!(a.same_as(&b), "{kind:?} frame {k}: {a:?} vs brute force {b:?}, ray {r:?}");
                hits += a.is_hit() as usize;
            }
            assert!(hits > rays.len() / 2, "{kind:?}: {hits} hits: the rays must reach the scene");
            let occluded = rays.iter().take(600).filter(|r| live.accel().occluded(r) != brute.occluded(r)).count();
            assert_eq!(occluded, 0, "{kind:?} frame {k}: any-hit answers differ");
        }
    }
}

#[test]
fn instanced_robots_equal_the_instanced_oracle_and_hit_the_flat_frames_triangles() {
    let scene = scene("bart/robot/aff/Robot.aff");
    let tl = scene.animation.timeline;
    let mut frames: Vec<_> = FRAMES.iter().map(|&k| scene.frame(tl.time_of(k))).collect();
    let ray_sets: Vec<Vec<Ray>> = frames.iter().map(|f| rays(f, 400)).collect();
    // The oracle per frame, from the first structure's instances (every structure has
    // the same instances and parts' triangles; only view-dependent ones do not share).
    let mut oracle: Vec<Vec<Hit>> = Vec::new();
    for &kind in AccelKind::ALL {
        let spec = AccelSpec::new(kind);
        let (mut live, _) = build_live_scene(
            &spec,
            UpdatePolicy::Auto { max_cost_ratio: 1.3 },
            SceneLayout::Instanced,
            &scene,
            &frames[0],
        )
        .unwrap();
        let (parts, instances) = live.two_level().unwrap().counts();
        assert_eq!(instances, 221, "{kind:?}");
        assert_eq!(parts, if kind.is_view_dependent() { 221 } else { 23 }, "{kind:?}: shared local meshes");
        for (i, frame) in frames.iter_mut().enumerate() {
            let report = live.update(&actor_geometry(&scene, frame), &frame.mesh, Some(frame.camera.position)).unwrap();
            if i > 0 && !kind.is_view_dependent() {
                assert_eq!(report.action, UpdateAction::Moved, "{kind:?}: rigid motion moves instances only");
                assert_eq!(live.last_parts().unwrap().rebuilt + live.last_parts().unwrap().refit, 0);
            }
            live.accel().validate(&frame.mesh).unwrap_or_else(|e| panic!("{kind:?} frame {i}: {e}"));
            let tl2 = live.two_level().unwrap();
            if oracle.len() <= i {
                oracle.push(ray_sets[i].iter().map(|r| tl2.intersect_brute(r, &|p| tl2.part_mesh(p))).collect());
            }
            let brute = Brute::build(&frame.mesh).unwrap();
            let (mut same, mut n) = (0, 0);
            for (r, want) in ray_sets[i].iter().zip(&oracle[i]) {
                let got = live.accel().intersect(r);
                assert!(got.same_as(want), "{kind:?} frame {i}: {got:?} vs instanced oracle {want:?}, ray {r:?}");
                let flat = brute.intersect(r);
                if flat.is_hit() || got.is_hit() {
                    n += 1;
                    same += (flat.prim == got.prim && (flat.t - got.t).abs() <= 1e-4 * flat.t.abs().max(1.0)) as usize;
                }
            }
            assert!(same * 1000 >= n * 995, "{kind:?} frame {i}: {same} of {n} hits agree with the flat frame");
        }
    }
}

#[test]
fn a_skinned_figure_is_one_deforming_part_refit_by_the_policy() {
    let scene = scene("CesiumMan/glTF-Binary/CesiumMan.glb");
    let tl = scene.animation.timeline;
    let spec = AccelSpec::new(AccelKind::Bvh2);
    let mut frame = scene.frame(tl.time_of(0));
    let (mut live, _) = build_live_scene(&spec, UpdatePolicy::Refit, SceneLayout::Instanced, &scene, &frame).unwrap();
    for k in [3, 6] {
        scene.frame_into(tl.time_of(k), &mut frame);
        let r = live.update(&actor_geometry(&scene, &frame), &frame.mesh, None).unwrap();
        assert_eq!(r.action, UpdateAction::Refit, "frame {k}");
        let brute = Brute::build(&frame.mesh).unwrap();
        for ray in rays(&frame, 1500) {
            assert!(live.accel().intersect(&ray).same_as(&brute.intersect(&ray)), "frame {k}");
        }
    }
    let flat = LiveScene::build(
        &spec,
        UpdatePolicy::Refit,
        SceneLayout::Flat,
        &actor_geometry(&scene, &frame),
        &frame.mesh,
        None,
    )
    .unwrap()
    .0;
    assert!(flat.two_level().is_none());
}
