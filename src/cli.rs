//! Command-line grammar (clap). Raw arguments only; validation happens in `commands/`.

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, Parser, Subcommand};
use dynray_accel::{AccelSpec, SceneLayout, UpdatePolicy};
use dynray_bench::{BenchConfig, Framing, Preset, RayKind};
use dynray_engine::hit_file::HitField;
use dynray_engine::jobs::shard::Shard;
use dynray_engine::{BackendChoice, RenderJob, TimeChoice};
use dynray_gpu::{Backend, GpuBuild, GpuOptions, GpuStrategy};
use dynray_render::{Aov, IntegratorKind};
use std::ops::Range;
use std::path::PathBuf;

/// Ray tracing of dynamic scenes with GPU-friendly acceleration structures.
#[derive(Parser, Debug)]
#[command(name = "dynray", version, about, propagate_version = true)]
pub struct Cli {
    /// Worker threads, at least 1 (default: all cores).
    #[arg(long, global = true, value_name = "N", value_parser = threads_parser())]
    pub threads: Option<usize>,
    /// Let models (glTF, OBJ/MTL, Mitsuba, AFF) read files outside their own folder tree
    /// (also DYNRAY_ALLOW_OUTSIDE_REFERENCES=1; docs/limits.md).
    #[arg(long, global = true)]
    pub allow_outside_references: bool,
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene (.scn, Mitsuba .xml) or a mesh file (.obj, .ply, .ply.gz, .gltf, .glb,
    /// .npz) to an image.
    Render(RenderArgs),
    /// Trace a batch of rays from a .npy file and write the hits to a .npz file.
    TraceRays(TraceRaysArgs),
    /// Join the archives of `trace-rays --rows A..B` into the archive one run over every
    /// row writes (docs/trace-rays.md, "Slices").
    MergeHits(MergeHitsArgs),
    /// Print a file's counts and bounding box and an acceleration structure's figures.
    Info(InfoArgs),
    /// Render the frames of an animated scene (.scn, .gltf/.glb, .aff) to numbered PNGs,
    /// with per-frame timings and a preview.
    Animate(AnimateArgs),
    /// Measure acceleration structures on test models: build, memory, Mrays/s, work per
    /// ray, time to image, heat maps; every structure checked against brute force.
    Bench(BenchArgs),
    /// Adaptively sampled distance fields (docs/adf.md): `adf build` makes a .adf file
    /// from a mesh, which `render` and `info` then read.
    Adf(AdfArgs),
    /// Ray trace a scene live in a window (docs/view.md): orbit, pan, zoom and fly; play
    /// its animation; switch structure, integrator and backend; heat map and boxes.
    View(ViewArgs),
}

/// `dynray view`.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// Scene or mesh file; without it, the built-in demo scene.
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub image: ImageArgs,
    /// How the structures follow an animated scene: `auto` (refit until the SAH cost
    /// grows by 30 %, then rebuild), `refit`, `rebuild`, or `auto:RATIO`.
    #[arg(long, default_value = "auto", value_parser = |s: &str| s.parse::<UpdatePolicy>())]
    pub update: UpdatePolicy,
    /// Start playing the animation (real time, looping).
    #[arg(long)]
    pub play: bool,
    /// The starting view: `image`, `heatmap` (nodes + triangles per primary ray) or
    /// `boxes[:DEPTH]` (the structure's boxes or cells over the image; depth 3 by default).
    #[arg(long, value_name = "VIEW", value_parser = |s: &str| s.parse::<dynray_view::Show>())]
    #[cfg(feature = "view")]
    pub show: Option<dynray_view::Show>,
    /// Input events, one per line: `wait N` (frames), `key NAME`, `drag X0 Y0 X1 Y1`
    /// (left button, window pixels), `scroll N`; `#` comments (docs/view.md).
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,
    /// Close the window after this many frames.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub exit_after: Option<u64>,
    /// Write the window's content (overlays included unless --no-overlay) to this PNG
    /// when it closes.
    #[arg(long, value_name = "FILE.png")]
    pub screenshot: Option<PathBuf>,
    /// Show the image alone: no panel or statistics.
    #[arg(long)]
    pub no_overlay: bool,
    /// Write one CSV row per frame (pose, physics, update, trace, view, present; rays)
    /// when the window closes.
    #[arg(long, value_name = "FILE.csv")]
    pub timings: Option<PathBuf>,
    /// Record every frame the window shows (overlays included unless --no-overlay), with
    /// its real duration, into this animated GIF when it closes (600 frames at most).
    #[arg(long, value_name = "FILE.gif")]
    pub record: Option<PathBuf>,
    /// Render at this fixed fraction (0 to 1] of the image size, instead of scaling down
    /// automatically while the view moves.
    #[arg(long, value_name = "S")]
    pub scale: Option<f32>,
}

/// `dynray adf`.
#[derive(Args, Debug)]
pub struct AdfArgs {
    #[command(subcommand)]
    pub command: AdfCommand,
}

/// `dynray adf` subcommands.
#[derive(Subcommand, Debug)]
pub enum AdfCommand {
    /// Build the distance field of a mesh (or of a scene's triangles) into a .adf file.
    Build(AdfBuildArgs),
}

/// `dynray adf build`.
#[derive(Args, Debug)]
pub struct AdfBuildArgs {
    /// Mesh or scene file (.ply, .obj, .gltf, .scn, ...).
    pub mesh: PathBuf,
    /// The .adf file to write (written to a temporary name, then renamed).
    #[arg(short, long, value_name = "FILE.adf")]
    pub output: PathBuf,
    /// Deepest octree level, 1 to 16 (cells near the surface reach it; past 10, H has
    /// a second identifier word per slot).
    #[arg(long, value_name = "L", default_value_t = 8)]
    pub max_level: u32,
    /// Subdivision tolerance, as a fraction of the field's cube edge.
    #[arg(long, value_name = "E", default_value_t = 1e-3)]
    pub epsilon: f32,
}

/// Where rays are traced (docs/gpu.md).
#[derive(Args, Debug, Default, Clone)]
pub struct BackendArgs {
    /// Trace on the CPU or on the GPU (docs/gpu.md; the GPU traverses the binary BVH, `bvh2`; plain `bvh` means `bvh2` there).
    #[arg(long, default_value = "cpu", value_parser = PossibleValuesParser::new(Backend::NAMES).map(|s| s.parse::<Backend>().expect("listed names parse")))]
    pub backend: Backend,
    /// GPU adapter: a case-insensitive substring of its name (default: $DYNRAY_GPU_ADAPTER,
    /// else the most capable; `dynray info --gpu` lists them).
    #[arg(long, value_name = "NAME")]
    pub gpu_adapter: Option<String>,
    /// Where the GPU's BVH is built: `cpu` (then uploaded), `sah` (seed 003's binned SAH on
    /// the device, level by level) or `lbvh` (Morton codes and Karras' hierarchy on the
    /// device). Needs --backend gpu.
    #[arg(long, default_value = "cpu", value_parser = PossibleValuesParser::new(GpuBuild::ALL.map(GpuBuild::name)).map(|s| s.parse::<GpuBuild>().expect("listed names parse")))]
    pub gpu_build: GpuBuild,
}

impl BackendArgs {
    /// The engine's backend choice (checked by the job it goes into).
    pub fn choice(&self) -> BackendChoice {
        BackendChoice { gpu: self.gpu_options(), gpu_build: self.gpu_build }
    }

    /// The GPU's options when `--backend gpu`, `None` for the CPU.
    pub fn gpu_options(&self) -> Option<GpuOptions> {
        (self.backend == Backend::Gpu).then(|| GpuOptions { adapter: self.gpu_adapter.clone(), ..Default::default() })
    }
}

/// Which instant of an animated scene a command looks at (docs/animate.md, "Time").
#[derive(Args, Debug, Default, Clone)]
pub struct TimeArgs {
    /// Time in seconds on the scene's own axis (default: the time of frame 0).
    #[arg(long, value_name = "T", conflicts_with = "frame", allow_negative_numbers = true)]
    pub time: Option<f32>,
    /// Frame number: its time is the timeline's start + K / frame rate.
    #[arg(long, value_name = "K")]
    pub frame: Option<u32>,
    /// Animation clip to play, by name, for files with several (default: the first).
    #[arg(long, value_name = "NAME")]
    pub clip: Option<String>,
    /// Frame rate of the timeline, replacing the file's (glTF: 24 unless given).
    #[arg(long, value_name = "R")]
    pub fps: Option<f32>,
}

impl TimeArgs {
    /// The engine's choice of instant.
    pub fn choice(&self) -> TimeChoice {
        TimeChoice { time: self.time, frame: self.frame, clip: self.clip.clone(), fps: self.fps }
    }
}

/// `dynray render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene, mesh or distance-field (.adf) file; without it, the built-in demo scene is
    /// rendered.
    pub scene: Option<PathBuf>,
    /// Output image: .png, .bmp or .exr.
    #[arg(short, long, default_value = "dynray.png")]
    pub output: PathBuf,
    /// Cumulative integrator: sample passes of --spp samples per pixel each, accumulated
    /// into the image (progressive refinement; passes × spp samples in all). Default 1.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=MAX_SPP as i64))]
    pub passes: Option<u32>,
    /// Write one channel of the pixel-centre rays instead of colour, as float EXR:
    /// depth (t, +inf on a miss), normal (shading normal), prim (triangle index, -1 on a
    /// miss) or albedo (diffuse colour).
    #[arg(long, value_parser = PossibleValuesParser::new(Aov::NAMES)
        .map(|s| s.parse::<Aov>().expect("listed names parse")))]
    pub aov: Option<Aov>,
    #[command(flatten)]
    pub image: ImageArgs,
}

/// What an image is made of, shared by `render` and `view`: size, structure, integrator,
/// samples, instant, camera and backend.
#[derive(Args, Debug, Clone)]
pub struct ImageArgs {
    /// Image width in pixels (overrides the scene's settings).
    #[arg(long, value_parser = edge_parser())]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene's settings).
    #[arg(long, value_parser = edge_parser())]
    pub height: Option<u32>,
    /// Whitted and cumulative: maximum ray level, 1 = primary rays only (overrides
    /// `max_recursion_level`). Path: longest path in segments as Mitsuba counts them,
    /// 2 = direct light only (overrides the file's `max_depth`).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub max_depth: Option<u32>,
    /// Secondary rays at or below this weight (0 to 1) are not traced (overrides `min_weight`).
    #[arg(long)]
    pub min_weight: Option<f32>,
    /// Acceleration structure: `NAME[:key=value,…]` or `NAME:PRESET` (docs/bench.md,
    /// "Structure parameters").
    #[arg(long, default_value = "bvh", value_parser = parse_accel)]
    pub accel: AccelSpec,
    /// How an animated scene's actors are spread over structures (as `animate`'s option,
    /// so `render --frame K` draws what `animate` draws for frame K).
    #[arg(long, default_value = "instanced", value_parser = PossibleValuesParser::new(SceneLayout::NAMES)
        .map(|s| s.parse::<SceneLayout>().expect("listed names parse")))]
    pub scene_accel: SceneLayout,
    /// How pixel samples are computed.
    #[arg(long, default_value = "whitted", value_parser = PossibleValuesParser::new(IntegratorKind::NAMES)
        .map(|s| s.parse::<IntegratorKind>().expect("listed names parse")))]
    pub integrator: IntegratorKind,
    /// Samples per pixel, stratified over the pixel and averaged (anti-aliasing); 1 traces
    /// one ray through each pixel centre, as the seeds' measurements do. Default: the
    /// file's (a Mitsuba sampler's `sample_count`), else 9.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_SPP as i64))]
    pub spp: Option<u32>,
    /// Cumulative integrator: bounces whose reflection/refraction pairs are all expanded
    /// before paths choose one child by Fresnel (docs/rendering.md, "Cumulative");
    /// max_recursion_level - 1 or more expands everything (Whitted's image). Default 2.
    #[arg(long, value_name = "K")]
    pub branch_depth: Option<u32>,
    /// Seed of the sample positions and of every random choice an integrator makes.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Shade every surface with its triangles' geometric normals: no vertex normals,
    /// neither generated nor from files (to compare with the default smooth shading).
    #[arg(long)]
    pub flat_shading: bool,
    #[command(flatten)]
    pub when: TimeArgs,
    #[command(flatten)]
    pub backend: BackendArgs,
    /// With `--backend gpu`: seed 003's tracing strategy (docs/gpu.md, "Tracing strategies").
    #[arg(long, default_value = "wavefront", value_parser = PossibleValuesParser::new(GpuStrategy::NAMES)
        .map(|s| s.parse::<GpuStrategy>().expect("listed names parse")))]
    pub gpu_strategy: GpuStrategy,
    /// The camera, replacing the scene's: the inside of a scene-language `camera { … }`
    /// statement, e.g. `perspective position <0, 2, 7> to <0, 0.7, 0> up <0, 1, 0> angle 40`
    /// (`dynray view` shows the current one in this form).
    #[arg(long, value_name = "CAMERA", value_parser = |s: &str| dynray_engine::parse_camera(s).map_err(|e| e.to_string()))]
    pub camera: Option<dynray_scene::Camera>,
}

impl ImageArgs {
    /// The engine's render job of these options (no output, AOV or passes).
    pub fn job(&self) -> RenderJob {
        RenderJob {
            output: None,
            width: self.width,
            height: self.height,
            max_depth: self.max_depth,
            min_weight: self.min_weight,
            accel: self.accel.clone(),
            scene_accel: self.scene_accel,
            integrator: self.integrator,
            spp: self.spp,
            branch_depth: self.branch_depth,
            passes: None,
            seed: self.seed,
            flat_shading: self.flat_shading,
            aov: None,
            when: self.when.choice(),
            camera: self.camera,
            backend: self.backend.choice(),
            gpu_strategy: self.gpu_strategy,
        }
    }
}

/// Default samples per pixel of `render` (the engine's): enough for clean silhouettes
/// and checker edges on the demo (a 3×3-stratified pattern), at 9× the one-ray cost.
pub const DEFAULT_SPP: u32 = dynray_engine::jobs::render::DEFAULT_SPP;

/// Most samples per pixel accepted, so a typo cannot start a week-long render.
pub const MAX_SPP: u32 = dynray_engine::jobs::render::MAX_SPP;

/// `dynray trace-rays`.
#[derive(Args, Debug)]
pub struct TraceRaysArgs {
    /// Mesh file (.obj, .ply, .ply.gz, .gltf, .glb, or .npz with numpy `vertices` and
    /// `faces`) or scene file (.scn).
    pub mesh: PathBuf,
    /// Rays: .npy of shape (N, 8): origin xyz, direction xyz, tmin, tmax (float32, or
    /// float64 / Fortran order, converted).
    #[arg(long, value_name = "RAYS.npy")]
    pub rays: PathBuf,
    /// Output .npz with `t`, `prim`, `u`, `v` (or `occluded` with --occluded).
    #[arg(short, long, value_name = "HITS.npz")]
    pub output: PathBuf,
    /// Acceleration structure: `NAME[:key=value,…]` or `NAME:PRESET` (docs/bench.md,
    /// "Structure parameters").
    #[arg(long, default_value = "bvh", value_parser = parse_accel)]
    pub accel: AccelSpec,
    /// Any-hit queries: write one boolean `occluded` per ray instead of closest hits.
    #[arg(long, conflicts_with = "fields")]
    pub occluded: bool,
    /// Arrays of the closest hits to write: `normal` (unit geometric normal) and `point`
    /// (hit point) are (N, 3), NaN on a miss.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "t,prim,u,v",
        value_parser = PossibleValuesParser::new(HitField::NAMES).map(|s| s.parse::<HitField>().expect("listed names parse")))]
    pub fields: Vec<HitField>,
    /// Trace only rows A..B of the ray file, B exclusive (as Python's `rays[A:B]`),
    /// reading no other row; the archive adds `rows` = [A, B, N] for `merge-hits`.
    #[arg(long, value_name = "A..B", value_parser = parse_row_range)]
    pub rows: Option<Range<u64>>,
    #[command(flatten)]
    pub when: TimeArgs,
    #[command(flatten)]
    pub backend: BackendArgs,
}

/// `A..B` with `A <= B`, B exclusive: the rows of `trace-rays --rows`.
fn parse_row_range(s: &str) -> Result<Range<u64>, String> {
    let bad = || format!("`{s}`: expected A..B with row numbers A <= B, B exclusive (0..1000 is rows 0 to 999)");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    if b.starts_with('=') {
        return Err(format!("`{s}`: rows are half-open, A..B with B exclusive; write {a}..B+1"));
    }
    let (a, b) = (a.trim().parse::<u64>().map_err(|_| bad())?, b.trim().parse::<u64>().map_err(|_| bad())?);
    if a > b {
        return Err(format!("`{s}`: the first row {a} is after the end {b}"));
    }
    Ok(a..b)
}

/// `dynray merge-hits`.
#[derive(Args, Debug)]
pub struct MergeHitsArgs {
    /// The slice archives of `trace-rays --rows A..B`, in any order: together they must
    /// cover every row of one ray file once, with one query.
    #[arg(required = true, value_name = "PART.npz")]
    pub parts: Vec<PathBuf>,
    /// The merged archive: what one `trace-rays` over every row writes (not a part).
    #[arg(short, long, value_name = "HITS.npz")]
    pub output: PathBuf,
}

/// `dynray animate` (docs/animate.md).
#[derive(Args, Debug)]
pub struct AnimateArgs {
    /// Scene or mesh file (a still one renders the same image every frame).
    pub scene: PathBuf,
    /// Frames to render, `A..B` inclusive or one frame `K` (default: all of the timeline).
    #[arg(long, value_name = "A..B", value_parser = parse_frame_range)]
    pub frames: Option<(u32, u32)>,
    /// Frame rate, replacing the file's (glTF: 24 unless given).
    #[arg(long, value_name = "R")]
    pub fps: Option<f32>,
    /// Animation clip to play, by name (default: the first).
    #[arg(long, value_name = "NAME")]
    pub clip: Option<String>,
    /// Output folder: frame_NNNN.png, timings.csv, preview.gif (mesh_NNNN.obj).
    #[arg(long, default_value = "frames")]
    pub out: PathBuf,
    /// Acceleration structure: `NAME[:key=value,…]` or `NAME:PRESET`.
    #[arg(long, default_value = "bvh", value_parser = parse_accel)]
    pub accel: AccelSpec,
    /// How the structure follows the geometry: rebuild, refit, auto or auto:RATIO
    /// (refit until the SAH cost exceeds RATIO × a fresh build's; default 1.3).
    #[arg(long, default_value = "auto", value_parser = |s: &str| s.parse::<UpdatePolicy>())]
    pub update: UpdatePolicy,
    /// How an animated scene's actors are spread over structures: `instanced` (static
    /// actors built once, deforming ones refit or rebuilt, rigid ones as instances under
    /// a top-level BVH), `split` (the same, rigid actors held like deforming ones), or
    /// `flat` (one structure over the frame). docs/animate.md, "Scene layouts".
    #[arg(long, default_value = "instanced", value_parser = PossibleValuesParser::new(SceneLayout::NAMES)
        .map(|s| s.parse::<SceneLayout>().expect("listed names parse")))]
    pub scene_accel: SceneLayout,
    /// Image width in pixels (overrides the scene's settings).
    #[arg(long, value_parser = edge_parser())]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene's settings).
    #[arg(long, value_parser = edge_parser())]
    pub height: Option<u32>,
    /// Samples per pixel.
    #[arg(long, default_value_t = DEFAULT_SPP, value_parser = clap::value_parser!(u32).range(1..=MAX_SPP as i64))]
    pub spp: u32,
    /// How pixel samples are computed.
    #[arg(long, default_value = "whitted", value_parser = PossibleValuesParser::new(IntegratorKind::NAMES)
        .map(|s| s.parse::<IntegratorKind>().expect("listed names parse")))]
    pub integrator: IntegratorKind,
    /// Seed of the sample positions (the same for every frame).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Render one task's part of the frames, 0 <= K < N: `K/N` the frames whose number is
    /// K modulo N, `K/N:blocks` the K-th of N contiguous ranges (with physics, each starts
    /// from the nearest checkpoint). The tasks' frames together are a full run's, byte for
    /// byte (docs/animate.md, "Shards and resumption").
    #[arg(long, value_name = "K/N[:blocks]", value_parser = |s: &str| s.parse::<Shard>())]
    pub shard: Option<Shard>,
    /// Skip frames whose PNG is already in the output folder (frames are written whole).
    #[arg(long)]
    pub resume: bool,
    /// With physics, save the simulation's state every K frames to OUT/checkpoints/
    /// (0: never); runs continue from the latest checkpoint instead of time 0.
    #[arg(long, value_name = "K", default_value_t = 1)]
    pub checkpoint_every: u32,
    /// With physics, wait up to SECS for each frame's checkpoint from a
    /// `--checkpoints-only` job running alongside, instead of simulating to it (after a
    /// wait times out the run simulates on its own).
    #[arg(long, value_name = "SECS", value_parser = parse_seconds)]
    pub await_checkpoints: Option<std::time::Duration>,
    /// Simulate the physics and write checkpoints without rendering: the first job of a
    /// chain whose `--shard K/N:blocks` tasks then render in parallel.
    #[arg(long, conflicts_with = "merge")]
    pub checkpoints_only: bool,
    /// After an array job: check that every frame is there, join the tasks' timings
    /// into timings.csv and write preview.gif; renders nothing.
    #[arg(long, conflicts_with = "shard")]
    pub merge: bool,
    /// Also write each frame's world-space triangles as mesh_NNNN.obj.
    #[arg(long)]
    pub export_meshes: bool,
    /// Shade every surface with its geometric normals (as render --flat-shading).
    #[arg(long)]
    pub flat_shading: bool,
    /// With `--backend gpu`: the frames traced and shaded on the GPU, the BVH kept there
    /// (docs/animate.md, "On the GPU").
    #[command(flatten)]
    pub backend: BackendArgs,
    /// With `--backend gpu`: seed 003's tracing strategy (docs/gpu.md, "Tracing strategies").
    #[arg(long, default_value = "wavefront", value_parser = PossibleValuesParser::new(GpuStrategy::NAMES)
        .map(|s| s.parse::<GpuStrategy>().expect("listed names parse")))]
    pub gpu_strategy: GpuStrategy,
}

/// A non-negative, finite number of seconds.
fn parse_seconds(s: &str) -> Result<std::time::Duration, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .and_then(|x| std::time::Duration::try_from_secs_f64(x).ok())
        .ok_or_else(|| format!("`{s}`: expected a number of seconds, as in 600"))
}

/// `A..B` (inclusive) or `K`.
fn parse_frame_range(s: &str) -> Result<(u32, u32), String> {
    let num = |t: &str| {
        t.trim().parse::<u32>().map_err(|_| format!("`{s}`: expected A..B or K with frame numbers (0, 1, 2, …)"))
    };
    let (a, b) = match s.split_once("..") {
        Some((a, b)) => (num(a)?, num(b.strip_prefix('=').unwrap_or(b))?),
        None => {
            let k = num(s)?;
            (k, k)
        }
    };
    if a > b {
        return Err(format!("`{s}`: the first frame is after the last"));
    }
    Ok((a, b))
}

/// `dynray info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Scene, mesh or distance-field (.adf) file.
    #[arg(required_unless_present_any = ["gpu", "structures"])]
    pub file: Option<PathBuf>,
    /// List every structure `--accel` names: what it is, its presets, whether its update
    /// refits and whether the GPU traces it.
    #[arg(long)]
    pub structures: bool,
    /// List the GPU adapters (name, driver, the features and limits the kernels use) and
    /// check the chosen one against the CPU; exits 1 when there is none.
    #[arg(long)]
    pub gpu: bool,
    /// GPU adapter to check with --gpu (default: $DYNRAY_GPU_ADAPTER, else the most capable).
    #[arg(long, value_name = "NAME", requires = "gpu")]
    pub gpu_adapter: Option<String>,
    /// Structure to build and describe: `NAME[:key=value,…]` or `NAME:PRESET`.
    #[arg(long, default_value = "bvh", value_parser = parse_accel)]
    pub accel: AccelSpec,
}

/// `dynray bench` (docs/bench.md). Threads come from the global `--threads`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Comma-separated scene names or mesh/scene files.
    #[arg(long, value_name = "LIST", help = scenes_help())]
    pub scenes: Option<String>,
    /// Comma-separated structures, each optionally with parameters:
    /// `bvh,bih:max_prims=5,shrink=off` (default: every registered structure but brute).
    #[arg(long, value_name = "LIST", value_parser = accels_parser)]
    pub accels: Option<String>,
    /// Comma-separated ray kinds (default: every kind).
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = ray_kind_parser())]
    pub rays: Option<Vec<RayKind>>,
    /// Image width of the ray sets and renders.
    #[arg(long, value_parser = edge_parser(), help = defaults_help("Image width of the ray sets and renders", |c| c.width))]
    pub width: Option<u32>,
    /// Image height.
    #[arg(long, value_parser = edge_parser(), help = defaults_help("Image height", |c| c.height))]
    pub height: Option<u32>,
    /// The standard run's camera: the scene's own, or moved to fill the image with the
    /// model (docs/bench.md, "Side by side").
    #[arg(long, value_parser = framing_parser(), help = defaults_help("The standard run's camera: `scene` (the scene's own) or `tight` (the same view moved to fill the image with the model)", |c| c.framing.name()))]
    pub framing: Option<Framing>,
    /// Timed repetitions after one warm-up; medians are reported.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..).map(|n| n as usize),
        help = defaults_help("Timed repetitions after one warm-up; medians are reported", |c| c.repeat))]
    pub repeat: Option<usize>,
    /// Which experiment to run (default: standard); `all` runs every one.
    #[arg(long, value_name = "NAME", value_parser = preset_parser())]
    pub preset: Option<String>,
    /// Output folder.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Small models and images, one repetition, every ray checked: well under a minute.
    #[arg(long)]
    pub quick: bool,
    /// Folder of the named models (default: $DYNRAY_SCENES, ../shared/scenes, or
    /// shared/scenes beside the executable's checkout).
    #[arg(long, value_name = "DIR")]
    pub scenes_dir: Option<PathBuf>,
    /// Rays per kind checked against brute force, or `all` (default 2000; --quick all).
    #[arg(long, value_name = "N|all")]
    pub verify: Option<String>,
    /// Frames of the dynamic preset (default 60; --quick 4).
    #[arg(long)]
    pub frames: Option<usize>,
    /// Write charts as SVG only, and no heat maps.
    #[arg(long)]
    pub no_png: bool,
    /// With `--backend gpu`: the GPU backend measured beside the CPU on the standard
    /// run's rays, and seed003's GPU tables (docs/bench.md, "On the GPU").
    #[command(flatten)]
    pub backend: BackendArgs,
    /// Measure nothing: draw the charts and write report.md again from DIR/report.json
    /// (after a change of layout; heat maps are kept).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["scenes", "accels", "rays", "preset", "quick"])]
    pub replot: Option<PathBuf>,
}

/// `--rays` values, listed from the bench's own registry of ray kinds.
fn ray_kind_parser() -> impl TypedValueParser<Value = RayKind> {
    PossibleValuesParser::new(RayKind::ALL.map(RayKind::name))
        .map(|s| s.parse::<RayKind>().expect("listed names parse"))
}

/// `--framing` values, listed from the bench's own names.
fn framing_parser() -> impl TypedValueParser<Value = Framing> {
    PossibleValuesParser::new(Framing::ALL.map(Framing::name))
        .map(|s| s.parse::<Framing>().expect("listed names parse"))
}

/// `--preset` values: every preset the bench has, and `all`.
fn preset_parser() -> PossibleValuesParser {
    PossibleValuesParser::new(Preset::ALL.iter().map(|p| p.name()).chain(["all"]))
}

/// `--accel NAME[:key=value,…]`, keys and values checked at parse time (clap then exits
/// with status 2 and names the flag).
/// Image edges accepted on the command line: 1 to the renderer's limit (a usage error,
/// status 2, outside it).
fn edge_parser() -> impl TypedValueParser<Value = u32> {
    clap::value_parser!(u32).range(1..=dynray_render::MAX_IMAGE_EDGE as i64)
}

/// `--scenes` help listing the bench's named models, so it follows the registry.
fn scenes_help() -> String {
    let names: Vec<&str> =
        dynray_bench::scenes::KNOWN_SCENES.iter().map(|(n, _)| *n).chain([dynray_bench::scenes::DEMO]).collect();
    format!("Comma-separated scene names ({}) or mesh/scene files", names.join(", "))
}

/// A bench option's help with its defaults read from `BenchConfig`, for a full and a
/// `--quick` run, so the text cannot drift from what runs.
fn defaults_help<T: std::fmt::Display>(what: &str, field: fn(&BenchConfig) -> T) -> String {
    format!("{what} (default {}; --quick {})", field(&BenchConfig::new(false)), field(&BenchConfig::new(true)))
}

/// `--accels`, checked when parsed (an unknown structure or key is a usage error) and
/// kept as text: the bench parses it again into its variants.
fn accels_parser(s: &str) -> Result<String, String> {
    dynray_bench::parse_accels(s).map(|_| s.to_string()).map_err(|e| format!("{e:#}"))
}

fn parse_accel(s: &str) -> Result<AccelSpec, String> {
    s.parse().map_err(|e: dynray_accel::BuildError| e.to_string())
}

/// `--threads`: a count of at least 1, so 0 is a usage error (exit 2) like every other
/// malformed flag.
fn threads_parser() -> impl clap::builder::TypedValueParser<Value = usize> {
    clap::value_parser!(u64).range(1..=4096).map(|n| n as usize)
}
