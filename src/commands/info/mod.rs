//! `dynray info`: what a file holds and what a structure built over it looks like.

mod adf;
mod gpu;

use super::thousands;
use crate::cli::InfoArgs;
use anyhow::{Context, Result};
use dynray_scene::{NormalSource, Scene};
use std::io::Write;
use std::time::Instant;

/// Prints through a locked, buffered stdout with `writeln!`, not `println!`, so a closed
/// pipe (`dynray info x | head -1`) is an error that `main` turns into a quiet exit
/// instead of a panic.
pub fn run(a: InfoArgs) -> Result<()> {
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if a.gpu {
        gpu::write(&mut out, a.gpu_adapter.as_deref())?;
    }
    let Some(file) = &a.file else { return Ok(()) };
    if a.gpu {
        writeln!(out)?;
    }
    file_info(&mut out, file, &a)
}

fn file_info(out: &mut impl Write, file: &std::path::Path, a: &InfoArgs) -> Result<()> {
    if dynray_engine::load::is_adf(file) {
        return adf::write(out, file);
    }
    // Loaded unshaded, then shaded as `render` does, so the file's own counts are shown
    // and the two steps are timed apart.
    let t0 = Instant::now();
    let mut loaded = super::load(Some(file))?;
    let load_ms = t0.elapsed().as_secs_f64() * 1e3;
    let frame = loaded.scene.frame(dynray_engine::timeline::frame_zero(&loaded.scene));
    let t1 = Instant::now();
    loaded.shade(false)?;
    let scene = &loaded.scene;
    let shading_ms = t1.elapsed().as_secs_f64() * 1e3;
    let mesh = &frame.mesh;
    let b = mesh.bounds();
    writeln!(out, "file        {}", file.display())?;
    writeln!(out, "load        {load_ms:.1} ms")?;
    writeln!(out, "actors      {}", thousands(scene.actors.len()))?;
    writeln!(out, "vertices    {}", thousands(mesh.vertex_count()))?;
    writeln!(out, "triangles   {}", thousands(mesh.triangle_count()))?;
    writeln!(out, "materials   {}", thousands(frame.materials.len()))?;
    let texel_bytes: usize = frame.textures.iter().map(|t| t.memory_bytes()).sum();
    match frame.textures.len() {
        0 => writeln!(out, "textures    0")?,
        n => {
            writeln!(out, "textures    {} ({:.1} MiB of texels)", thousands(n), texel_bytes as f64 / (1 << 20) as f64)?
        }
    }
    writeln!(out, "lights      {}", thousands(frame.lights.len()))?;
    writeln!(out, "normals     {}", normals_summary(scene, shading_ms))?;
    writeln!(out, "animation   {}", animation_summary(scene))?;
    writeln!(
        out,
        "bounds      [{:.6}, {:.6}, {:.6}] .. [{:.6}, {:.6}, {:.6}]",
        b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
    )?;
    // Show the file's figures before a long build.
    out.flush()?;
    let t0 = Instant::now();
    let accel = a.accel.build(mesh, None).with_context(|| format!("{}: cannot build {}", file.display(), a.accel))?;
    let build_ms = t0.elapsed().as_secs_f64() * 1e3;
    let s = accel.stats();
    writeln!(out)?;
    writeln!(out, "structure   {}", accel.name())?;
    writeln!(out, "build       {build_ms:.1} ms")?;
    writeln!(out, "nodes       {}", thousands(s.nodes))?;
    writeln!(out, "leaves      {}", thousands(s.leaves))?;
    writeln!(out, "max depth   {}", s.max_depth)?;
    let tris = mesh.triangle_count().max(1);
    writeln!(
        out,
        "prim refs   {} ({:.3} per triangle)",
        thousands(s.primitive_refs),
        s.primitive_refs as f64 / tris as f64
    )?;
    if s.leaves > 0 {
        writeln!(out, "prims/leaf  {:.2} (mean)", s.primitive_refs as f64 / s.leaves as f64)?;
    }
    if let Some(sah) = s.sah_cost {
        writeln!(out, "SAH cost    {sah:.2}")?;
    }
    writeln!(
        out,
        "memory      {} bytes ({:.2} MiB)",
        thousands(s.memory_bytes),
        s.memory_bytes as f64 / (1 << 20) as f64
    )?;
    for (k, v) in &s.extra {
        writeln!(out, "{k:<11} {v}")?;
    }
    if !s.leaf_sizes.is_empty() {
        writeln!(out, "leaf sizes  (triangles: leaves)")?;
        let last = s.leaf_sizes.len() - 1;
        for (n, &count) in s.leaf_sizes.iter().enumerate().filter(|(_, &c)| c > 0) {
            let label = if n == last { format!("{n}+") } else { n.to_string() };
            writeln!(out, "  {label:>4}: {}", thousands(count))?;
        }
    }
    out.flush()?;
    Ok(())
}

/// Where the rendered normals come from, per kind over the actors (`from file`,
/// `generated (crease 60°), 645 vertices split, in 12.3 ms`, `geometric`), in the order
/// the actors first show each; the actor counts appear when kinds are mixed.
fn normals_summary(scene: &Scene, shading_ms: f64) -> String {
    // (label, actors, split vertices, generated)
    let mut kinds: Vec<(String, usize, usize, bool)> = Vec::new();
    for a in &scene.actors {
        let label = a.normal_source.to_string();
        let (split, generated) = match a.normal_source {
            NormalSource::Generated { split_vertices, .. } => (split_vertices, true),
            _ => (0, false),
        };
        match kinds.iter_mut().find(|k| k.0 == label) {
            Some(k) => {
                k.1 += 1;
                k.2 += split;
            }
            None => kinds.push((label, 1, split, generated)),
        }
    }
    let mixed = kinds.len() > 1;
    let parts: Vec<String> = kinds
        .iter()
        .map(|(label, actors, split, generated)| {
            let mut s = label.clone();
            if mixed {
                s += &format!(" for {} actor{}", thousands(*actors), if *actors == 1 { "" } else { "s" });
            }
            if *generated {
                s += &format!(", {} vertices split", thousands(*split));
            }
            s
        })
        .collect();
    let mut summary = if parts.is_empty() { "none (no actors)".to_string() } else { parts.join("; ") };
    if kinds.iter().any(|k| k.3) {
        summary += &format!(", in {shading_ms:.1} ms");
    }
    summary
}

/// One line on what moves: frames and rate, clips, nodes, skins, dynamic actors.
fn animation_summary(scene: &Scene) -> String {
    if !scene.is_animated() {
        return "none (a still scene)".into();
    }
    let a = &scene.animation;
    let t = a.timeline;
    let mut parts = vec![format!(
        "{} frames at {} fps from {} s to {} s",
        thousands(t.frames as usize),
        // Three decimals at most: BART's rates are (N - 1) / duration.
        format!("{:.3}", t.frame_rate).trim_end_matches('0').trim_end_matches('.'),
        t.time_of(0),
        t.time_of(t.frames - 1)
    )];
    let clips = &a.rig.clips;
    if clips.len() > 1 {
        let names: Vec<String> =
            clips.iter().enumerate().map(|(i, c)| c.name.clone().unwrap_or_else(|| format!("#{i}"))).collect();
        parts.push(format!("clips {} (playing {})", names.join(", "), names[a.rig.active_clip.min(names.len() - 1)]));
    } else if let Some(name) = clips.first().and_then(|c| c.name.as_deref()) {
        parts.push(format!("clip {name}"));
    }
    if !a.rig.nodes.is_empty() {
        parts.push(format!("{} nodes", thousands(a.rig.nodes.len())));
    }
    if !a.rig.skins.is_empty() {
        parts.push(match a.rig.skins.len() {
            1 => "1 skin".to_string(),
            n => format!("{n} skins"),
        });
    }
    let dynamic = scene.actors.iter().filter(|x| x.motion == dynray_scene::Motion::Dynamic).count();
    parts.push(format!("{dynamic} of {} actors dynamic", scene.actors.len()));
    parts.join("; ")
}
