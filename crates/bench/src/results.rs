//! Measurement results the standard run and the presets share: a scene's structures
//! with their figures per ray kind, competitors' figures, disagreements with brute force.

use serde::{Deserialize, Serialize};

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
