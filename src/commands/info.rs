//! `dynray info`: what a file holds and what a structure built over it looks like.

use super::thousands;
use crate::cli::InfoArgs;
use anyhow::{Context, Result};
use std::time::Instant;

pub fn run(a: InfoArgs) -> Result<()> {
    let scene = super::load_scene(&a.file)?;
    let frame = scene.frame(0.0);
    let mesh = &frame.mesh;
    let b = mesh.bounds();
    println!("file        {}", a.file.display());
    println!("actors      {}", thousands(scene.actors.len()));
    println!("vertices    {}", thousands(mesh.vertex_count()));
    println!("triangles   {}", thousands(mesh.triangle_count()));
    println!("materials   {}", thousands(frame.materials.len()));
    println!("lights      {}", thousands(frame.lights.len()));
    println!("normals     {}", if mesh.normals.is_some() { "per vertex" } else { "geometric" });
    println!(
        "bounds      [{:.6}, {:.6}, {:.6}] .. [{:.6}, {:.6}, {:.6}]",
        b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
    );
    let t0 = Instant::now();
    let accel = a.accel.build(mesh, None).with_context(|| format!("{}: cannot build {}", a.file.display(), a.accel))?;
    let build_ms = t0.elapsed().as_secs_f64() * 1e3;
    let s = accel.stats();
    println!();
    println!("structure   {}", accel.name());
    println!("build       {build_ms:.1} ms");
    println!("nodes       {}", thousands(s.nodes));
    println!("leaves      {}", thousands(s.leaves));
    println!("max depth   {}", s.max_depth);
    let tris = mesh.triangle_count().max(1);
    println!("prim refs   {} ({:.3} per triangle)", thousands(s.primitive_refs), s.primitive_refs as f64 / tris as f64);
    if s.leaves > 0 {
        println!("prims/leaf  {:.2} (mean)", s.primitive_refs as f64 / s.leaves as f64);
    }
    if let Some(sah) = s.sah_cost {
        println!("SAH cost    {sah:.2}");
    }
    println!("memory      {} bytes ({:.2} MiB)", thousands(s.memory_bytes), s.memory_bytes as f64 / (1 << 20) as f64);
    for (k, v) in &s.extra {
        println!("{k:<11} {v}");
    }
    if !s.leaf_sizes.is_empty() {
        println!("leaf sizes  (triangles: leaves)");
        let last = s.leaf_sizes.len() - 1;
        for (n, &count) in s.leaf_sizes.iter().enumerate().filter(|(_, &c)| c > 0) {
            let label = if n == last { format!("{n}+") } else { n.to_string() };
            println!("  {label:>4}: {}", thousands(count));
        }
    }
    Ok(())
}
