//! `dynray animate`: the frames of an animated scene to numbered PNGs, through the one
//! frame path of the engine — `Scene::frame_into(t)`, the structure kept current by its
//! update policy (`dynray_accel::LiveAccel`), `dynray_render::render` — with per-frame
//! timings, a preview, shards for array jobs and resumption (docs/animate.md).

use super::animate_tracer::{GpuChoice, Tracer};
use super::fields::Fields;
use super::{preview, thousands, time};
use crate::cli::AnimateArgs;
use anyhow::{bail, Context, Result};
use dynray_render::{write_image, RenderOptions};
use dynray_scene::{Frame, Shading};
use indicatif::{ProgressBar, ProgressStyle};
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Columns of `timings.csv`, one row per rendered frame.
pub const TIMINGS_HEADER: &str = "frame,time_s,pose_ms,update,update_ms,sah_ratio,render_ms,time_to_image_ms,rays";

/// `DIR/frame_NNNN.png`.
pub fn frame_path(dir: &Path, k: u32) -> PathBuf {
    dir.join(format!("frame_{k:04}.png"))
}

pub fn run(a: AnimateArgs) -> Result<()> {
    let label = a.scene.display().to_string();
    let mut scene = super::load_unshaded(&a.scene)?;
    if a.flat_shading {
        for actor in &mut scene.actors {
            actor.shading = Shading::Flat;
        }
    }
    super::apply_shading(&mut scene, &a.scene)?;
    time::shape_timeline(&mut scene, &label, a.clip.as_deref(), a.fps)?;
    let timeline = scene.animation.timeline;
    let last_frame = timeline.frames - 1;
    let (first, last) = a.frames.unwrap_or((0, last_frame));
    if last > last_frame {
        bail!(
            "{label}: --frames {first}..{last} goes past the last frame, {last_frame} ({} frames at {} fps)",
            timeline.frames,
            timeline.frame_rate
        );
    }
    let (shard, shards) = a.shard.unwrap_or((0, 1));
    // Refused options and a missing GPU fail before anything is written.
    let options = RenderOptions { spp: a.spp, seed: a.seed, integrator: a.integrator, ..Default::default() };
    a.backend.check()?;
    let fields = Fields::load(&scene.distance_fields, &label)?;
    if !fields.is_empty() && a.backend.gpu_options().is_some() {
        bail!("{label}: scenes with `adf` blocks render on the CPU only; drop --backend gpu");
    }
    let mut tracer = match a.backend.gpu_options() {
        None => Tracer::cpu(&a.accel, a.update, a.scene_accel),
        Some(gpu) => {
            let choice = GpuChoice { options: &gpu, build: a.backend.gpu_build, strategy: a.gpu_strategy };
            Tracer::gpu(&a.accel, a.update, &options, choice).with_context(|| label.clone())?
        }
    };
    std::fs::create_dir_all(&a.out).with_context(|| format!("{}: cannot create the output folder", a.out.display()))?;
    let mine: Vec<u32> = (first..=last).filter(|k| k % shards == shard).collect();
    let todo: Vec<u32> = mine.iter().copied().filter(|&k| !(a.resume && frame_path(&a.out, k).is_file())).collect();
    if todo.len() < mine.len() {
        eprintln!("{label}: resuming: {} of {} frames already there", mine.len() - todo.len(), mine.len());
    }

    let timings_name =
        if shards == 1 { "timings.csv".to_string() } else { format!("timings_shard_{shard}_of_{shards}.csv") };
    let timings_path = a.out.join(&timings_name);
    let mut timings = open_timings(&timings_path, a.resume)?;

    let bar = ProgressBar::new(todo.len() as u64);
    bar.set_style(ProgressStyle::with_template("{bar:40} frame {pos}/{len} {elapsed} (eta {eta}) {msg}").unwrap());
    // Built before the loop (sampling and neighbourhoods once); each frame steps it on.
    let mut world = super::physics::world(&scene, &label)?;
    if let Some(w) = &world {
        eprintln!("{label}: physics: {}", w.describe());
    }
    let mut frame = Frame::default();
    let started = Instant::now();
    let mut rays_total = 0u64;
    for &k in &todo {
        let t = timeline.time_of(k);
        let t0 = Instant::now();
        scene.frame_into(t, &mut frame);
        // Simulated bodies replace their actors' vertices (pose_ms includes the steps).
        super::physics::simulate(world.as_mut(), t, &mut frame, &label)?;
        if let Some(w) = a.width {
            frame.settings.width = w;
        }
        if let Some(h) = a.height {
            frame.settings.height = h;
        }
        let pose = t0.elapsed();
        let report = tracer.update(&scene, &frame).with_context(|| format!("{label}: frame {k}"))?;
        let t1 = Instant::now();
        let (film, stats) = tracer.render(&frame, &fields, &options).with_context(|| format!("{label}: frame {k}"))?;
        let render_time = t1.elapsed();
        let to_image = t0.elapsed();
        write_image(&film, &frame_path(&a.out, k))?;
        if a.export_meshes {
            write_obj(&frame, &a.out.join(format!("mesh_{k:04}.obj")))?;
        }
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        let ratio = report.cost_ratio.map(|r| format!("{r:.4}")).unwrap_or_default();
        writeln!(
            timings,
            "{k},{t},{:.3},{},{:.3},{ratio},{:.3},{:.3},{}",
            ms(pose),
            report.action.name(),
            ms(report.time),
            ms(render_time),
            ms(to_image),
            stats.total_rays()
        )
        .and_then(|()| timings.flush())
        .with_context(|| format!("{}: cannot write", timings_path.display()))?;
        rays_total += stats.total_rays();
        bar.set_message(format!("{} {:.0} ms", report.action.name(), ms(to_image)));
        bar.inc(1);
    }
    bar.finish_and_clear();
    let all: Vec<PathBuf> = (first..=last).map(|k| frame_path(&a.out, k)).collect();
    let preview_note = if all.iter().all(|p| p.is_file()) {
        let path = a.out.join("preview.gif");
        preview::write_gif(&all, timeline.frame_rate, &path)?;
        format!(", preview {}", path.display())
    } else {
        String::new()
    };
    eprintln!(
        "{label}: {} frames of {first}..={last} ({} triangles, {}), {} rays in {:.2} s -> {}/frame_NNNN.png, {timings_name}{preview_note}",
        todo.len(),
        thousands(frame.mesh.triangle_count()),
        tracer.describe(),
        thousands(rays_total as usize),
        started.elapsed().as_secs_f64(),
        a.out.display()
    );
    Ok(())
}

/// The timings file: new (with its header), or appended to when resuming one that has
/// rows already (rows are written only after their frame's PNG, so none is repeated).
fn open_timings(path: &Path, resume: bool) -> Result<BufWriter<File>> {
    let append = resume && path.is_file();
    let file = if append { OpenOptions::new().append(true).open(path) } else { File::create(path) }
        .with_context(|| format!("{}: cannot open", path.display()))?;
    let mut w = BufWriter::new(file);
    if !append {
        writeln!(w, "{TIMINGS_HEADER}").with_context(|| format!("{}: cannot write", path.display()))?;
    }
    Ok(w)
}

/// The frame's world-space triangles as OBJ, in the frame's stable order (vertex `i` of
/// the frame is OBJ vertex `i + 1`), written under a temporary name and renamed. Floats
/// are printed in Rust's shortest round-trip form, so reading them back gives the same
/// bits.
fn write_obj(frame: &Frame, path: &Path) -> Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut tmp = tempfile::NamedTempFile::new_in(dir).with_context(|| format!("{}: cannot create", dir.display()))?;
    {
        let mut w = BufWriter::new(tmp.as_file_mut());
        writeln!(w, "# dynray animate: frame at t = {} s, {} triangles", frame.time, frame.mesh.triangle_count())?;
        for p in &frame.mesh.positions {
            writeln!(w, "v {} {} {}", p[0], p[1], p[2])?;
        }
        for t in &frame.mesh.indices {
            writeln!(w, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
        }
        w.flush()?;
    }
    tmp.persist(path).map_err(|e| e.error).with_context(|| format!("{}: cannot write", path.display()))?;
    Ok(())
}
