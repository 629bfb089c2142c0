//! `dynray adf build`: a mesh file to a distance field in seed 001's GPU layout.

use super::thousands;
use crate::cli::{AdfArgs, AdfBuildArgs, AdfCommand};
use anyhow::{bail, Context, Result};
use dynray_adf::{Adf, BuildParams, View, SIGN_RAYS};
use indicatif::{ProgressBar, ProgressStyle};

pub fn run(a: AdfArgs) -> Result<()> {
    match a.command {
        AdfCommand::Build(b) => build(b),
    }
}

fn build(a: AdfBuildArgs) -> Result<()> {
    if !dynray_engine::load::is_adf(&a.output) {
        bail!("{}: the output must be a .adf file (render and info recognise fields by it)", a.output.display());
    }
    let scene = super::load(Some(&a.mesh))?.scene;
    let frame = scene.frame(dynray_engine::timeline::frame_zero(&scene));
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
    adf.set_view(Some(View::of_camera(&frame.camera)));
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
