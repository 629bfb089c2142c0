//! The live job against the render job: progressive frames of a still view add up to
//! exactly the image `render --spp N` gives, whatever the thread count, and every change
//! restarts the image.

use dynray_accel::UpdatePolicy;
use dynray_engine::{Live, Loaded, RenderJob};
use dynray_render::IntegratorKind;
use dynray_scene::demo::demo_scene_with;

fn small_job(integrator: IntegratorKind, spp: u32) -> RenderJob {
    RenderJob { width: Some(48), height: Some(36), spp: Some(spp), integrator, seed: 7, ..Default::default() }
}

fn demo() -> Loaded {
    Loaded::from_scene(demo_scene_with(6), "demo")
}

fn bits(film: &dynray_render::Film) -> Vec<u32> {
    film.pixels().iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect()
}

#[test]
fn n_still_frames_equal_a_render_of_n_samples_bit_for_bit() {
    for (integrator, spp) in [(IntegratorKind::Whitted, 4), (IntegratorKind::Path, 5), (IntegratorKind::Cumulative, 3)]
    {
        let job = small_job(integrator, spp);
        let expected = job.clone().run(demo(), None).unwrap();
        let mut live = Live::new(demo(), job, UpdatePolicy::default()).unwrap();
        live.set_threads(Some(1)).unwrap();
        for k in 0..spp {
            let f = live.step().unwrap();
            assert_eq!(f.restarted, k == 0, "{integrator}: frame {k}");
            assert_eq!(f.samples, k + 1);
        }
        assert!(bits(live.film()) == bits(&expected.film), "{integrator}: {spp} frames against --spp {spp}");
        assert_eq!(live.film().to_srgb8(), expected.film.to_srgb8());
    }
}

#[test]
fn whitted_converges_after_its_pattern_and_then_idles() {
    let mut live = Live::new(demo(), small_job(IntegratorKind::Whitted, 2), UpdatePolicy::default()).unwrap();
    live.step().unwrap();
    assert!(!live.converged());
    live.step().unwrap();
    assert!(live.converged());
    let f = live.step().unwrap();
    assert!(f.idle && f.samples == 2 && f.rays == 0);
}

#[test]
fn the_path_tracer_keeps_adding_passes_that_match_render_passes() {
    let job = small_job(IntegratorKind::Path, 2);
    let mut live = Live::new(demo(), job, UpdatePolicy::default()).unwrap();
    live.step().unwrap();
    live.step().unwrap();
    let after_two = bits(live.film());
    live.step().unwrap();
    live.step().unwrap();
    assert!(!live.converged());
    assert!(bits(live.film()) != after_two, "the later frames add samples");
    let options = dynray_render::RenderOptions {
        spp: 2,
        passes: 2,
        seed: 7,
        integrator: IntegratorKind::Path,
        ..Default::default()
    };
    let (expected, _) = dynray_render::render(live.frame(), live.accel().unwrap(), &options);
    // The same samples; a pass adds its pixel's sum of 2 where frames add one at a time,
    // so the sums agree to rounding, not to the bit.
    let worst = live
        .film()
        .pixels()
        .iter()
        .zip(expected.pixels())
        .map(|(a, b)| (*a - b).abs().max_element() / b.abs().max_element().max(1e-3))
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-5, "4 frames of a 2-sample pattern against 2 passes of 2 samples: {worst}");
}

#[test]
fn a_moved_camera_restarts_and_renders_what_the_render_job_renders_from_there() {
    let job = small_job(IntegratorKind::Whitted, 1);
    let mut live = Live::new(demo(), job.clone(), UpdatePolicy::default()).unwrap();
    live.step().unwrap();
    let before = live.film().to_srgb8();
    let mut cam = live.camera();
    cam.position += glam::Vec3::new(0.7, 0.3, 0.0);
    live.set_camera(cam);
    let f = live.step().unwrap();
    assert!(f.restarted && f.update.is_none(), "a view-independent structure is not updated for a camera move");
    assert_ne!(live.film().to_srgb8(), before);

    let mut moved = demo_scene_with(6);
    moved.camera = Some(cam);
    let expected = job.run(Loaded::from_scene(moved, "demo"), None).unwrap();
    assert!(bits(live.film()) == bits(&expected.film));

    live.reset_camera();
    live.step().unwrap();
    assert_eq!(live.film().to_srgb8(), before, "reset returns to the scene's camera");
}

#[test]
fn a_view_dependent_structure_is_updated_when_the_camera_moves() {
    let job = RenderJob { accel: "apit".parse().unwrap(), ..small_job(IntegratorKind::Whitted, 1) };
    let mut live = Live::new(demo(), job, UpdatePolicy::default()).unwrap();
    live.step().unwrap();
    let mut cam = live.camera();
    cam.position += glam::Vec3::new(0.5, 0.0, 0.2);
    live.set_camera(cam);
    assert!(live.step().unwrap().update.is_some());
}

#[test]
fn switching_the_structure_changes_no_pixel() {
    let mut live = Live::new(demo(), small_job(IntegratorKind::Whitted, 2), UpdatePolicy::default()).unwrap();
    let run = |live: &mut Live| {
        while !live.converged() {
            live.step().unwrap();
        }
        bits(live.film())
    };
    let bvh = run(&mut live);
    for accel in ["bih", "kdtree", "octree", "grid", "bvh2"] {
        let job = RenderJob { accel: accel.parse().unwrap(), ..live.job().clone() };
        live.reconfigure(job, UpdatePolicy::default()).unwrap();
        assert!(!live.converged());
        let f = live.step().unwrap();
        assert!(f.restarted && f.update.is_some(), "{accel}: built at the next step");
        assert!(run(&mut live) == bvh, "{accel} changed pixels");
    }
}

#[test]
fn resolution_scale_renders_smaller_and_restarts() {
    let mut live = Live::new(demo(), small_job(IntegratorKind::Whitted, 1), UpdatePolicy::default()).unwrap();
    live.set_scale(0.5);
    live.step().unwrap();
    assert_eq!((live.film().width(), live.film().height()), (24, 18));
    live.set_scale(1.0);
    assert!(live.step().unwrap().restarted);
    assert_eq!((live.film().width(), live.film().height()), (48, 36));
}

#[test]
fn bad_switches_change_nothing() {
    let mut live = Live::new(demo(), small_job(IntegratorKind::Whitted, 1), UpdatePolicy::default()).unwrap();
    let job = RenderJob { spp: Some(0), ..live.job().clone() };
    let e = live.reconfigure(job, UpdatePolicy::default()).unwrap_err().to_string();
    assert!(e.contains("--spp"), "{e}");
    assert_eq!(live.job().spp, Some(1));
    let e = Live::new(
        demo(),
        RenderJob { aov: Some(dynray_render::Aov::Depth), ..Default::default() },
        UpdatePolicy::default(),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("AOV"), "{e}");
}
