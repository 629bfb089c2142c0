//! BART's AFF (Lext, Assarsson & Möller, "A Benchmark for Animated Ray Tracing", 2001)
//! and Eric Haines' NFF, which AFF extends: `.aff` and `.nff` files.
//!
//! What is read, and where (docs/formats.md has the user's version):
//! - `lexer.rs`: words, `#`/`%` comments, typed reads that name the line;
//! - `parser.rs`: the commands — `v` view, `b` background, `am` ambient, `l` lights,
//!   `a` animation range, `i` includes, `x`/`xs` transform blocks — and their state;
//! - `geometry.rs`: `p`, `pp`, `s`, `c`, `tt`, `ttp`, `tpa`, `m`, and actor grouping;
//! - `material.rs`: `f`, `fm`, textures;
//! - `anim.rs`: `k` keyframes, the rig's clip, the animated camera, range checks.
//!
//! # How a file maps to the scene
//! - Static transforms (`xs`) are baked into vertices; each animated transform (`x name`)
//!   is a [`crate::animation::Node`] of `scene.animation.rig` (parents first; static
//!   transforms between two animated ones become a matrix node), driven by the
//!   `k name` block through one clip. Geometry inside an `x` block belongs to an actor
//!   placed by its node ([`crate::Actor::node`]), whose [`crate::Actor::transform`] is
//!   the node's world matrix at the first frame; everything else is static, in world
//!   space, with [`crate::Transform::IDENTITY`].
//! - `a start end frames` gives [`crate::Timeline::spanning`]: frame `k` at
//!   `start + k·(end − start)/(frames − 1)`. Without `a` the scene has one frame at 0.
//! - The camera is `v`'s (vertical field of view = NFF's `angle`; `resolution` sets the
//!   image size). With a `k camera` block, the camera is a node of its own: in that node's
//!   space it sits at the origin looking down −z with +y up (BART's convention: the keys'
//!   translation is the eye, their rotation turns the view), and `v` gives only the
//!   field of view and resolution.
//! - Lights are point lights without falloff, white unless coloured; a light inside an
//!   `x` block moves with its node ([`crate::Animation::light_nodes`]).
//!
//! Not read: BART's `tpp` (unused by the three scenes) and NFF's detail levels (every
//! `i` is read whatever its level). Unknown commands are errors, not skipped.

mod anim;
mod geometry;
mod lexer;
mod material;
mod parser;

use crate::report::LoadReport;
use crate::texture::untexture_where_no_uvs;
use crate::{Camera, LoadError, Projection, Timeline, Transform};
use dynray_geom::{MeshError, Vec3};
use geometry::Place;
use glam::Mat4;
use std::path::Path;

/// Loads an `.aff` or `.nff` file and the files it includes (module docs).
pub fn load(path: &Path) -> Result<LoadReport, LoadError> {
    let bytes = dynray_geom::file::read(path).map_err(|e| LoadError::io(path, e))?;
    let canonical = std::fs::canonicalize(path).map_err(|e| LoadError::io(path, e))?;
    let text = String::from_utf8_lossy(&bytes);
    let mut loader = parser::Loader::default();
    loader.materials.root_dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    loader.read_file(path, canonical, &text, Place { node: None, local: Mat4::IDENTITY })?;
    finish(path, loader)
}

/// Builds the rig, timeline, camera and actors from what was read, and checks them.
fn finish(path: &Path, loader: parser::Loader) -> Result<LoadReport, LoadError> {
    let parser::Loader { mut scene, mut warnings, groups, keys, range, view, .. } = loader;
    if let Some(r) = &range {
        scene.animation.timeline = Timeline::spanning(r.start, r.end, r.frames);
    }
    let camera_node = keys.build(&mut scene.animation.rig, range.as_ref(), &mut warnings)?;
    if let Some(node) = camera_node {
        let fov_y_deg = view.map_or(45.0, |v| v.angle);
        scene.camera = Some(Camera {
            position: Vec3::ZERO,
            look_at: Vec3::NEG_Z,
            up: Vec3::Y,
            projection: Projection::Perspective { fov_y_deg },
            clip: crate::Clip::NONE,
        });
        scene.animation.camera_node = Some(node);
    }
    let stem = path.file_stem().map_or_else(|| "aff".to_string(), |s| s.to_string_lossy().into_owned());
    let names: Vec<Option<String>> = scene.animation.rig.nodes.iter().map(|n| n.name.clone()).collect();
    scene.actors = groups.into_actors(|node| match node {
        Some(n) => names[n as usize].clone().unwrap_or_else(|| format!("node {n}")),
        None => stem.clone(),
    });
    if scene.actors.is_empty() {
        return Err(LoadError::Mesh { path: path.to_path_buf(), source: MeshError::Empty });
    }
    for a in &scene.actors {
        a.mesh.validate().map_err(|source| LoadError::Mesh { path: path.to_path_buf(), source })?;
    }
    scene.validate_animation().map_err(|m| LoadError::parse(path, None, format!("animation: {m}")))?;
    // Rest placement: the nodes at the first frame.
    let mut world = Vec::new();
    if !scene.animation.rig.nodes.is_empty() {
        scene.animation.rig.world_matrices(scene.animation.timeline.start, &mut world);
    }
    for a in &mut scene.actors {
        if let Some(n) = a.node {
            a.transform = Transform::new(world[n as usize]);
        }
    }
    scene.mark_moving_actors();
    untexture_where_no_uvs(&mut scene, path, &mut warnings);
    Ok(LoadReport { scene, warnings })
}
