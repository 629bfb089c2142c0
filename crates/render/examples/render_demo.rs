//! Renders the built-in demo scene with brute force, for looking at the integrator's
//! output before the `dynray render` command exists.
//!
//! `cargo run --release -p dynray-render --example render_demo -- OUT.png [WIDTH HEIGHT [SPHERE_DETAIL]]`

use dynray_accel::Brute;
use dynray_render::{render, write_image, RenderOptions};
use dynray_scene::demo::{demo_scene_with, DEMO_SPHERE_DETAIL};
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = PathBuf::from(args.first().map(String::as_str).unwrap_or("demo.png"));
    let num = |i: usize, default: u32| -> Result<u32, Box<dyn std::error::Error>> {
        Ok(args.get(i).map(|s| s.parse()).transpose()?.unwrap_or(default))
    };
    let mut frame = demo_scene_with(num(3, DEMO_SPHERE_DETAIL)?).frame(0.0);
    frame.settings.width = num(1, frame.settings.width)?;
    frame.settings.height = num(2, frame.settings.height)?;
    let t0 = Instant::now();
    let accel = Brute::build(&frame.mesh)?;
    let t1 = Instant::now();
    let (film, stats) = render(&frame, &accel, &RenderOptions::default());
    let secs = t1.elapsed().as_secs_f64();
    write_image(&film, &out)?;
    println!(
        "{} triangles, build {:.3} s, render {:.3} s, {} rays ({} primary, {} shadow, {} secondary), {:.3} Mrays/s",
        frame.mesh.triangle_count(),
        (t1 - t0).as_secs_f64(),
        secs,
        stats.total_rays(),
        stats.primary_rays,
        stats.shadow_rays,
        stats.secondary_rays,
        stats.total_rays() as f64 / secs / 1e6
    );
    Ok(())
}
