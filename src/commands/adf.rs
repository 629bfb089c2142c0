//! `dynray adf build`, and the distance-field side of `render` and `info`: loading a
//! `.adf` file, the scene it is seen in, and its figures.

use super::thousands;
use crate::cli::{AdfArgs, AdfBuildArgs, AdfCommand};
use anyhow::{bail, Context, Result};
use dynray_adf::{Adf, BuildParams, View, ViewProjection, FORMAT_VERSION, SIGN_RAYS};
use dynray_scene::{Camera, Clip, Material, Projection, Scene};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::path::Path;

pub fn run(a: AdfArgs) -> Result<()> {
    match a.command {
        AdfCommand::Build(b) => build(b),
    }
}

/// True for a path `render` and `info` read as a distance field.
pub fn is_adf(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("adf"))
}

/// Reads and checks a `.adf` file (its errors name it).
pub fn load(path: &Path) -> Result<Adf> {
    Ok(Adf::load(path)?)
}

fn build(a: AdfBuildArgs) -> Result<()> {
    if !is_adf(&a.output) {
        bail!("{}: the output must be a .adf file (render and info recognise fields by it)", a.output.display());
    }
    let scene = super::load_unshaded(&a.mesh)?;
    let frame = scene.frame(scene.animation.timeline.time_of(0));
    let params = BuildParams { max_level: a.max_level, epsilon: a.epsilon };
    let bar = ProgressBar::new(a.max_level as u64);
    // `unwrap` on a literal template, checked by every run.
    bar.set_style(ProgressStyle::with_template("{msg} {bar:40} level {pos}/{len} {elapsed}").unwrap());
    bar.set_message("building");
    let label = a.mesh.display().to_string();
    let (mut adf, topology) = Adf::from_mesh(&frame.mesh, &params, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })
    .with_context(|| format!("{label}: cannot build a distance field"))?;
    bar.finish_and_clear();
    if !topology.is_closed() {
        eprintln!(
            "dynray: warning: {label}: the mesh is not closed ({} boundary and {} non-manifold edges): \
             inside and outside follow the majority of {SIGN_RAYS} ray-parity votes (docs/adf.md, \"Sign rule\")",
            thousands(topology.boundary_edges),
            thousands(topology.non_manifold_edges)
        );
    }
    adf.set_view(Some(view_of(&frame.camera)));
    adf.save(&a.output)?;
    let h = adf.hash();
    eprintln!(
        "{label}: {} triangles -> {}: max level {}, {} cells ({} internal), build {:.1} ms, hash {:.1} ms \
         (H {}^3, Φ {}^3, {} attempt(s))",
        thousands(frame.mesh.triangle_count()),
        a.output.display(),
        adf.max_level(),
        thousands(adf.cells() as usize),
        thousands(adf.internal_cells() as usize),
        adf.info().build_ms,
        adf.info().hash_ms,
        h.table_edge(),
        h.offset_edge(),
        h.attempts()
    );
    Ok(())
}

fn view_of(c: &Camera) -> View {
    let projection = match c.projection {
        Projection::Perspective { fov_y_deg } => ViewProjection::Perspective(fov_y_deg),
        Projection::Parallel { height } => ViewProjection::Parallel(height),
    };
    View { position: c.position, look_at: c.look_at, up: c.up, projection }
}

/// The scene a field is rendered in: what its source mesh file would have had — the
/// default material, the default light placed for the mesh's box, and the mesh's camera
/// (stored in the file), so `render mesh.ply` and `render mesh.adf` frame the same view.
pub fn scene_of(adf: &Adf) -> Scene {
    let mut scene = Scene { materials: vec![Material::default()], ..Default::default() };
    scene.add_default_light_around(adf.source_bounds());
    scene.camera = Some(match adf.info().view {
        Some(v) => Camera {
            position: v.position,
            look_at: v.look_at,
            up: v.up,
            projection: match v.projection {
                ViewProjection::Perspective(fov_y_deg) => Projection::Perspective { fov_y_deg },
                ViewProjection::Parallel(height) => Projection::Parallel { height },
            },
            // The source is a mesh file, whose default view has no clip planes.
            clip: Clip::NONE,
        },
        None => Camera::framing(&adf.source_bounds()),
    });
    scene
}

fn kib(bytes: u64) -> String {
    format!("{:.1} KiB", bytes as f64 / 1024.0)
}

fn saving(ours: u64, theirs: u64) -> String {
    format!("{:.1} %", 100.0 * (1.0 - ours as f64 / theirs.max(1) as f64))
}

/// `dynray info FILE.adf`.
pub fn info(out: &mut impl Write, file: &Path) -> Result<()> {
    let adf = load(file)?;
    let i = adf.info();
    let (b, c) = (adf.source_bounds(), adf.cube());
    let m = adf.memory();
    let h = adf.hash();
    let n = adf.internal_cells();
    let per_level = |v: &[u64]| v.iter().map(|&x| thousands(x as usize)).collect::<Vec<_>>().join(" ");
    writeln!(out, "file        {}", file.display())?;
    writeln!(out, "format      dynray distance field, version {FORMAT_VERSION}")?;
    writeln!(out, "source      {} triangles", thousands(i.triangles as usize))?;
    writeln!(
        out,
        "bounds      [{:.6}, {:.6}, {:.6}] .. [{:.6}, {:.6}, {:.6}]",
        b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z
    )?;
    writeln!(out, "cube        origin [{:.6}, {:.6}, {:.6}], edge {:.6}", c.origin.x, c.origin.y, c.origin.z, c.size)?;
    writeln!(
        out,
        "levels      0..={} (finest cell {:.6})",
        adf.max_level(),
        c.size / (1u32 << adf.max_level()) as f32
    )?;
    writeln!(
        out,
        "cells       {} ({} internal, {} leaves)",
        thousands(adf.cells() as usize),
        thousands(n as usize),
        thousands((adf.cells() - n) as usize)
    )?;
    writeln!(out, "internal    per level {}", per_level(&i.internal_per_level))?;
    writeln!(out, "leaves      per level {}", per_level(&i.leaves_per_level))?;
    writeln!(
        out,
        "field       epsilon {:.3e}, Lipschitz bound {:.3} (global), {} samples set by the T-junction rule",
        adf.epsilon(),
        adf.lipschitz(),
        thousands(i.constrained_samples as usize)
    )?;
    let t = adf.voxels().size();
    writeln!(
        out,
        "voxels      {}x{}x{} texels, {} ({} in the {} blocks)",
        t[0],
        t[1],
        t[2],
        kib(m.voxel_bytes),
        kib(m.voxel_block_bytes),
        thousands(n as usize)
    )?;
    writeln!(
        out,
        "cell table  H {}^3 entries of 8 bytes, {} ({:.1} % full)",
        h.table_edge(),
        kib(m.cell_table_bytes),
        100.0 * n as f64 / (h.table_edge() as f64).powi(3)
    )?;
    writeln!(out, "offsets     Φ {}^3 entries of 8 bytes, {}", h.offset_edge(), kib(m.offset_table_bytes))?;
    writeln!(
        out,
        "step bounds {} floats, {} (per-cell Lipschitz bounds of the sphere tracer; not in the seed)",
        thousands(n as usize),
        kib(m.step_bound_bytes)
    )?;
    writeln!(out, "memory      {} in all", kib(m.total_bytes()))?;
    writeln!(
        out,
        "full grid   {}^3 samples, {}: the field takes {:.2} % of it",
        (1u64 << adf.max_level()) + 1,
        kib(m.full_grid_bytes),
        100.0 * m.total_bytes() as f64 / m.full_grid_bytes.max(1) as f64
    )?;
    writeln!(
        out,
        "classic ADF voxels {} (8 per cell): the 3x3x3 sibling blocks save {} (seed: ~57 %)",
        kib(m.classic_voxel_bytes),
        saving(m.voxel_block_bytes, m.classic_voxel_bytes)
    )?;
    writeln!(
        out,
        "classic ADF cells  {} (one per cell): H of internal cells saves {} ({} with its empty slots; seed: up to 87 %)",
        kib(m.classic_cell_bytes),
        saving(8 * n, m.classic_cell_bytes),
        saving(m.cell_table_bytes, m.classic_cell_bytes)
    )?;
    writeln!(
        out,
        "classic ADF total  {}: the field takes {:.1} % of it",
        kib(m.classic_bytes()),
        100.0 * m.total_bytes() as f64 / m.classic_bytes().max(1) as f64
    )?;
    writeln!(out, "build       {:.1} ms", i.build_ms)?;
    writeln!(out, "hash        {:.1} ms, {} attempt(s)", i.hash_ms, h.attempts())?;
    Ok(())
}
