//! `carousel`: the dynamic preset's rigid instanced scene. Eight copies of a model circle
//! a ninth on a floor, each turning about the centre as it goes; the floor and the centre
//! copy are static. Written in the scene language (so it exercises the same loader and
//! keyframes a user's file does) around whichever model is asked for: the bunny for
//! `carousel`, the 11k-triangle dragon for `carousel-small`.
//!
//! Under `--scene-accel instanced` the eight moving copies are instances of one shared
//! local-space structure and the static ones one part built once, so a frame costs a
//! top-level rebuild over nine boxes; a flat structure refits or rebuilds 9× the model.

use anyhow::{Context, Result};
use dynray_scene::Scene;
use std::fmt::Write;
use std::path::Path;

/// Names: the bunny's carousel and the small one.
pub const NAMES: [(&str, &str); 2] = [("carousel", "bunny"), ("carousel-small", "dragon-res4")];

/// Copies that move.
pub const MOVING: usize = 8;

/// Frames of the carousel's timeline (at 24 per second): one slow turn of the ring.
pub const FRAMES: u32 = 60;

/// The carousel around `model` (a mesh file), loaded.
pub fn scene(model: &Path) -> Result<Scene> {
    let mesh = dynray_scene::load_mesh(model).with_context(|| format!("carousel model {}", model.display()))?;
    let b = mesh.bounds();
    let (c, e) = (b.center(), b.extent());
    // Each copy about 0.8 units across, standing on the floor.
    let s = 0.8 / e.max_element().max(1e-6);
    let file = model.display().to_string().replace('\\', "/");
    let place = format!("translate <{}, {}, {}> scale <0, 0, 0> <{s}, {s}, {s}>", -c.x, -b.min.y, -c.z);
    let mut t = String::new();
    let _ = writeln!(
        t,
        "settings {{ image_width 320 image_height 240 max_recursion_level 3 frames {FRAMES} frame_rate 24 }}"
    );
    let _ = writeln!(t, "environment {{ background rgb(0.45, 0.65, 0.95) ambient rgb(0.2, 0.2, 0.2) ior 1 }}");
    let _ = writeln!(t, "camera {{ perspective position <0, 3.2, 5.2> to <0, 0.2, 0> up <0, 1, 0> angle 45 }}");
    let _ = writeln!(t, "light {{ position <2, 6, 3> color rgb(0.9, 0.9, 0.9) }}");
    let _ = writeln!(t, "define floor material {{ color rgb(0.8, 0.8, 0.75) finish {{ ambient 0.3 diffuse 0.7 }} }}");
    let _ = writeln!(
        t,
        "define clay material {{ color rgb(0.85, 0.55, 0.35) finish {{ ambient 0.2 diffuse 0.7 spot 0.3 shine 40 }} }}"
    );
    let _ = writeln!(
        t,
        "box {{ center <0, -0.05, 0> orientation <0, 0, 0> scale <8, 0.1, 8> material floor motion static }}"
    );
    let _ = writeln!(t, "mesh {{ file \"{file}\" material clay transform {{ {place} }} motion static }}");
    let last = FRAMES - 1;
    for k in 0..MOVING {
        let a = 360.0 * k as f32 / MOVING as f32;
        // Placed on the ring, then turned about the centre: an orbit.
        let _ = writeln!(
            t,
            "mesh {{ file \"{file}\" material clay transform {{ {place} translate <1.8, 0, 0> }}\n  \
             animate {{ key 0 {{ rotate_y {a} }} frame {last} {{ rotate_y {} }} }} }}",
            a + 90.0
        );
    }
    dynray_scene::parse_scn_str("carousel.scn", &t, Path::new(".")).map_err(|e| anyhow::anyhow!("carousel: {e}"))
}
