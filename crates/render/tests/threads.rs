//! The image depends neither on the number of threads nor on the tile size, with one
//! sample per pixel or many, and the progress callback sees every tile once.

mod common;

use dynray_accel::Brute;
use dynray_render::{render, Film, RenderOptions, RenderStats};
use dynray_scene::demo::demo_scene_with;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

fn render_in_pool(threads: usize, tile_size: u32) -> (Film, RenderStats) {
    render_samples(threads, tile_size, 1)
}

fn render_samples(threads: usize, tile_size: u32, spp: u32) -> (Film, RenderStats) {
    let mut frame = demo_scene_with(6).frame(0.0);
    frame.settings.width = 72;
    frame.settings.height = 54;
    let accel = Brute::build(&frame.mesh).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| render(&frame, &accel, &RenderOptions { tile_size, spp, ..Default::default() }))
}

fn bits(f: &Film) -> Vec<u32> {
    f.pixels().iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect()
}

#[test]
fn image_is_identical_with_one_and_two_threads() {
    let (one, s1) = render_in_pool(1, 16);
    let (two, s2) = render_in_pool(2, 16);
    assert!(bits(&one) == bits(&two), "1-thread and 2-thread films differ");
    assert_eq!(one.to_srgb8(), two.to_srgb8());
    assert_eq!(s1, s2);
    assert!(s1.secondary_rays > 0 && s1.shadow_rays > 0, "{s1:?}");
}

#[test]
fn image_is_identical_for_any_tile_size() {
    let (a, sa) = render_in_pool(2, 16);
    let (b, sb) = render_in_pool(2, 7);
    assert!(bits(&a) == bits(&b), "tile sizes 16 and 7 give different films");
    assert_eq!(sa.total_rays(), sb.total_rays());
    assert_eq!((sa.tiles, sb.tiles), (5 * 4, 11 * 8));
}

#[test]
fn many_samples_per_pixel_are_independent_of_threads_and_tiles() {
    let (one, s1) = render_samples(1, 16, 5);
    let (two, s2) = render_samples(2, 7, 5);
    assert!(bits(&one) == bits(&two), "5-sample films differ between 1 thread/16 px and 2 threads/7 px tiles");
    assert_eq!(s1.total_rays(), s2.total_rays());
    assert_eq!(s1.primary_rays, 72 * 54 * 5);
    // Anti-aliasing changes silhouette pixels, not the whole image.
    let (centre, _) = render_samples(2, 16, 1);
    let changed =
        one.pixels().iter().zip(&centre.pixels()).filter(|(a, b)| (**a - **b).abs().max_element() > 1e-3).count();
    assert!(changed > 0 && changed * 2 < 72 * 54, "{changed} of {} pixels changed", 72 * 54);
}

#[test]
fn progress_reports_every_tile_once() {
    let mut frame = demo_scene_with(3).frame(0.0);
    frame.settings.width = 40;
    frame.settings.height = 20;
    let accel = Brute::build(&frame.mesh).unwrap();
    let calls = AtomicUsize::new(0);
    let seen = Mutex::new(Vec::new());
    let progress = |done: usize, total: usize| {
        calls.fetch_add(1, Ordering::Relaxed);
        seen.lock().unwrap().push((done, total));
    };
    let (_, stats) =
        render(&frame, &accel, &RenderOptions { tile_size: 16, progress: Some(&progress), ..Default::default() });
    let mut seen = seen.into_inner().unwrap();
    seen.sort();
    assert_eq!(stats.tiles, 3 * 2);
    assert_eq!(seen, (1..=6).map(|d| (d, 6)).collect::<Vec<_>>());
    assert_eq!(calls.load(Ordering::Relaxed), 6);
    assert_eq!(stats.primary_rays, 800);
}
