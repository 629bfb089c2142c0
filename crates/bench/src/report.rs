//! Everything a bench run measured, as written to `report.json` (schema in docs/bench.md).

use serde::{Deserialize, Serialize};

/// Version of the JSON layout; bumped when a field changes meaning or disappears.
pub const SCHEMA_VERSION: u32 = 1;

/// A whole run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Report {
    /// [`SCHEMA_VERSION`].
    pub schema: u32,
    /// `dynray` version.
    pub dynray_version: String,
    /// Git commit of the source, if known.
    pub commit: Option<String>,
    /// Where it ran.
    pub machine: Machine,
    /// Worker threads of the parallel passes.
    pub threads: usize,
    /// Start, ISO 8601 UTC.
    pub started_utc: String,
    /// End, ISO 8601 UTC.
    pub finished_utc: String,
    /// The settings of the run.
    pub config: ConfigEcho,
    /// Standard measurements: one entry per scene (empty when only presets ran).
    pub scenes: Vec<SceneResult>,
    /// `--preset seed000` results (BIH leaf-size sweep against the kd-trees).
    pub seed000: Option<StudyResult>,
    /// `--preset seed000`'s dynamic scenario (an elastic bunny dropped; structures rebuilt
    /// or refitted per frame). (Absent from reports written before it existed.)
    #[serde(default)]
    pub seed000_physics: Option<Seed000Physics>,
    /// `--preset seed001` results (distance fields). (Absent from reports written before
    /// it existed.)
    #[serde(default)]
    pub seed001: Option<Seed001Result>,
    /// `--preset seed002` results (octree walks against the BVH).
    pub seed002: Option<StudyResult>,
    /// `--preset seed003` results.
    pub seed003: Option<Seed003Result>,
    /// `--preset seed004` results (A-PIT against the plain A-buffer by resolution).
    pub seed004: Option<StudyResult>,
    /// `--preset seed004`'s renderer comparison (cumulative against recursive Whitted
    /// over the A-PIT, the A-buffer and the BVH). (Absent from reports written before it
    /// existed.)
    #[serde(default)]
    pub seed004_renderers: Option<Seed004Renderers>,
    /// `--preset dynamic` results.
    pub dynamic: Option<DynamicResult>,
    /// `--preset path` results (the path tracer against Mitsuba 3's references). (Absent
    /// from reports written before it existed.)
    #[serde(default)]
    pub path: Option<PathResult>,
    /// `--backend gpu`: the adapter the GPU figures were measured on. (Absent from
    /// reports written before it existed.)
    #[serde(default)]
    pub gpu: Option<GpuInfo>,
    /// Every disagreement with brute force (the run fails when this is not empty).
    pub mismatches: Vec<Mismatch>,
    /// Remarks a reader needs (reduced resolution, skipped parts).
    pub notes: Vec<String>,
}

impl Report {
    /// Scene measurements in the run, over the standard run and every preset.
    pub fn scene_runs(&self) -> usize {
        let studies = [&self.seed000, &self.seed002, &self.seed004];
        self.scenes.len()
            + studies.iter().filter_map(|s| s.as_ref()).map(|s| s.scenes.len()).sum::<usize>()
            + self.seed003.as_ref().map_or(0, |s| s.scenes.len())
            + self.dynamic.as_ref().map_or(0, |d| d.runs.len())
            + self.seed001.as_ref().map_or(0, |s| s.runs.len())
    }
}

/// The adapter of a `--backend gpu` run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GpuInfo {
    /// Device name.
    pub adapter: String,
    /// Graphics API (Vulkan).
    pub backend: String,
    /// Discrete, integrated, virtual or CPU (software).
    pub device_type: String,
    /// Driver name and version.
    pub driver: String,
    /// `f64` (hits equal brute force's bit for bit) or `f32` (docs/gpu.md's rule).
    pub precision: String,
    /// True for a software device (lavapipe): a CPU emulating a GPU, whose figures rank
    /// the strategies but are no GPU's speed.
    pub software: bool,
    /// Where the standard run's device tree was built: `cpu` (built there, uploaded),
    /// `sah` or `lbvh`.
    pub build: String,
    /// Per-stage GPU times come from timestamp queries (false: wall clock per stage).
    pub timestamps: bool,
}

/// The machine.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Machine {
    /// CPU model from /proc/cpuinfo (or "unknown").
    pub cpu: String,
    /// Logical cores the OS reports.
    pub logical_cores: usize,
    /// `std::env::consts::OS` / `ARCH`.
    pub os: String,
}

/// The run's settings, as used.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ConfigEcho {
    /// Image width of the ray sets and renders.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Timed repetitions (medians are reported), after one warm-up.
    pub repeat: usize,
    /// Ray kinds measured.
    pub rays: Vec<String>,
    /// Structures measured, as `--accels` spells them.
    pub accels: Vec<String>,
    /// Rays per kind checked against brute force (`null`: all).
    pub verify_sample: Option<usize>,
    /// `--quick`.
    pub quick: bool,
    /// The preset(s) run.
    pub presets: Vec<String>,
    /// The standard run's camera: `scene` or `tight` (`--framing`; reports written
    /// before it existed read as `scene`).
    #[serde(default = "scene_framing")]
    pub framing: String,
}

fn scene_framing() -> String {
    crate::framing::Framing::Scene.name().to_string()
}

/// One scene of the standard measurements.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SceneResult {
    /// Scene name.
    pub name: String,
    /// File read.
    pub path: String,
    /// Triangles.
    pub triangles: usize,
    /// Vertices.
    pub vertices: usize,
    /// Rays per kind.
    pub ray_counts: Vec<KindCount>,
    /// One entry per structure.
    pub structures: Vec<StructureResult>,
    /// Other libraries on the same rays (feature `compare`; empty without it).
    pub competitors: Vec<CompetitorResult>,
    /// `--backend gpu`: the GPU backend on the same rays, one entry per structure it
    /// traces (`bvh`), measured as the CPU's and checked against the same brute force.
    /// (Absent from reports written before it existed.)
    #[serde(default)]
    pub gpu: Vec<StructureResult>,
}

/// How many rays of a kind a scene has.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct KindCount {
    /// Ray kind.
    pub kind: String,
    /// Rays.
    pub rays: usize,
}

/// One structure on one scene.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StructureResult {
    /// `--accels` spelling (with parameters).
    pub accel: String,
    /// Median build time, ms.
    pub build_ms: f64,
    /// Every timed build, ms.
    pub build_ms_runs: Vec<f64>,
    /// Bytes owned by the structure.
    pub memory_bytes: usize,
    /// Nodes (or cells).
    pub nodes: usize,
    /// Leaves (or non-empty cells).
    pub leaves: usize,
    /// Deepest leaf.
    pub max_depth: u32,
    /// Triangle references in leaves.
    pub primitive_refs: usize,
    /// SAH cost, where the structure defines one.
    pub sah_cost: Option<f64>,
    /// Structure-specific figures.
    pub extra: Vec<(String, String)>,
    /// Per ray kind.
    pub kinds: Vec<KindResult>,
    /// The primary rays once more, through the structure's packet path
    /// (`Accel::intersect_coherent_into`: 8 consecutive rays of one origin traced
    /// together), timed right after the single-ray primary pass and checked against the
    /// same brute-force answers; `kind` is `primary-packet`, the work per ray is the
    /// single rays' (counted pass). `null` for structures without packets (and absent
    /// from reports written before it existed).
    #[serde(default)]
    pub primary_packets: Option<KindResult>,
    /// Whitted render of the frame at the bench size: build + render, median, ms (`null`
    /// when the preset does not measure it).
    pub time_to_image_ms: Option<f64>,
    /// The render part alone, median, ms (`null` as above).
    pub render_ms: Option<f64>,
    /// Rays the render traced (primary + shadow + secondary).
    pub render_rays: u64,
    /// Heat map file, relative to the output folder.
    pub heatmap: Option<String>,
}

/// One ray kind through one structure.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct KindResult {
    /// Ray kind.
    pub kind: String,
    /// Rays traced.
    pub rays: usize,
    /// Median time of the timed pass, ms.
    pub trace_ms: f64,
    /// Every timed pass, ms.
    pub trace_ms_runs: Vec<f64>,
    /// Million rays per second (rays / median time).
    pub mrays_per_s: f64,
    /// Mean nodes visited per ray (counted pass, closest-hit traversal).
    pub nodes_per_ray: f64,
    /// Mean triangles tested per ray (counted pass).
    pub triangles_per_ray: f64,
    /// Mean work of the rays that hit (counted pass); `null` when none did. (Absent from
    /// reports written before it existed.)
    #[serde(default)]
    pub hit_work: Option<Work>,
    /// Mean work of the rays that escaped, hitting nothing; `null` when none did.
    #[serde(default)]
    pub escaped_work: Option<Work>,
    /// Rays that hit (closest hit) or were occluded (shadow).
    pub hits: usize,
    /// Rays compared with brute force.
    pub verified: usize,
}

/// Mean traversal work per ray of a group of rays.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Work {
    /// Nodes (or cells, or fragments) visited per ray.
    pub nodes: f64,
    /// Triangles tested per ray.
    pub triangles: f64,
}

/// A disagreement with brute force.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Mismatch {
    /// Where: scene (and frame for the dynamic preset).
    pub scene: String,
    /// Structure.
    pub accel: String,
    /// Ray kind.
    pub kind: String,
    /// Index of the ray in its set.
    pub ray_index: usize,
    /// Origin, direction, tmin, tmax.
    pub ray: [f32; 8],
    /// Brute force's answer (`prim t` or `occluded`).
    pub expected: String,
    /// The structure's answer.
    pub got: String,
}

/// A seed preset measured like the standard run (same fields per scene and structure) on
/// the preset's scenes and structure variants, with the ratios the seed reports.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StudyResult {
    /// Preset name (`seed000`, …).
    pub preset: String,
    /// Image width of the ray sets (and renders, when time to image is measured).
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Timed repetitions (medians reported).
    pub repeat: usize,
    /// Ray kinds measured.
    pub rays: Vec<String>,
    /// Per scene, as in the standard run.
    pub scenes: Vec<SceneResult>,
    /// The seed's comparisons, computed from `scenes`.
    pub ratios: Vec<Ratio>,
}

/// One comparison of two structures on one scene and metric.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Ratio {
    /// Scene.
    pub scene: String,
    /// `build_ms`, `trace_ms:KIND`, `time_to_image_ms` or `memory_bytes`.
    pub metric: String,
    /// The structure compared against (`--accels` spelling).
    pub baseline: String,
    /// The structure compared.
    pub candidate: String,
    /// The baseline's value (ms or bytes).
    pub baseline_value: f64,
    /// The candidate's value.
    pub candidate_value: f64,
    /// `baseline_value / candidate_value`: above 1 the candidate is faster (or smaller).
    pub speedup: f64,
}

/// Another library on one scene (feature `compare`, docs/bench.md "Side by side").
///
/// Every `ours_over_theirs_*` ratio reads "> 1: ours is better", against our structure
/// named in `ours` on the same scene in the same run: build and memory are
/// theirs / ours (their ms or bytes over ours), speed is ours / theirs (our Mrays/s over
/// theirs). `None` when our structure was not measured or the figure is unknown.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CompetitorResult {
    /// Library (`embree`, `obvhs`).
    pub name: String,
    /// Layout or API within the library.
    pub variant: String,
    /// What runs: API, layout, build settings.
    pub describe: String,
    /// Median build time, ms (from our mesh to a traceable structure).
    pub build_ms: f64,
    /// Every timed build, ms.
    pub build_ms_runs: Vec<f64>,
    /// Bytes the structure holds, where the library reports it or it can be computed.
    pub memory_bytes: Option<usize>,
    /// Our structure the ratios compare with (`bvh`), if it was measured.
    pub ours: Option<String>,
    /// Their build ms / our build ms (> 1: ours builds faster).
    pub ours_over_theirs_build: Option<f64>,
    /// Their bytes / our bytes (> 1: ours is smaller).
    pub ours_over_theirs_memory: Option<f64>,
    /// Per ray kind it was measured on.
    pub kinds: Vec<CompetitorKind>,
}

/// One ray kind through a competitor, and how its answers compare with brute force's.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CompetitorKind {
    /// Ray kind.
    pub kind: String,
    /// Rays traced.
    pub rays: usize,
    /// Shadow rays: true when timed with the library's own any-hit query (else its closest hit).
    pub any_hit: bool,
    /// Median time of the timed pass, ms.
    pub trace_ms: f64,
    /// Every timed pass, ms.
    pub trace_ms_runs: Vec<f64>,
    /// Million rays per second (rays / median time).
    pub mrays_per_s: f64,
    /// Rays that hit (closest hit) or were occluded (shadow).
    pub hits: usize,
    /// Sampled rays compared with brute force.
    pub checked: usize,
    /// Same triangle as brute force (a miss for a miss), or the same `occluded`.
    pub same_answer: usize,
    /// Both hit or both miss, whatever the triangle (shadow: = `same_answer`).
    pub same_hit_or_miss: usize,
    /// `same_answer / checked`.
    pub agreement: f64,
    /// Largest |t − t_brute| / |t_brute| over the rays with the same triangle.
    pub max_rel_t_diff: f64,
    /// Our Mrays/s / theirs (> 1: ours traces faster), ours being the entry
    /// [`CompetitorKind::ours_kind`] names.
    pub ours_over_theirs_speed: Option<f64>,
    /// Which of our figures the speed ratio compares with: the same kind (`primary`, …),
    /// or `primary-packet` (our [`StructureResult::primary_packets`]) for a packet
    /// variant where our structure has packets. `null` without a ratio (and absent from
    /// reports written before it existed).
    #[serde(default)]
    pub ours_kind: Option<String>,
}

/// `--preset seed003`: the Whitted tracer on one thread against the same tracer on every
/// thread (the seed's CPU-vs-GPU speed-up, SP, and efficiency, EF = SP / threads), and
/// single-threaded brute force on scenes small enough for it.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003Result {
    /// Image width used (the seed used 640).
    pub width: u32,
    /// Image height used (the seed used 480).
    pub height: u32,
    /// The accelerated structure.
    pub accel: String,
    /// Threads of the parallel tracer.
    pub threads: usize,
    /// Brute force runs only on scenes with at most this many triangles.
    pub brute_max_triangles: usize,
    /// One entry per scene.
    pub scenes: Vec<Seed003Scene>,
    /// Ray casting against the number of lights and the image size (the seed's Tables 4.3
    /// and 4.4); absent from reports written before it existed.
    #[serde(default)]
    pub sweeps: Option<Seed003Sweeps>,
    /// `--backend gpu`: the adapter of the GPU columns (`null` without it).
    #[serde(default)]
    pub gpu_adapter: Option<String>,
}

/// The seed003 preset's two ray-casting sweeps, on one scene.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003Sweeps {
    /// Scene name.
    pub scene: String,
    /// One point per light count, at the preset's image size.
    pub lights: Vec<Seed003Point>,
    /// One point per (square) image size.
    pub resolution: Vec<Seed003Point>,
}

/// One ray-casting render of a sweep, on 1 thread and on every thread (medians).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003Point {
    /// Lights in the scene.
    pub lights: usize,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Rays traced (primary + shadow).
    pub rays: u64,
    /// 1 thread, ms.
    pub single_ms: f64,
    /// Every thread, ms.
    pub parallel_ms: f64,
    /// `single_ms / parallel_ms`.
    pub speedup: f64,
    /// `speedup / threads`.
    pub efficiency: f64,
    /// The two images are identical pixel for pixel (they must be).
    pub images_identical: bool,
    /// `--backend gpu`: the three strategies on the same image (empty without it).
    #[serde(default)]
    pub gpu: Vec<Seed003GpuRun>,
}

/// One scene of the seed003 preset.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003Scene {
    /// Scene name.
    pub name: String,
    /// Triangles.
    pub triangles: usize,
    /// Lights.
    pub lights: usize,
    /// Build time of the structure, median, ms (the seed's Table 4.9 measures the CPU build).
    pub build_ms: f64,
    /// Rows by recursion level 1..=10 (level 1 = ray casting: primary + shadow rays, the
    /// seed's "0 nível" row of Table 4.8).
    pub levels: Vec<Seed003Level>,
    /// `--backend gpu`: the BVH built on 1 thread, median, ms (Table 4.9's CPU column).
    #[serde(default)]
    pub cpu_single_build_ms: Option<f64>,
    /// `--backend gpu`: the device's builds (Table 4.9; empty without it).
    #[serde(default)]
    pub gpu_builds: Vec<Seed003GpuBuild>,
}

/// One recursion level of the seed003 preset (renders with the structure prebuilt,
/// medians of `repeat`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003Level {
    /// Maximum ray level (1 = primary + shadow rays only).
    pub level: u32,
    /// Rays traced.
    pub rays: u64,
    /// The accelerated tracer on one thread, ms (the seed's CPU column).
    pub accel_single_ms: f64,
    /// The accelerated tracer on every thread, ms (the seed's GPU columns).
    pub accel_parallel_ms: f64,
    /// `accel_single_ms / accel_parallel_ms` (the seed's SP).
    pub speedup: f64,
    /// `speedup / threads` (the seed's EF).
    pub efficiency: f64,
    /// Brute force on one thread, ms (`null` above `brute_max_triangles`).
    pub brute_single_ms: Option<f64>,
    /// `brute_single_ms / accel_parallel_ms`: structure and threads together.
    pub brute_speedup: Option<f64>,
    /// True when every image of this level is identical pixel for pixel (they must be).
    pub images_identical: bool,
    /// `--backend gpu`: seed 003's three strategies at this level (empty without it).
    #[serde(default)]
    pub gpu: Vec<Seed003GpuRun>,
}

/// One GPU strategy rendering one seed003 image (medians of `repeat` after a warm-up).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003GpuRun {
    /// `wavefront` (the seed's Alg. 1), `megakernel` (Alg. 2) or `hybrid` (Alg. 3).
    pub strategy: String,
    /// Render time on the device, ms: the kernels and the read-back of the image, without
    /// the frame's upload (the seed times rendering with the tree already there).
    pub ms: f64,
    /// Rays traced (primary + shadow + secondary).
    pub rays: u64,
    /// The 1-thread CPU time over this one (the seed's SP = T_CPU / T_GPU).
    pub speedup: f64,
    /// Largest channel difference from the CPU's image of the same level.
    pub max_abs_diff: f64,
    /// Pixels whose largest channel difference from the CPU's image is over 1e-3.
    pub pixels_over_1e3: usize,
    /// True when at most 1 % of the pixels differ by over 1e-3 (f32 shading on both sides
    /// in another order; grazing rays may take another path): otherwise a mismatch.
    pub images_agree: bool,
}

/// One BVH build of seed003's Table 4.9 (median of `repeat` after a warm-up).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003GpuBuild {
    /// `cpu` (the CPU's binned SAH on every thread, then uploaded), `sah` (seed 003 §3.8
    /// on the device) or `lbvh`.
    pub build: String,
    /// Build time, ms (upload of the triangles included).
    pub ms: f64,
    /// The 1-thread CPU build's time over this one (the seed's "aceleração").
    pub cpu_over_this: f64,
    /// Nodes of the tree.
    pub nodes: usize,
    /// SAH cost of the tree (the CPU builder's cost model).
    pub sah_cost: Option<f64>,
    /// The last build's stages, ms.
    pub stages: Vec<(String, f64)>,
}

/// `--preset dynamic`: every vertex moves each frame.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DynamicResult {
    /// Frames per scene.
    pub frames: usize,
    /// Image width of the primary rays and renders.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// One entry per scene × structure.
    pub runs: Vec<DynamicRun>,
    /// Scene layouts and update policies on the animated scenes
    /// (`presets::dynamic_layouts`); empty in reports written before it.
    #[serde(default)]
    pub layouts: Vec<LayoutRun>,
}

/// One structure in one scene layout under one update policy, over an animated scene.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct LayoutRun {
    /// Scene name.
    pub scene: String,
    /// Triangles per frame.
    pub triangles: usize,
    /// Structure (of every part).
    pub accel: String,
    /// `flat` or `instanced` (`flat` also where the scene had nothing moving).
    pub layout: String,
    /// `rebuild`, `refit` or `auto`.
    pub policy: String,
    /// Bottom-level structures (1 when flat).
    pub parts: usize,
    /// Instances under the top level (1 when flat).
    pub instances: usize,
    /// Per frame: the update, ms.
    pub update_ms: Vec<f64>,
    /// Per frame: what the update did (`kept`, `refit`, `rebuilt`, `moved`).
    pub actions: Vec<String>,
    /// Per frame: the worst part's SAH cost over its last fresh build (`auto` only).
    pub cost_ratio: Vec<Option<f64>>,
    /// Per frame: primary rays, ms.
    pub trace_ms: Vec<f64>,
    /// Per frame: update + Whitted render, ms.
    pub time_to_image_ms: Vec<f64>,
    /// Median update.
    pub median_update_ms: f64,
    /// Median primary trace.
    pub median_trace_ms: f64,
    /// Median time to image.
    pub median_time_to_image_ms: f64,
    /// Frames in which something was rebuilt.
    pub rebuilds: usize,
    /// Rays checked against the layout's oracle.
    pub verified: usize,
}

/// One structure animated over one scene.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DynamicRun {
    /// Scene name.
    pub scene: String,
    /// What moves it: `wave` (the preset's deformation of a still model) or `animation`
    /// (the file's own).
    pub motion: String,
    /// Triangles.
    pub triangles: usize,
    /// Structure.
    pub accel: String,
    /// Per frame: full rebuild, ms (the update's own time when `update` is a rebuild,
    /// i.e. when `refits` is false).
    pub rebuild_ms: Vec<f64>,
    /// Whether `update` refits (BVH, BIH) rather than rebuilds.
    pub refits: bool,
    /// Per frame: `update` (refit where the structure has one), ms.
    pub update_ms: Vec<f64>,
    /// Per frame: primary rays through the updated structure, ms.
    pub trace_ms: Vec<f64>,
    /// Per frame: the same rays through a fresh build, ms (= `trace_ms` where `refits` is
    /// false: the update was the fresh build).
    pub fresh_trace_ms: Vec<f64>,
    /// Per frame, where the structure refits and reports an SAH cost: the refit tree's
    /// normalised SAH cost over the fresh build's (empty otherwise).
    pub sah_ratio: Vec<f64>,
    /// Per frame: update + Whitted render, ms.
    pub time_to_image_ms: Vec<f64>,
    /// Medians of the four series.
    pub median_rebuild_ms: f64,
    /// Median update time.
    pub median_update_ms: f64,
    /// Median trace time.
    pub median_trace_ms: f64,
    /// Median time to image.
    pub median_time_to_image_ms: f64,
    /// Primary-ray Mrays/s in the last frame after updates (refit quality decay shows here).
    pub last_frame_mrays_per_s: f64,
    /// Primary-ray Mrays/s in the first frame.
    pub first_frame_mrays_per_s: f64,
    /// Rays checked against brute force over all frames.
    pub verified: usize,
}

/// Median of a non-empty series (mean of the middle two for even lengths); 0 when empty.
pub fn median(v: &[f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// `--preset seed004`'s renderer comparison (`presets::seed004_renderers`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed004Renderers {
    /// Scene rendered.
    pub scene: String,
    /// Its triangles.
    pub triangles: usize,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The scene's `max_recursion_level` (the full branch depth used).
    pub max_recursion_level: u32,
    /// Passes of the `K = 0` renders (one sample per pixel each).
    pub passes: u32,
    /// One entry per structure.
    pub runs: Vec<RendererRun>,
    /// RMSE against Whitted's image after each pass of `K = 0` (the first structure's;
    /// every structure's images are identical).
    pub convergence: Vec<ConvergencePoint>,
}

/// Both renderers over one structure.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RendererRun {
    /// `--accels` spelling.
    pub accel: String,
    /// Build, ms (one build).
    pub build_ms: f64,
    /// Recursive Whitted render, median, ms.
    pub whitted_ms: f64,
    /// Rays of the Whitted render (primary + shadow + secondary).
    pub whitted_rays: u64,
    /// Cumulative render with every bounce expanded, median, ms.
    pub full_branch_ms: f64,
    /// Its largest per-channel relative difference to Whitted's image.
    pub full_branch_max_rel_diff: f64,
    /// Cumulative `K = 0`: median render time over the passes / passes, ms.
    pub pass_ms: f64,
    /// Rays per pass of that render.
    pub pass_rays: u64,
    /// Its RMSE against Whitted's image after the last pass.
    pub rmse: f64,
    /// Whether this structure's images equal the first structure's, bit for bit.
    pub images_identical: bool,
}

/// The error after some passes.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct ConvergencePoint {
    /// Passes accumulated.
    pub passes: u32,
    /// RMSE over every channel against Whitted's image.
    pub rmse: f64,
}

/// `--preset path`: the path tracer's speed per structure and its convergence towards
/// Mitsuba 3's references (`presets::path`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PathResult {
    /// One entry per reference scene.
    pub scenes: Vec<PathScene>,
}

/// The path tracer on one reference scene.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PathScene {
    /// Reference name (`sphere_d2`, ...).
    pub name: String,
    /// The Mitsuba XML rendered.
    pub xml: String,
    /// Its triangles (dynray tessellates Mitsuba's analytic sphere).
    pub triangles: usize,
    /// Image width (the reference's).
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Mitsuba's `max_depth` (path segments).
    pub max_depth: u32,
    /// Samples per pixel of the per-structure runs.
    pub spp: u32,
    /// One entry per structure.
    pub runs: Vec<PathRun>,
    /// RMSE against the reference after each sample per pixel (first structure's run).
    pub convergence: Vec<PathConvergencePoint>,
    /// Mitsuba's own figures for its reference, from `reference/stats.json`.
    pub mitsuba: MitsubaFigures,
}

/// The path tracer over one structure at a fixed sample count.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PathRun {
    /// `--accels` spelling.
    pub accel: String,
    /// Build, ms.
    pub build_ms: f64,
    /// Render, median, ms.
    pub render_ms: f64,
    /// Camera samples per second (pixels × spp / render time).
    pub samples_per_s: f64,
    /// Every ray sent to the structure (camera, shadow, bounce) per second, millions.
    pub mrays_per_s: f64,
    /// Rays of one render.
    pub rays: u64,
    /// RMSE of the image against the reference.
    pub rmse: f64,
    /// Whether the image equals the first structure's, bit for bit.
    pub image_identical: bool,
}

/// The error after some samples per pixel, and when it was reached.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct PathConvergencePoint {
    /// Samples per pixel accumulated.
    pub spp: u32,
    /// Render time until then, ms.
    pub ms: f64,
    /// RMSE over every channel against the reference.
    pub rmse: f64,
    /// Time Mitsuba 3 needs for the same RMSE, ms, estimated from its reference's time and
    /// noise (null where the RMSE is below what that estimate can reach).
    pub mitsuba_ms: Option<f64>,
}

/// What `reference/stats.json` says of Mitsuba's reference render.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct MitsubaFigures {
    /// Samples per pixel of the reference.
    pub spp: u32,
    /// Its render time, s (Mitsuba 3, `scalar_rgb`, same machine class).
    pub render_s: f64,
    /// Root-mean-square per-pixel standard deviation at that spp, over the channels.
    pub rms_pixel_std: f64,
}

impl MitsubaFigures {
    /// Mitsuba's expected RMSE after `spp` samples against an independent reference like
    /// its own: pixel noise falls as 1/√spp, and the reference adds its own.
    pub fn rmse_at(&self, spp: f64) -> f64 {
        let s2 = self.rms_pixel_std.powi(2);
        (s2 * self.spp as f64 / spp + s2).sqrt()
    }

    /// The time, ms, at which Mitsuba reaches `rmse` (inverse of [`Self::rmse_at`] at its
    /// measured seconds per sample); `None` at or below the reference's own noise.
    pub fn ms_for(&self, rmse: f64) -> Option<f64> {
        let s2 = self.rms_pixel_std.powi(2);
        let excess = rmse * rmse - s2;
        (excess > 0.0 && s2 > 0.0).then(|| self.render_s * 1e3 * (s2 / excess))
    }
}

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

/// `--preset seed000`'s dynamic scenario (`presets::seed000_physics`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed000Physics {
    /// Triangles of the frame (the bunny and the floor).
    pub triangles: usize,
    /// Phyxels of the elastic body.
    pub phyxels: usize,
    /// The world in words (bodies, pairs, steps per frame).
    pub world: String,
    /// Frames simulated and rendered.
    pub frames: usize,
    /// Frames per second of simulated time.
    pub frame_rate: u32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Simulation time per frame, ms (once; shared by every structure).
    pub physics_ms: Vec<f64>,
    /// One entry per structure.
    pub runs: Vec<PhysicsRun>,
}

/// One structure following the deforming mesh.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PhysicsRun {
    /// `--accels` spelling.
    pub accel: String,
    /// True: refitted each frame (`update`); false: rebuilt from scratch.
    pub refit: bool,
    /// Rebuild or refit per frame, ms.
    pub update_ms: Vec<f64>,
    /// Primary trace per frame, ms.
    pub trace_ms: Vec<f64>,
    /// Whitted render per frame, ms.
    pub render_ms: Vec<f64>,
    /// Physics + update + render per frame, ms.
    pub time_to_image_ms: Vec<f64>,
    /// Sum of `time_to_image_ms`.
    pub total_time_to_image_ms: f64,
    /// Median of `time_to_image_ms`.
    pub median_time_to_image_ms: f64,
    /// Primary rays checked against brute force over all frames.
    pub verified: usize,
}
