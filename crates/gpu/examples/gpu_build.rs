//! Times the three ways of getting a BVH onto the device (`cpu`, `sah`, `lbvh`) and the
//! device refit on one mesh, stage by stage, with each tree's shape and SAH cost, and
//! checks every device tree against the CPU validator: the figures of docs/gpu.md
//! ("Building on the GPU").
//!
//! `cargo run --release -p dynray-gpu --example gpu_build [MESH] [REPEAT]`
//! (default: the Stanford bunny of ../shared/scenes, 3 repeats; the fastest is kept).

use dynray_accel::{Accel, BvhParams};
use dynray_gpu::{BuildTimings, GpuBuild, GpuBvh, GpuContext};
use std::path::PathBuf;
use std::sync::Arc;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let path = args.next().map(PathBuf::from).unwrap_or_else(|| {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes/bunny/bun_zipper.ply")
    });
    let repeat: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(3).max(1);
    let mesh = dynray_scene::load_mesh(&path)?;
    let ctx = Arc::new(GpuContext::new(&Default::default())?);
    let params = BvhParams::default();
    println!(
        "{}: {} triangles on {} ({} repeats, fastest kept)",
        path.display(),
        mesh.triangle_count(),
        ctx.adapter().name,
        repeat
    );
    let fastest = |f: &mut dyn FnMut() -> anyhow::Result<BuildTimings>| -> anyhow::Result<BuildTimings> {
        let mut best: Option<BuildTimings> = None;
        for _ in 0..repeat {
            let t = f()?;
            if best.as_ref().is_none_or(|b| t.total() < b.total()) {
                best = Some(t);
            }
        }
        Ok(best.expect("repeat >= 1"))
    };
    // Kernels are compiled on first use: one untimed build of each first.
    for how in GpuBuild::ALL {
        GpuBvh::build(ctx.clone(), &mesh, how, &params)?;
    }
    let mut cpu_ms = 0.0;
    for how in GpuBuild::ALL {
        let t = fastest(&mut || Ok(GpuBvh::build(ctx.clone(), &mesh, how, &params)?.1))?;
        let (mut gpu, _) = GpuBvh::build(ctx.clone(), &mesh, how, &params)?;
        let stats = gpu.download(&mesh, &params)?.stats();
        if how == GpuBuild::Cpu {
            cpu_ms = t.total() * 1e3;
        }
        println!(
            "{how:>5}: {:8.1} ms ({:.2}x the cpu build+upload)  {} nodes, depth {}, SAH {:.2}  [{}]",
            t.total() * 1e3,
            t.total() * 1e3 / cpu_ms,
            stats.nodes,
            stats.max_depth,
            stats.sah_cost.unwrap_or(f64::NAN),
            t.summary()
        );
        if how != GpuBuild::Cpu {
            let r = fastest(&mut || Ok(gpu.refit(&mesh)?))?;
            println!(
                "       refit {:8.1} ms ({:.1}x faster than its build)  [{}]",
                r.total() * 1e3,
                t.total() / r.total(),
                r.summary()
            );
        }
    }
    Ok(())
}
