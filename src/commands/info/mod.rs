//! `dynray info`: what a file holds and what a structure built over it looks like.

mod adf;
mod gpu;
mod scene;
mod structure;
mod structures;

use super::thousands;
use crate::cli::InfoArgs;
use anyhow::Result;

use std::io::Write;
use std::time::Instant;

/// Prints through a locked, buffered stdout with `writeln!`, not `println!`, so a closed
/// pipe (`dynray info x | head -1`) is an error that `main` turns into a quiet exit
/// instead of a panic.
pub fn run(a: InfoArgs) -> Result<()> {
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut sections = 0;
    if a.structures {
        structures::write(&mut out)?;
        sections += 1;
    }
    if a.gpu {
        if sections > 0 {
            writeln!(out)?;
        }
        gpu::write(&mut out, a.gpu_adapter.as_deref())?;
        sections += 1;
    }
    let Some(file) = &a.file else { return Ok(()) };
    if sections > 0 {
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
    writeln!(out, "normals     {}", scene::normals_summary(scene, shading_ms))?;
    writeln!(out, "animation   {}", scene::animation_summary(scene))?;
    writeln!(
        out,
        "bounds      [{:.6}, {:.6}, {:.6}] .. [{:.6}, {:.6}, {:.6}]",
        b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
    )?;
    // Show the file's figures before a long build.
    out.flush()?;
    structure::write(out, file, mesh, &a.accel)
}
