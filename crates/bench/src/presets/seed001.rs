//! `--preset seed001`: seed 001's measurements of adaptively sampled distance fields, per
//! model and maximum level (8, 9 and 10 on the bunny and the 202k-triangle dragon):
//! build and hash-generation time, the three tables against a full grid and the classic
//! pointer ADF, the cost of point location by linear, binary and coherent linear level
//! search (random points, and the samples sphere tracing takes along primary rays, the
//! case of the seed's "≈ 30 %" claim), sphere-traced Mrays/s, and the reconstructed
//! distance's error against the exact signed distance. With `--backend gpu` the
//! location and tracing are measured on the device too, and its answers compared with the
//! CPU's.

use super::experiment::{Experiment, Lab};
use crate::config::BenchConfig;
use crate::format::{bytes, num, thousands};
use crate::gpu::GpuSession;
use crate::measure::warm_then_timed;
use crate::progress::progress_bar;
use crate::results::median;
use crate::scenes::load_scenes;
use anyhow::{Context, Result};
use dynray_adf::{Adf, BuildParams, DistanceSource, HashVariant, MeshSource, PerfectHash, Search};
use dynray_geom::{Ray, TriangleMesh, Vec3};
use dynray_gpu::GpuAdf;
use dynray_render::CameraRays;
use rand::{rngs::SmallRng, Rng, SeedableRng};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt::Write;

/// `--preset seed001` (`presets::seed001`): distance fields per model and maximum level.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed001Result {
    /// Primary-ray image width of the sphere-tracing measurements.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Random points of the point-location and error measurements.
    pub points: usize,
    /// The device of the GPU columns, when `--backend gpu` was given.
    pub gpu_adapter: Option<String>,
    /// One entry per model and level.
    pub runs: Vec<FieldRun>,
}

/// One field: build, tables, memory, point location, sphere tracing, error.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FieldRun {
    /// Model name.
    pub scene: String,
    /// Its triangles.
    pub triangles: usize,
    /// Maximum level.
    pub max_level: u32,
    /// Build tolerance, world units.
    pub epsilon: f64,
    /// Finest cell edge, world units.
    pub finest_cell: f64,
    /// Subdivision, T-junction rule and packing, ms.
    pub build_ms: f64,
    /// Perfect-hash generation, ms.
    pub hash_ms: f64,
    /// Hash attempts (1: the first succeeded).
    pub hash_attempts: u32,
    /// Cells of the full tree.
    pub cells: u64,
    /// Internal cells (entries of H).
    pub internal_cells: u64,
    /// Edges of H and Φ.
    pub table_edges: [u32; 2],
    /// The unmodified Lefebvre–Hoppe hash (`w = m̄`) generated on the same keys: its
    /// time, ms (to success or to giving up).
    pub lefebvre_hoppe_ms: f64,
    /// Its attempts when it succeeded; `None`: it failed within the retry budget.
    pub lefebvre_hoppe_attempts: Option<u32>,
    /// Bytes: voxel texture, H, Φ, per-cell step bounds, total.
    pub bytes: [u64; 5],
    /// Bytes of a full grid at the finest resolution and of the classic ADF (voxels,
    /// cell records).
    pub baseline_bytes: [u64; 3],
    /// Point location of random points, per search (linear, binary, coherent linear).
    pub locate_cpu: Vec<SearchCost>,
    /// The same on the device.
    pub locate_gpu: Vec<SearchCost>,
    /// Sphere tracing the primary rays with each search, on the CPU.
    pub march_cpu: Vec<SearchCost>,
    /// The same on the device.
    pub march_gpu: Vec<SearchCost>,
    /// Primary rays that hit the field.
    pub hits: usize,
    /// Device rays whose answer differs from the CPU's (hit/miss or `t` bits).
    pub gpu_differences: Option<usize>,
    /// |reconstructed − exact| signed distance over `ε` at random points of the cube and
    /// at points within two finest cells of the surface: mean, 99th percentile, max.
    pub error_cube: [f64; 3],
    /// The same near the surface.
    pub error_near: [f64; 3],
    /// Share of the near-surface points within `ε`.
    pub within_epsilon_near: f64,
}

/// One search's cost in one measurement.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SearchCost {
    /// `linear`, `binary` or `coherent`.
    pub search: String,
    /// Median wall time, ms.
    pub ms: f64,
    /// Lookups (points, or field samples of the march).
    pub lookups: u64,
    /// Hash probes per lookup.
    pub probes_per_lookup: f64,
    /// Millions of lookups (or, for the march, of rays) per second.
    pub mega_per_s: f64,
}

/// The searches, in report order.
const SEARCHES: [(Search, &str); 3] =
    [(Search::Linear, "linear"), (Search::Binary, "binary"), (Search::CoherentLinear, "coherent")];

/// Points per run of the coherent search's hint in the random-point measurement (one
/// device invocation takes a run; the CPU the same runs).
const RUN: usize = 16;

/// Tolerance of every build, as a fraction of the cube's edge (`adf build`'s default).
const EPSILON: f32 = 1e-3;

/// The models and levels measured.
fn plan(config: &BenchConfig) -> Vec<(String, Vec<u32>)> {
    let levels = if config.quick { vec![6] } else { vec![8, 9, 10] };
    let names: Vec<String> = if !config.scenes.is_empty() {
        config.scenes.clone()
    } else if config.quick {
        vec!["bunny".into()]
    } else {
        vec!["bunny".into(), "dragon-res2".into()]
    };
    names.into_iter().map(|n| (n, levels.clone())).collect()
}

/// Runs the preset. Device failures (a table too large for the adapter) become notes and
/// leave that field's GPU columns empty.
pub fn run(config: &BenchConfig, gpu: Option<&GpuSession>, notes: &mut Vec<String>) -> Result<Seed001Result> {
    let (width, height) = if config.size_given {
        (config.width, config.height)
    } else if config.quick {
        (64, 48)
    } else {
        (640, 480)
    };
    let points = if config.quick { 4_000 } else { 200_000 };
    let plan = plan(config);
    let total: usize = plan.iter().map(|(_, l)| l.len()).sum();
    let bar = progress_bar(config.progress, total as u64);
    let mut runs = Vec::new();
    for (name, levels) in &plan {
        let scene = load_scenes(std::slice::from_ref(name), config.scenes_dir.as_deref())?.remove(0);
        let mesh = &scene.frame.mesh;
        let camera = CameraRays::new(&scene.frame.camera, width, height);
        let rays: Vec<Ray> = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| camera.ray_at(x as f32 + 0.5, y as f32 + 0.5))
            .collect();
        let exact = MeshSource::new(mesh).with_context(|| format!("seed001: {name}"))?;
        for &level in levels {
            bar.set_message(format!("seed001: {name} at level {level}"));
            let params = BuildParams { max_level: level, epsilon: EPSILON };
            let (adf, _) =
                Adf::from_mesh(mesh, &params, &|_, _| {}).with_context(|| format!("seed001: {name} level {level}"))?;
            let (mut run, cpu_answers) = measure_cpu(config, name, mesh, &adf, &rays, &exact, points)?;
            if let Some(g) = gpu {
                match measure_gpu(config, g, &adf, (&rays, &cpu_answers), points, &mut run) {
                    Ok(()) => {}
                    Err(e) => notes.push(format!("seed001: {name} level {level} on the GPU: {e:#}")),
                }
            }
            runs.push(run);
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    Ok(Seed001Result { width, height, points, gpu_adapter: gpu.map(|g| g.ctx.adapter().name.clone()), runs })
}

/// Random unit-cube points as finest-level coordinates (seeded: the same on every run).
fn random_points(adf: &Adf, n: usize) -> Vec<[u32; 3]> {
    let mut rng = SmallRng::seed_from_u64(1);
    (0..n).map(|_| adf.fine_coords(Vec3::new(rng.gen(), rng.gen(), rng.gen()))).collect()
}

fn cost(search: &str, ms: f64, lookups: u64, probes: u64, items: u64) -> SearchCost {
    SearchCost {
        search: search.to_string(),
        ms,
        lookups,
        probes_per_lookup: probes as f64 / lookups.max(1) as f64,
        mega_per_s: items as f64 / (ms.max(1e-9) * 1e3),
    }
}

/// |a − b| / ε: mean, 99th percentile, max.
fn error_figures(mut e: Vec<f64>) -> [f64; 3] {
    if e.is_empty() {
        return [0.0; 3];
    }
    e.sort_by(f64::total_cmp);
    let mean = e.iter().sum::<f64>() / e.len() as f64;
    [mean, e[(e.len() * 99 / 100).min(e.len() - 1)], e[e.len() - 1]]
}

/// Points within two finest cells of the surface: a random point of a random triangle,
/// moved along its normal.
fn near_surface(mesh: &TriangleMesh, finest: f32, n: usize) -> Vec<Vec3> {
    let mut rng = SmallRng::seed_from_u64(2);
    (0..n)
        .filter_map(|_| {
            let t = mesh.triangle(rng.gen_range(0..mesh.triangle_count()));
            let (a, b, c) = (t.p0, t.p1, t.p2);
            let n = (b - a).cross(c - a).normalize_or_zero();
            let (mut u, mut v) = (rng.gen::<f32>(), rng.gen::<f32>());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            (n != Vec3::ZERO).then(|| a + (b - a) * u + (c - a) * v + n * (rng.gen_range(-2.0..2.0) * finest))
        })
        .collect()
}

fn measure_cpu(
    config: &BenchConfig,
    name: &str,
    mesh: &TriangleMesh,
    adf: &Adf,
    rays: &[Ray],
    exact: &MeshSource,
    points: usize,
) -> Result<(FieldRun, Vec<Option<f32>>)> {
    let repeat = config.repeat.max(1);
    let pts = random_points(adf, points);
    let mut locate_cpu = Vec::new();
    for (search, label) in SEARCHES {
        let (times, probes) = warm_then_timed(repeat, || {
            Ok(pts
                .par_chunks(RUN)
                .map(|c| {
                    let mut hint = 0;
                    c.iter().map(|&q| adf.locate_fine(q, search, &mut hint).probes as u64).sum::<u64>()
                })
                .sum::<u64>())
        })?;
        locate_cpu.push(cost(label, median(&times), pts.len() as u64, probes, pts.len() as u64));
    }
    let mut march_cpu = Vec::new();
    let mut hits = 0;
    // The coherent search's answers (every search gives the same), which the device's
    // are compared with.
    let mut answers = Vec::new();
    for (search, label) in SEARCHES {
        let (times, stats) =
            warm_then_timed(repeat, || Ok(rays.par_iter().map(|r| adf.march_with(r, search)).collect::<Vec<_>>()))?;
        let samples: u64 = stats.iter().map(|s| s.samples as u64).sum();
        let probes: u64 = stats.iter().map(|s| s.probes as u64).sum();
        hits = stats.iter().filter(|s| s.t.is_some()).count();
        march_cpu.push(cost(label, median(&times), samples, probes, rays.len() as u64));
        answers = stats.iter().map(|s| s.t).collect();
    }

    let eps = adf.epsilon() as f64;
    let finest = adf.cube().size / (1u32 << adf.max_level()) as f32;
    let cube = adf.cube();
    let mut rng = SmallRng::seed_from_u64(3);
    let in_cube: Vec<Vec3> =
        (0..points / 10).map(|_| cube.origin + Vec3::new(rng.gen(), rng.gen(), rng.gen()) * cube.size).collect();
    let near = near_surface(mesh, finest, points / 10);
    let errors = |ps: &[Vec3]| -> Vec<f64> {
        ps.par_iter()
            .filter_map(|&p| {
                let d = adf.distance(p, Search::CoherentLinear)?;
                Some(((d - exact.signed_distance(p)).abs() as f64) / eps)
            })
            .collect()
    };
    let near_errors = errors(&near);
    let within = near_errors.iter().filter(|&&e| e <= 1.0).count() as f64 / near_errors.len().max(1) as f64;
    let m = adf.memory();
    let info = adf.info();
    let hash = adf.hash();
    // The seed's claim: the original hash fails on deep trees. The same keys, w = m̄.
    let keys = hash.keys();
    let t = std::time::Instant::now();
    let plain = PerfectHash::generate(&keys, HashVariant::LefebvreHoppe);
    let lefebvre_hoppe_ms = crate::measure::ms(t);
    let run = FieldRun {
        scene: name.to_string(),
        triangles: mesh.triangle_count(),
        max_level: adf.max_level(),
        epsilon: eps,
        finest_cell: finest as f64,
        build_ms: info.build_ms as f64,
        hash_ms: info.hash_ms as f64,
        hash_attempts: hash.attempts(),
        cells: adf.cells(),
        internal_cells: adf.internal_cells(),
        table_edges: [hash.table_edge(), hash.offset_edge()],
        lefebvre_hoppe_ms,
        lefebvre_hoppe_attempts: plain.ok().map(|h| h.attempts()),
        bytes: [m.voxel_bytes, m.cell_table_bytes, m.offset_table_bytes, m.step_bound_bytes, m.total_bytes()],
        baseline_bytes: [m.full_grid_bytes, m.classic_voxel_bytes, m.classic_cell_bytes],
        locate_cpu,
        locate_gpu: Vec::new(),
        march_cpu,
        march_gpu: Vec::new(),
        hits,
        gpu_differences: None,
        error_cube: error_figures(errors(&in_cube)),
        error_near: error_figures(near_errors),
        within_epsilon_near: within,
    };
    Ok((run, answers))
}

fn measure_gpu(
    config: &BenchConfig,
    gpu: &GpuSession,
    adf: &Adf,
    (rays, cpu): (&[Ray], &[Option<f32>]),
    points: usize,
    run: &mut FieldRun,
) -> Result<()> {
    let repeat = config.repeat.max(1);
    let device = GpuAdf::upload(gpu.ctx.clone(), adf)?;
    let pts = random_points(adf, points);
    for (search, label) in SEARCHES {
        let (times, located) = warm_then_timed(repeat, || Ok(device.locate(&pts, search, RUN as u32)?))?;
        let probes: u64 = located.iter().map(|l| l.probes as u64).sum();
        run.locate_gpu.push(cost(label, median(&times), pts.len() as u64, probes, pts.len() as u64));
    }
    for (search, label) in SEARCHES {
        let (times, marched) = warm_then_timed(repeat, || Ok(device.march(rays, search, false)?))?;
        let samples: u64 = marched.iter().map(|m| m.samples as u64).sum();
        let probes: u64 = marched.iter().map(|m| m.probes as u64).sum();
        run.march_gpu.push(cost(label, median(&times), samples, probes, rays.len() as u64));
        if search == Search::CoherentLinear {
            let bits = |t: Option<f32>| t.map(f32::to_bits);
            run.gpu_differences = Some(cpu.iter().zip(&marched).filter(|(c, g)| bits(**c) != bits(g.t)).count());
        }
    }
    Ok(())
}

fn find<'a>(costs: &'a [SearchCost], search: &str) -> Option<&'a SearchCost> {
    costs.iter().find(|c| c.search == search)
}

/// Linear search time over coherent linear search time (above 1: coherent is faster).
pub fn coherent_speedup(costs: &[SearchCost]) -> Option<f64> {
    Some(find(costs, "linear")?.ms / find(costs, "coherent")?.ms.max(1e-9))
}

fn search_cells(costs: &[SearchCost]) -> String {
    if costs.is_empty() {
        return "— | — | — | —".to_string();
    }
    let each: Vec<String> = ["linear", "binary", "coherent"]
        .iter()
        .map(|s| find(costs, s).map_or("—".into(), |c| format!("{} ({:.2})", num(c.mega_per_s), c.probes_per_lookup)))
        .collect();
    let x = coherent_speedup(costs).map_or("—".into(), |x| format!("{x:.2}×"));
    format!("{} | {x}", each.join(" | "))
}

/// The preset's section of report.md.
pub fn markdown(r: &Seed001Result, s: &mut String) {
    let _ = writeln!(
        s,
        "## seed001: adaptively sampled distance fields (seed 001)\n\n\
         ε = {EPSILON} of the cube's edge. Memory: the field's three tables (voxel texture of 3×3×3 sibling blocks, \
         H of internal cells, Φ) and the sphere tracer's per-cell step bounds, against a full grid at the finest \
         resolution and the classic ADF (8 voxels and a record per cell). Point location: {} random points, \
         the coherent search's hint carried over runs of {RUN}; the march: {}×{} primary rays of the model's \
         default view, every field sample located by the search named. Cells give millions of lookups (march: \
         of rays) per second and, in brackets, hash probes per lookup; \"coh.\" is linear time / coherent time.{}\n",
        r.points,
        r.width,
        r.height,
        r.gpu_adapter.as_ref().map_or(String::new(), |a| format!(" GPU columns: {a} (wall clock with uploads)."))
    );
    let _ = writeln!(
        s,
        "### Build, tables and memory\n\n\
         | model | level | cells (internal) | build s | hash s (attempts) | Lefebvre–Hoppe hash s | H / Φ | voxels | H | Φ | \
         bounds | total | / full grid | / classic ADF | voxels / classic | H / classic records |\n\
         |---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"
    );
    let pct = |a: u64, b: u64| format!("{:.1} %", 100.0 * a as f64 / b.max(1) as f64);
    for f in &r.runs {
        let [vox, h, phi, bounds, total] = f.bytes;
        let [grid, cvox, ccell] = f.baseline_bytes;
        let _ = writeln!(
            s,
            "| {} | {} | {} ({}) | {:.1} | {:.2} ({}) | {} | {}³ / {}³ | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            f.scene,
            f.max_level,
            thousands(f.cells),
            thousands(f.internal_cells),
            f.build_ms / 1e3,
            f.hash_ms / 1e3,
            f.hash_attempts,
            match f.lefebvre_hoppe_attempts {
                Some(a) => format!("{:.2} ({a})", f.lefebvre_hoppe_ms / 1e3),
                None => format!("failed ({:.2})", f.lefebvre_hoppe_ms / 1e3),
            },
            f.table_edges[0],
            f.table_edges[1],
            bytes(vox as usize),
            bytes(h as usize),
            bytes(phi as usize),
            bytes(bounds as usize),
            bytes(total as usize),
            pct(total, grid),
            pct(total, cvox + ccell),
            pct(27 * 4 * f.internal_cells, cvox),
            pct(8 * f.internal_cells, ccell),
        );
    }
    let _ = writeln!(
        s,
        "\n### Point location and sphere tracing\n\n\
         | model | level | where | random points: linear | binary | coherent | coh. | march: linear | binary | coherent | coh. |\n\
         |---|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|"
    );
    for f in &r.runs {
        for (place, locate, march) in [("CPU", &f.locate_cpu, &f.march_cpu), ("GPU", &f.locate_gpu, &f.march_gpu)] {
            if !locate.is_empty() {
                let (l, m) = (search_cells(locate), search_cells(march));
                let _ = writeln!(s, "| {} | {} | {place} | {l} | {m} |", f.scene, f.max_level);
            }
        }
    }
    let _ = writeln!(
        s,
        "\n### Reconstruction error and hits\n\n\
         |reconstructed − exact| in units of ε: mean / 99th percentile / max.\n\n\
         | model | level | ε (world) | finest cell | in the cube | within 2 cells of the surface | near the surface ≤ ε | \
         primary hits | GPU answers ≠ CPU |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|"
    );
    for f in &r.runs {
        let e = |x: &[f64; 3]| format!("{:.3} / {:.2} / {:.1}", x[0], x[1], x[2]);
        let _ = writeln!(
            s,
            "| {} | {} | {:.2e} | {:.2e} | {} | {} | {:.1} % | {} | {} |",
            f.scene,
            f.max_level,
            f.epsilon,
            f.finest_cell,
            e(&f.error_cube),
            e(&f.error_near),
            100.0 * f.within_epsilon_near,
            thousands(f.hits as u64),
            f.gpu_differences.map_or("—".into(), |d| thousands(d as u64)),
        );
    }
    let _ = writeln!(s);
}

/// `--preset seed001`: distance fields per model and level.
pub struct Seed001;

impl Experiment for Seed001 {
    const PRESET: crate::config::Preset = crate::config::Preset::Seed001;
    type Output = Seed001Result;

    fn run(ctx: &mut Lab<'_>) -> anyhow::Result<Seed001Result> {
        run(ctx.config, ctx.gpu.as_deref(), ctx.notes)
    }

    fn markdown(out: &Seed001Result, png: bool, s: &mut String) {
        let _ = png;
        markdown(out, s)
    }

    fn charts(out: &Seed001Result, dir: &std::path::Path, png: bool) -> anyhow::Result<()> {
        let _ = (out, dir, png);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_follows_the_seed_and_quick_stays_small() {
        let full = plan(&BenchConfig::new(false));
        assert_eq!(full.len(), 2);
        assert!(full.iter().all(|(_, l)| l == &[8, 9, 10]));
        assert_eq!(plan(&BenchConfig::new(true)), vec![("bunny".to_string(), vec![6])]);
        assert_eq!(error_figures(vec![3.0, 1.0, 2.0]), [2.0, 3.0, 3.0]);
        let c = [cost("linear", 3.0, 10, 50, 10), cost("coherent", 2.0, 10, 20, 10)];
        assert_eq!(coherent_speedup(&c), Some(1.5));
        assert_eq!(c[0].probes_per_lookup, 5.0);
    }
}
