//! Smooth vertex normals for meshes that have none: each face's unit normal weighted by
//! the angle of its corner at the vertex (Thürmer & Wüthrich 1998), with a crease angle
//! so that hard edges stay hard.
//!
//! The rule, per corner (one triangle's use of one vertex): gather the faces around the
//! corner's position, and average, weighted by their corner angles there, those whose
//! normal lies within the crease angle of the corner's own face. Positions are welded by
//! their exact bits (`-0.0` equal to `+0.0`) when gathering, so a mesh whose loader
//! duplicated vertices along uv seams (OBJ, glTF) still smooths across the seam. A vertex
//! whose corners end up averaging different sets of faces is split: one output vertex per
//! set, with the position's bits copied. Triangle count, order and the three positions of
//! every triangle are unchanged bit for bit, so no ray's hit changes.
//!
//! Built in two steps so that a deforming mesh (a skin, point-based physics) pays for the
//! topology once: [`SmoothNormals::new`] decides on the rest pose which corners share an
//! output vertex and which faces each output vertex averages; [`SmoothNormals::compute`]
//! recomputes the normals from new positions of the same vertices in one linear pass.
//!
//! With a crease below 90°, every face a corner averages lies within 90° of the corner's
//! own, so a generated normal always faces the same side as its triangle.
//!
//! Angle weighting, rather than area weighting or a plain mean, makes the normal a
//! property of the surface and not of how it was triangulated: splitting a face into a
//! fan of thin triangles leaves the weights of its corners the same.

use crate::{MeshError, TriangleMesh};
use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// Most corners a welded position may have for the exact per-corner crease rule, which
/// keeps one bit per corner in a `u64` and costs the square of the count. A position with
/// more (a fan centre, a cone tip, the pole of a fine lat-long sphere) is smoothed as a
/// whole when all its faces lie within half the crease angle of their mean normal — then
/// every pair is within the crease, so the exact rule would give the same — and is shaded
/// flat (each corner its own face) otherwise: such points have no single normal anyway.
pub const MAX_EXACT_CORNERS: usize = 64;

/// Triangles per batch of [`SmoothNormals::compute`]'s parallel weights (1.1 MiB of them).
const BATCH: usize = 1 << 15;

/// Fewest items a parallel task takes, so that splitting costs little next to the work.
const PAR_MIN: usize = 4096;

/// Which faces around a welded position an output vertex averages.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Members {
    /// Every face around the position. Ordered first, so the smooth class of a vertex
    /// keeps the vertex's index when it is split.
    All,
    /// The corners whose bits are set, numbered in the position's corner list.
    Mask(u64),
    /// Only the face of this corner of the list (see [`MAX_EXACT_CORNERS`]).
    Own(u32),
}

/// An output vertex that averages only some of the faces around its position.
#[derive(Clone, Copy, Debug)]
struct Subset {
    vertex: u32,
    /// Its position's corners: `subset_corners[start..end]`, which `members` numbers.
    start: u32,
    end: u32,
    members: Members,
}

/// The topology of smooth normals for one mesh: which corners share an output vertex and
/// which faces each output vertex averages, decided once (module docs).
///
/// ```
/// use dynray_geom::{SmoothNormals, TriangleMesh};
/// // Two triangles folded 90° along their shared edge: the crease keeps it hard.
/// let mesh = TriangleMesh::new(
///     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
///     vec![[0, 1, 2], [0, 3, 1]],
/// );
/// let smooth = SmoothNormals::new(&mesh, 60.0)?;
/// let mut shaded = mesh.clone();
/// smooth.apply(&mut shaded)?;
/// assert_eq!(smooth.split_count(), 2); // vertices 0 and 1 are split along the edge
/// assert_eq!(shaded.triangle(1).p0, mesh.triangle(1).p0);
/// assert_eq!(shaded.normals.unwrap()[shaded.indices[0][0] as usize], [0.0, 0.0, 1.0]);
/// # Ok::<(), dynray_geom::MeshError>(())
/// ```
#[derive(Clone, Debug)]
pub struct SmoothNormals {
    crease_deg: f32,
    /// Vertices of the mesh the topology was built for.
    source_vertices: usize,
    /// The output triangles: the input's, in order, with split vertices renumbered.
    indices: Vec<[u32; 3]>,
    /// Number of welded positions.
    welded_count: usize,
    /// The input vertex and the welded position of each output vertex; output vertex
    /// `i < source_vertices` copies input vertex `i`, the split ones follow.
    out_source: Vec<u32>,
    out_welded: Vec<u32>,
    /// Output vertices that average a subset of their position's faces (a few, along
    /// creases), and the corner lists (`3 × triangle + k`) of the positions where the
    /// crease mattered.
    subsets: Vec<Subset>,
    subset_corners: Vec<u32>,
}

impl SmoothNormals {
    /// The topology of `mesh` (positions and indices; its normals and uvs are not read)
    /// for crease angle `crease_deg`, in degrees, clamped to `0..=180` (NaN counts as 0):
    /// 0 shades every corner with its own face (exactly coplanar neighbours aside), 180
    /// smooths across every edge.
    ///
    /// Errors on an index out of range, and on a mesh too large for `u32` vertex numbers
    /// once split. Degenerate (zero-area) triangles are allowed: they add nothing to any
    /// normal, and their own corners get their position's full average (zero when no
    /// face there has an area, which shading reads as "use the geometric normal").
    pub fn new(mesh: &TriangleMesh, crease_deg: f32) -> Result<Self, MeshError> {
        let n = mesh.positions.len();
        for (triangle, tri) in mesh.indices.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(MeshError::IndexOutOfRange { triangle, index, vertices: n });
            }
        }
        let corner_count = mesh.indices.len() * 3;
        // Splitting adds at most one vertex per corner.
        if n.saturating_add(corner_count) > u32::MAX as usize {
            return Err(MeshError::TooLarge { vertices: n, triangles: mesh.indices.len() });
        }
        let crease = if crease_deg.is_nan() { 0.0 } else { crease_deg.clamp(0.0, 180.0) };
        let position = |i: u32| DVec3::from_array(mesh.positions[i as usize].map(f64::from));
        // Unit face normals as wound (computed in f64, kept in f32: they only decide the
        // crease), zero for a degenerate triangle.
        let face_normals: Vec<Vec3> = mesh
            .indices
            .par_iter()
            .with_min_len(PAR_MIN)
            .map(|t| {
                let (p0, p1, p2) = (position(t[0]), position(t[1]), position(t[2]));
                unit_or_zero((p1 - p0).cross(p2 - p0)).as_vec3()
            })
            .collect();

        let (weld, welded) = weld_positions(&mesh.positions);
        let welded_indices: Vec<[u32; 3]> = mesh.indices.iter().map(|t| t.map(|v| weld[v as usize])).collect();
        let test = CreaseTest::new(crease);
        let creased = test.creased_positions(&welded_indices, &face_normals, welded);

        // Corner lists (`3 × triangle + k`, ascending) of the creased positions only: the
        // rest keep one normal per vertex and need none.
        let mut slot = vec![u32::MAX; welded];
        for (i, &w) in creased.iter().enumerate() {
            slot[w as usize] = i as u32;
        }
        let mut offsets = vec![0u32; creased.len() + 1];
        for t in &welded_indices {
            for &w in t {
                let s = slot[w as usize];
                if s != u32::MAX {
                    offsets[s as usize + 1] += 1;
                }
            }
        }
        for i in 0..creased.len() {
            offsets[i + 1] += offsets[i];
        }
        let mut fill: Vec<u32> = offsets[..creased.len()].to_vec();
        let mut subset_corners = vec![0u32; offsets[creased.len()] as usize];
        for (f, t) in welded_indices.iter().enumerate() {
            for (k, &w) in t.iter().enumerate() {
                let s = slot[w as usize];
                if s != u32::MAX {
                    subset_corners[fill[s as usize] as usize] = (3 * f + k) as u32;
                    fill[s as usize] += 1;
                }
            }
        }
        drop((slot, fill));

        let mut out_source: Vec<u32> = (0..n as u32).collect();
        let mut subsets = Vec::new();
        let mut claimed = vec![false; n];
        let mut indices = mesh.indices.clone();
        let mut classes = Vec::new();
        // (input vertex, members, corner) of one position's corners.
        let mut group: Vec<(u32, Members, u32)> = Vec::new();
        for i in 0..creased.len() {
            let (start, end) = (offsets[i], offsets[i + 1]);
            let around = &subset_corners[start as usize..end as usize];
            test.classify(around, &face_normals, &mut classes);
            group.clear();
            group.extend(around.iter().zip(&classes).map(|(&c, &m)| (corner_vertex(&mesh.indices, c), m, c)));
            group.sort_unstable();
            // One output vertex per (input vertex, members): the first keeps the input
            // vertex's number, later ones are appended (the split).
            let mut i = 0;
            while i < group.len() {
                let (v, members, _) = group[i];
                let out = if !std::mem::replace(&mut claimed[v as usize], true) {
                    v
                } else {
                    out_source.push(v);
                    out_source.len() as u32 - 1
                };
                if members != Members::All {
                    subsets.push(Subset { vertex: out, start, end, members });
                }
                while i < group.len() && group[i].0 == v && group[i].1 == members {
                    let c = group[i].2 as usize;
                    indices[c / 3][c % 3] = out;
                    i += 1;
                }
            }
        }
        let out_welded = out_source.iter().map(|&v| weld[v as usize]).collect();
        Ok(Self {
            crease_deg: crease,
            source_vertices: n,
            indices,
            welded_count: welded,
            out_source,
            out_welded,
            subsets,
            subset_corners,
        })
    }

    /// The crease angle in degrees, as clamped by [`SmoothNormals::new`].
    pub fn crease_deg(&self) -> f32 {
        self.crease_deg
    }

    /// Output triangles: the input's in order, pointing at split vertices where needed.
    pub fn indices(&self) -> &[[u32; 3]] {
        &self.indices
    }

    /// Number of output vertices (input vertices plus [`SmoothNormals::split_count`]).
    pub fn vertex_count(&self) -> usize {
        self.out_source.len()
    }

    /// Vertices added by splitting along creases.
    pub fn split_count(&self) -> usize {
        self.out_source.len() - self.source_vertices
    }

    /// Makes `mesh` (the mesh the topology was built for, or a deformation of it with the
    /// same vertices) the smooth mesh, in place: split vertices appended with their
    /// positions' and uvs' bits copied, the output triangles, generated normals (replacing
    /// any). On an error (vertex counts that do not match) `mesh` is left as it was.
    pub fn apply(&self, mesh: &mut TriangleMesh) -> Result<(), MeshError> {
        self.check_len("positions", mesh.positions.len())?;
        if let Some(uvs) = &mesh.uvs {
            self.check_len("uvs", uvs.len())?;
        }
        let mut normals = mesh.normals.take().unwrap_or_default();
        self.compute(&mesh.positions, &mut normals)?;
        mesh.normals = Some(normals);
        let split = &self.out_source[self.source_vertices..];
        append_copies(&mut mesh.positions, split);
        if let Some(uvs) = &mut mesh.uvs {
            append_copies(uvs, split);
        }
        mesh.indices.clear();
        mesh.indices.extend_from_slice(&self.indices);
        Ok(())
    }

    /// Per-vertex `values` of the input (positions, uvs, colours) for the output
    /// vertices, into `out` (cleared first).
    pub fn gather<T: Copy>(&self, values: &[T], out: &mut Vec<T>) -> Result<(), MeshError> {
        self.check_len("values", values.len())?;
        out.clear();
        out.extend(self.out_source.iter().map(|&v| values[v as usize]));
        Ok(())
    }

    /// Normals of the output vertices, into `normals` (cleared first), from `positions`
    /// of the input vertices — the rest pose or any deformation of it (the topology and
    /// the split decided by [`SmoothNormals::new`] are kept). Unit vectors, or zero where
    /// the faces averaged have no area or cancel out; never NaN.
    pub fn compute(&self, positions: &[[f32; 3]], normals: &mut Vec<[f32; 3]>) -> Result<(), MeshError> {
        self.check_len("positions", positions.len())?;
        // Every position's full average in one pass over the triangles, adding in corner
        // order (so seam copies get the same bits); the few vertices that average a
        // subset are summed again from their lists. (A first version summed every vertex
        // from its position's corner list, with random reads: 2.5× as long on the dragon.)
        // The weights (the arithmetic) in parallel, a batch at a time; the sums in order,
        // so the bits do not depend on the threads.
        let mut full = vec![Vec3::ZERO; self.welded_count];
        let mut batch = vec![[Vec3::ZERO; 3]; BATCH.min(self.indices.len())];
        for (b, tris) in self.indices.chunks(BATCH).enumerate() {
            let weights = &mut batch[..tris.len()];
            weights
                .par_iter_mut()
                .with_min_len(PAR_MIN)
                .enumerate()
                .for_each(|(i, w)| *w = self.corner_weights(b * BATCH + i, positions));
            for (t, w) in tris.iter().zip(weights.iter()) {
                for k in 0..3 {
                    full[self.out_welded[t[k] as usize] as usize] += w[k];
                }
            }
        }
        normals.clear();
        normals.extend(self.out_welded.iter().map(|&w| full[w as usize].normalize_or_zero().to_array()));
        for s in &self.subsets {
            let around = &self.subset_corners[s.start as usize..s.end as usize];
            let weight = |c: u32| self.corner_weights(c as usize / 3, positions)[c as usize % 3];
            let sum = match s.members {
                Members::All => full[self.out_welded[s.vertex as usize] as usize],
                Members::Mask(mask) => around
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| mask >> j & 1 == 1)
                    .fold(Vec3::ZERO, |sum, (_, &c)| sum + weight(c)),
                Members::Own(j) => weight(around[j as usize]),
            };
            normals[s.vertex as usize] = sum.normalize_or_zero().to_array();
        }
        Ok(())
    }

    /// Triangle `f`'s unit normal scaled by its angle at each corner; zero for a
    /// degenerate triangle. Computed in `f64` (cross products of `f32` coordinates cannot
    /// overflow there, and slivers keep their direction), summed in `f32`.
    fn corner_weights(&self, f: usize, positions: &[[f32; 3]]) -> [Vec3; 3] {
        let p =
            self.indices[f].map(|o| DVec3::from_array(positions[self.out_source[o as usize] as usize].map(f64::from)));
        let (e01, e02, e12) = (p[1] - p[0], p[2] - p[0], p[2] - p[1]);
        let n = e01.cross(e02);
        let len = n.length();
        if !(len > 0.0 && len.is_finite()) {
            return [Vec3::ZERO; 3];
        }
        // The angle of (dot, |cross|) — |cross| is twice the area, the same at every
        // corner — is the corner angle, accurate for slivers too; the third closes the
        // triangle.
        let a0 = corner_angle(len, e01.dot(e02));
        let a1 = corner_angle(len, -e01.dot(e12));
        let a2 = (std::f64::consts::PI - a0 - a1).max(0.0);
        let unit = n / len;
        [unit * a0, unit * a1, unit * a2].map(|w| w.as_vec3())
    }

    fn check_len(&self, what: &'static str, got: usize) -> Result<(), MeshError> {
        if got == self.source_vertices {
            Ok(())
        } else {
            Err(MeshError::AttributeCount { what, got, vertices: self.source_vertices })
        }
    }
}

/// The crease angle as the dot-product thresholds the rule compares against (of `f32`
/// unit normals: the crease is a tolerance, not a measurement).
struct CreaseTest {
    /// Faces within the crease of each other: `dot ≥ cos(crease)`; `None` at 180°,
    /// where every face is (a threshold of −1 could miss antiparallel faces by rounding).
    cos_crease: Option<f32>,
    /// All faces within half the crease of their mean: then every pair is within it.
    cos_half: f32,
}

impl CreaseTest {
    fn new(crease_deg: f32) -> Self {
        let r = f64::from(crease_deg).to_radians();
        Self { cos_crease: (crease_deg < 180.0).then(|| r.cos() as f32), cos_half: (r * 0.5).cos() as f32 }
    }

    /// The welded positions whose faces do not all lie within half the crease of their
    /// mean normal, ascending: the only ones where corners may need different normals
    /// (the others are one smooth cap: every pair of faces is within the crease). One
    /// pass over the triangles, in their order.
    fn creased_positions(&self, welded_indices: &[[u32; 3]], face_normals: &[Vec3], welded: usize) -> Vec<u32> {
        if self.cos_crease.is_none() {
            return Vec::new();
        }
        let mut mean = vec![Vec3::ZERO; welded];
        for (t, n) in welded_indices.iter().zip(face_normals) {
            for &w in t {
                mean[w as usize] += *n;
            }
        }
        for m in &mut mean {
            *m = m.normalize_or_zero();
        }
        // Which corners of each triangle fail, in parallel (a zero mean, of faces that
        // cancel, fails too: `cos_half` is positive below 180°; nothing here is NaN);
        // then the positions they name.
        let fails: Vec<u8> = welded_indices
            .par_iter()
            .zip(face_normals)
            .with_min_len(PAR_MIN)
            .map(|(t, n)| {
                let live = *n != Vec3::ZERO;
                (0..3).filter(|&k| live && n.dot(mean[t[k] as usize]) < self.cos_half).fold(0, |m, k| m | 1 << k)
            })
            .collect();
        let mut creased = vec![false; welded];
        for (t, &f) in welded_indices.iter().zip(&fails) {
            for (k, &w) in t.iter().enumerate() {
                if f >> k & 1 == 1 {
                    creased[w as usize] = true;
                }
            }
        }
        (0..welded as u32).filter(|&w| creased[w as usize]).collect()
    }

    /// The members of each corner of `around` (the corners of one creased position),
    /// into `out`: the exact per-corner rule, or each face alone past
    /// [`MAX_EXACT_CORNERS`].
    fn classify(&self, around: &[u32], face_normals: &[Vec3], out: &mut Vec<Members>) {
        out.clear();
        let normal = |c: u32| face_normals[c as usize / 3];
        let live = |c: u32| normal(c) != Vec3::ZERO;
        let Some(cos_crease) = self.cos_crease else {
            out.resize(around.len(), Members::All);
            return;
        };
        if around.len() > MAX_EXACT_CORNERS {
            out.extend(
                around.iter().enumerate().map(|(j, &c)| if live(c) { Members::Own(j as u32) } else { Members::All }),
            );
            return;
        }
        let all: u64 = around.iter().enumerate().filter(|&(_, &c)| live(c)).fold(0, |m, (j, _)| m | 1 << j);
        for (j, &c) in around.iter().enumerate() {
            if !live(c) {
                // A degenerate face's corners take the whole position's average.
                out.push(Members::All);
                continue;
            }
            let n = normal(c);
            let mask = around
                .iter()
                .enumerate()
                .filter(|&(i, &d)| live(d) && (i == j || normal(d).dot(n) >= cos_crease))
                .fold(0u64, |m, (i, _)| m | 1 << i);
            out.push(if mask == all { Members::All } else { Members::Mask(mask) });
        }
    }
}

/// `y.atan2(x)` for `y > 0` (an angle in `(0, π)`), within 5e-10 rad: reduced to
/// `|u| ≤ tan(π/8)`, where ten terms of atan's alternating series leave an error below
/// the eleventh, `tan(π/8)^21 / 21 < 5e-10`. libm's `atan2` was a third of
/// [`SmoothNormals::compute`] on the dragon; with this one compute took 58 ms, not 75.
fn corner_angle(y: f64, x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let (a, b) = (x.abs(), y);
    // atan(t) for t in [0, 1], from the smaller over the larger side.
    let (t, steep) = if b > a { (a / b, true) } else { (b / a, false) };
    let (u, base) = if t > std::f64::consts::SQRT_2 - 1.0 { ((t - 1.0) / (t + 1.0), FRAC_PI_4) } else { (t, 0.0) };
    let u2 = u * u;
    const C: [f64; 10] = [
        1.0,
        -1.0 / 3.0,
        1.0 / 5.0,
        -1.0 / 7.0,
        1.0 / 9.0,
        -1.0 / 11.0,
        1.0 / 13.0,
        -1.0 / 15.0,
        1.0 / 17.0,
        -1.0 / 19.0,
    ];
    let series = C.iter().rev().fold(0.0, |acc, &c| acc * u2 + c);
    let r = base + u * series;
    let r = if steep { FRAC_PI_2 - r } else { r };
    if x < 0.0 {
        PI - r
    } else {
        r
    }
}

/// Appends a copy of `values[v]` for each `v` of `sources`.
fn append_copies<T: Copy>(values: &mut Vec<T>, sources: &[u32]) {
    // Exact: a doubled buffer would be fresh pages for the kernel to clear, for nothing.
    values.reserve_exact(sources.len());
    for &v in sources {
        let x = values[v as usize];
        values.push(x);
    }
}

/// The input vertex of corner `c`.
fn corner_vertex(indices: &[[u32; 3]], c: u32) -> u32 {
    indices[c as usize / 3][c as usize % 3]
}

/// `v / |v|`, or zero when `v` has no usable length.
fn unit_or_zero(v: DVec3) -> DVec3 {
    let len = v.length();
    if len > 0.0 && len.is_finite() {
        v / len
    } else {
        DVec3::ZERO
    }
}

/// Numbers the distinct positions (by bits, `-0.0` as `+0.0`) in the order of their first
/// vertex: returns each vertex's number and the count. Found by sorting rather than
/// hashing (no hasher to choose, nothing depends on one); numbered in vertex order rather
/// than sorted order because meshes store nearby vertices together, and the passes over
/// positions then read memory in order (numbered in sorted order, building the dragon's
/// topology took 1.6× as long).
fn weld_positions(positions: &[[f32; 3]]) -> (Vec<u32>, usize) {
    let mut keyed: Vec<([u32; 3], u32)> =
        positions.iter().enumerate().map(|(i, p)| (p.map(|c| (c + 0.0).to_bits()), i as u32)).collect();
    keyed.par_sort_unstable();
    // The first (lowest) vertex of each position stands for it.
    let mut first = vec![0u32; positions.len()];
    let mut rep = 0;
    for (i, &(key, v)) in keyed.iter().enumerate() {
        if i == 0 || keyed[i - 1].0 != key {
            rep = v;
        }
        first[v as usize] = rep;
    }
    let mut weld = first;
    let mut count = 0u32;
    for v in 0..weld.len() {
        let rep = weld[v] as usize;
        weld[v] = if rep == v {
            count += 1;
            count - 1
        } else {
            // `rep < v`: already numbered.
            weld[rep]
        };
    }
    (weld, count as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welding_treats_signed_zeros_as_one_position_and_keeps_others_apart() {
        let (weld, n) = weld_positions(&[[0.0, 1.0, 2.0], [-0.0, 1.0, 2.0], [0.0, 1.0, 2.5], [0.0, 1.0, 2.0]]);
        assert_eq!(n, 2);
        assert_eq!(weld[0], weld[1]);
        assert_eq!(weld[0], weld[3]);
        assert_ne!(weld[0], weld[2]);
        assert_eq!(weld_positions(&[]), (vec![], 0));
    }

    #[test]
    fn corner_angle_is_atan2_within_its_bound() {
        let check = |y: f64, x: f64| {
            let e = (corner_angle(y, x) - y.atan2(x)).abs();
            assert!(e < 5e-10, "corner_angle({y}, {x}) is off by {e}");
        };
        // Every octant boundary and reduction switch, and a sweep around the half circle.
        for (y, x) in [(1.0, 0.0), (1.0, 1.0), (1.0, -1.0), (1e-300, 1.0), (1e-300, -1.0), (1.0, 1e-300)] {
            check(y, x);
        }
        for i in 1..20_000 {
            let a = std::f64::consts::PI * i as f64 / 20_000.0;
            check(a.sin() * 3.0, a.cos() * 3.0);
            let t = (std::f64::consts::SQRT_2 - 1.0) * (1.0 + (i as f64 - 10_000.0) * 1e-9);
            check(t, 1.0);
        }
    }

    #[test]
    fn crease_thresholds() {
        let t = CreaseTest::new(60.0);
        assert!((t.cos_crease.unwrap() - 0.5).abs() < 1e-7);
        assert!((t.cos_half - 0.75f32.sqrt()).abs() < 1e-7);
        assert_eq!(CreaseTest::new(180.0).cos_crease, None);
    }
}
