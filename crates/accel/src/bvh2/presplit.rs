//! Pre-splitting (Ernst and Greiner's early split clipping, budgeted as Karras and Aila
//! and Embree's `sah_presplit` builder do): before the binned build, the triangles whose
//! boxes are worst filled are cut into several references, each with the box of the
//! triangle's part on one side of a plane of a power-of-two grid over the scene (planes of
//! neighbouring triangles' cuts then coincide). A wall or floor of two triangles then
//! stops being one leaf whose box every ray through the room enters. What it buys depends
//! on the rays (docs/structures.md, "Pre-splitting"): it is off unless asked for.
//!
//! Exactness: a ray's hit point on the triangle lies in the box of some part (the parts'
//! boxes cover the triangle, each made from the clipped polygon's vertices rounded
//! outwards), so the leaf holding that reference is reached as the whole triangle's leaf
//! would be; the closest hit over a superset of tests is the same hit, and a triangle
//! found twice is the same `(t, id)`.

use super::prim_ref::{Box3, PrimRef};
use super::BvhNode;
use dynray_geom::{Triangle, TriangleMesh};
use glam::Vec3A;
use rayon::prelude::*;

/// Finest grid level a plane is chosen from (2^20 cells per axis over the scene).
const MAX_LEVEL: u32 = 20;

/// Cuts about `budget × n` extra references from `refs` (one whole-triangle reference per
/// triangle, in mesh order, as the build makes them): each triangle gets pieces in
/// proportion to its priority (how much its box exceeds the triangle), at least one. A
/// cut triangle's first part takes its reference's place, the others are appended (few
/// triangles are cut, so only those are revisited).
pub(super) fn cut_refs(mesh: &TriangleMesh, refs: &mut Vec<PrimRef>, budget: f32) {
    let n = mesh.triangle_count();
    debug_assert_eq!(refs.len(), n, "one reference per triangle before cutting");
    let scene = refs
        .par_chunks(4096)
        .map(|c| c.iter().fold(Box3::EMPTY, |b, r| b.union(&r.bounds())))
        .reduce(|| Box3::EMPTY, |a, b| a.union(&b));
    let priority: Vec<f32> = (0..n).into_par_iter().with_min_len(4096).map(|i| priority(&mesh.triangle(i))).collect();
    // Summed in f64 in index order: the piece counts do not depend on the thread count.
    let total: f64 = priority.iter().map(|&p| p as f64).sum();
    if total <= 0.0 {
        return;
    }
    let extra = budget as f64 * n as f64;
    let cut: Vec<(usize, u32)> = (0..n)
        .filter_map(|i| {
            let k = (1 + (priority[i] as f64 / total * extra) as u32).min(MAX_PIECES);
            (k > 1).then_some((i, k))
        })
        .collect();
    let parts: Vec<Vec<Box3>> = cut
        .par_iter()
        .map(|&(i, k)| {
            let mut out = Vec::with_capacity(k as usize);
            split(&mesh.triangle(i), refs[i].bounds(), k, &scene, &mut out);
            out
        })
        .collect();
    for (&(i, _), boxes) in cut.iter().zip(&parts) {
        refs[i] = PrimRef::new(&boxes[0].aabb(), i as u32);
        refs.extend(boxes[1..].iter().map(|b| PrimRef::new(&b.aabb(), i as u32)));
    }
}

/// Most references one triangle is cut into (Embree's presplit caps it at 32 too).
const MAX_PIECES: u32 = 32;

/// How badly the triangle fills its box: the box's surface area less twice the
/// triangle's area (a triangle filling a face of a flat box leaves nothing), square-rooted
/// so that piece counts grow with the box's size rather than its area.
fn priority(t: &Triangle) -> f32 {
    let area = 0.5 * (t.p1 - t.p0).cross(t.p2 - t.p0).length();
    let waste = t.bounds().surface_area() - 2.0 * area;
    if waste.is_finite() && waste > 0.0 {
        waste.sqrt()
    } else {
        0.0
    }
}

/// Cuts the part of `t` inside `b` into `pieces` boxes (fewer where no grid plane crosses
/// a box), appending them to `out`.
fn split(t: &Triangle, b: Box3, pieces: u32, scene: &Box3, out: &mut Vec<Box3>) {
    if pieces <= 1 {
        out.push(b);
        return;
    }
    let Some((axis, c)) = grid_plane(&b, scene) else {
        out.push(b);
        return;
    };
    let (left, right) = clip(t, &b, axis, c);
    match (left, right) {
        (Some(l), Some(r)) => {
            let half = pieces / 2;
            split(t, l, half, scene, out);
            split(t, r, pieces - half, scene, out);
        }
        _ => out.push(b),
    }
}

/// The plane of the coarsest grid level (over `scene`) that crosses `b` strictly inside,
/// on `b`'s longest axis; the one nearest `b`'s centre at that level.
fn grid_plane(b: &Box3, scene: &Box3) -> Option<(usize, f32)> {
    let e = b.hi - b.lo;
    let axis = if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    };
    let (lo, hi, slo, shi) = (b.lo[axis] as f64, b.hi[axis] as f64, scene.lo[axis] as f64, scene.hi[axis] as f64);
    // Finite: the mesh was validated before the build.
    if hi <= lo || shi <= slo {
        return None;
    }
    let mid = 0.5 * (lo + hi);
    for level in 1..=MAX_LEVEL {
        let cell = (shi - slo) / (1u64 << level) as f64;
        let j = ((mid - slo) / cell).round();
        let c = (slo + j * cell) as f32;
        if (c as f64) > lo && (c as f64) < hi {
            return Some((axis, c));
        }
    }
    None
}

/// The boxes of the parts of `t` inside `b` on either side of the plane `axis = c`: the
/// vertices on each side and the edges' crossings with the plane, rounded outwards to
/// `f32`, cut to `b`. `None` for a side the triangle does not reach.
fn clip(t: &Triangle, b: &Box3, axis: usize, c: f32) -> (Option<Box3>, Option<Box3>) {
    let v = [t.p0, t.p1, t.p2].map(|p| [p.x as f64, p.y as f64, p.z as f64]);
    let (mut left, mut right) = (Box3::EMPTY, Box3::EMPTY);
    let c64 = c as f64;
    for i in 0..3 {
        let p = v[i];
        let q = v[(i + 1) % 3];
        if p[axis] <= c64 {
            left.grow(exact(p));
        }
        if p[axis] >= c64 {
            right.grow(exact(p));
        }
        if (p[axis] < c64 && q[axis] > c64) || (p[axis] > c64 && q[axis] < c64) {
            let s = (c64 - p[axis]) / (q[axis] - p[axis]);
            let x: [f64; 3] = std::array::from_fn(|k| if k == axis { c64 } else { p[k] + s * (q[k] - p[k]) });
            let (lo, hi) = outward(x);
            for side in [&mut left, &mut right] {
                side.grow(lo);
                side.grow(hi);
            }
        }
    }
    let cut = |s: Box3| {
        let s = Box3 { lo: s.lo.max(b.lo), hi: s.hi.min(b.hi) };
        (s.lo.cmple(s.hi).all()).then_some(s)
    };
    (cut(left), cut(right))
}

fn exact(p: [f64; 3]) -> Vec3A {
    Vec3A::new(p[0] as f32, p[1] as f32, p[2] as f32)
}

/// The `f32` corners below and above an `f64` point.
fn outward(p: [f64; 3]) -> (Vec3A, Vec3A) {
    let down = |x: f64| {
        let f = x as f32;
        if (f as f64) > x {
            f.next_down()
        } else {
            f
        }
    };
    let up = |x: f64| {
        let f = x as f32;
        if (f as f64) < x {
            f.next_up()
        } else {
            f
        }
    };
    (Vec3A::new(down(p[0]), down(p[1]), down(p[2])), Vec3A::new(up(p[0]), up(p[1]), up(p[2])))
}

/// Drops the repeats of a triangle within one leaf (two parts of a triangle often land
/// side by side), renumbering the leaves' ranges of `ids` in their order.
pub(super) fn dedup_leaves(nodes: &mut [BvhNode], ids: &[u32]) -> Vec<u32> {
    let mut leaves: Vec<usize> = (0..nodes.len()).filter(|&i| nodes[i].is_leaf()).collect();
    leaves.sort_by_key(|&i| nodes[i].index);
    let mut out = Vec::with_capacity(ids.len());
    for i in leaves {
        let (first, count) = (nodes[i].index as usize, nodes[i].count as usize);
        let mut run = ids[first..first + count].to_vec();
        run.sort_unstable();
        run.dedup();
        nodes[i].index = out.len() as u32;
        nodes[i].count = run.len() as u32;
        out.extend_from_slice(&run);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::build::triangle_refs;
    use super::*;
    use dynray_geom::{Aabb, Vec3};

    /// The build's references of `mesh` after cutting.
    fn presplit_refs(mesh: &TriangleMesh, budget: f32) -> Vec<PrimRef> {
        let mut refs = triangle_refs(mesh);
        cut_refs(mesh, &mut refs, budget);
        refs
    }
    use rand::{rngs::SmallRng, Rng, SeedableRng};

    /// `n` random triangles whose sizes span three orders of magnitude (radius `10 u⁴`,
    /// `u` uniform), centred anywhere in a 20-wide cube: a few large slanted ones, the
    /// triangles pre-splitting cuts, among many small ones.
    fn sized_mesh(seed: u64, n: usize) -> TriangleMesh {
        let mut rng = SmallRng::seed_from_u64(seed);
        let mut positions = Vec::with_capacity(3 * n);
        for _ in 0..n {
            let r = 10.0 * rng.gen_range(0.0f32..1.0).powi(4) + 1e-3;
            let c = Vec3::new(rng.gen_range(-10.0..10.0), rng.gen_range(-10.0..10.0), rng.gen_range(-10.0..10.0));
            for _ in 0..3 {
                let d = Vec3::new(rng.gen_range(-r..r), rng.gen_range(-r..r), rng.gen_range(-r..r));
                positions.push((c + d).to_array());
            }
        }
        let indices = (0..n as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        TriangleMesh::new(positions, indices)
    }

    fn contains(b: &Box3, p: [f64; 3]) -> bool {
        (0..3).all(|k| b.lo[k] as f64 <= p[k] && p[k] <= b.hi[k] as f64)
    }

    /// Points of `t` (in f64): its vertices, edge points and interior points.
    fn points_of(t: &Triangle, rng: &mut SmallRng) -> Vec<[f64; 3]> {
        let v = [t.p0, t.p1, t.p2].map(|p| [p.x as f64, p.y as f64, p.z as f64]);
        let mut out = v.to_vec();
        for i in 0..200 {
            let (mut a, mut b) = (rng.gen_range(0.0..1.0f64), rng.gen_range(0.0..1.0f64));
            if a + b > 1.0 {
                (a, b) = (1.0 - a, 1.0 - b);
            }
            if i % 4 == 0 {
                b = 0.0; // on an edge
            }
            out.push(std::array::from_fn(|k| v[0][k] + a * (v[1][k] - v[0][k]) + b * (v[2][k] - v[0][k])));
        }
        out
    }

    /// Each side's box holds every point of the triangle on that side of the plane
    /// (checked in f64 against the f32 box), and the crossings of the plane lie in both.
    #[test]
    fn clipped_boxes_hold_each_sides_points() {
        let mut rng = SmallRng::seed_from_u64(11);
        let mesh = sized_mesh(3, 400);
        for i in 0..mesh.triangle_count() {
            let t = mesh.triangle(i);
            let b = Box3::from(&t.bounds());
            let axis = rng.gen_range(0..3);
            let c = rng.gen_range(b.lo[axis]..=b.hi[axis]);
            let (left, right) = clip(&t, &b, axis, c);
            for p in points_of(&t, &mut rng) {
                let c = c as f64;
                if p[axis] <= c {
                    assert!(left.is_some_and(|l| contains(&l, p)), "triangle {i} point {p:?} left of {c}: {left:?}");
                }
                if p[axis] >= c {
                    assert!(right.is_some_and(|r| contains(&r, p)), "triangle {i} point {p:?} right of {c}: {right:?}");
                }
            }
            for s in [left, right].into_iter().flatten() {
                assert!(b.lo.cmple(s.lo).all() && s.hi.cmple(b.hi).all(), "a side leaves the box");
            }
        }
    }

    /// Where a crossing is a side's extreme, the box must reach past the crossing's
    /// nearest `f32`: here edge p0–p1 crosses x = 1 at y = 5/3, whose nearest `f32` lies
    /// below it, so a box rounded to nearest would miss the crossing.
    #[test]
    fn crossings_are_rounded_outwards() {
        let t = Triangle::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(3.0, 5.0, 0.0), Vec3::new(3.0, 0.0, 0.0));
        let y = 5.0f64 / 3.0;
        assert!(((y as f32) as f64) < y, "the check needs a crossing whose nearest f32 is below it");
        let (left, _) = clip(&t, &Box3::from(&t.bounds()), 0, 1.0);
        let left = left.unwrap();
        assert!(contains(&left, [1.0, y, 0.0]), "{left:?}");
        assert_eq!(left.hi.x, 1.0, "the plane bounds the left side exactly");
    }

    /// The references of a triangle together cover it, every reference is inside the
    /// triangle's box, the budget is about what was asked, and the pieces go to large
    /// triangles.
    #[test]
    fn references_cover_their_triangle() {
        let mesh = sized_mesh(5, 2_000);
        let n = mesh.triangle_count();
        let refs = presplit_refs(&mesh, 0.5);
        assert!(refs.len() > n + n / 5 && refs.len() <= n + n / 2, "{} refs for {n} triangles", refs.len());
        let mut of = vec![Vec::new(); n];
        for r in &refs {
            of[r.id() as usize].push(r.bounds());
        }
        let mut rng = SmallRng::seed_from_u64(12);
        for (i, boxes) in of.iter().enumerate() {
            let t = mesh.triangle(i);
            let tb = Box3::from(&t.bounds());
            assert!(!boxes.is_empty(), "triangle {i} lost");
            for b in boxes {
                assert!(tb.lo.cmple(b.lo).all() && b.hi.cmple(tb.hi).all(), "triangle {i}: {b:?} outside {tb:?}");
            }
            for p in points_of(&t, &mut rng) {
                assert!(boxes.iter().any(|b| contains(b, p)), "triangle {i}: point {p:?} in none of {boxes:?}");
            }
        }
        let mut areas: Vec<f32> = (0..n).map(|i| mesh.triangle(i).bounds().surface_area()).collect();
        areas.sort_by(f32::total_cmp);
        let median = areas[n / 2];
        assert!((0..n).all(|i| of[i].len() == 1 || mesh.triangle(i).bounds().surface_area() > median));
    }

    #[test]
    fn same_references_on_one_and_two_threads() {
        let mesh = sized_mesh(6, 20_000);
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| presplit_refs(&mesh, 0.3))
        };
        let key = |r: &Vec<PrimRef>| r.iter().map(|p| (p.id(), p.bounds().aabb())).collect::<Vec<_>>();
        assert_eq!(key(&run(1)), key(&run(2)));
    }

    #[test]
    fn dedup_keeps_one_copy_per_leaf_and_renumbers() {
        let b = Aabb::EMPTY;
        let mut nodes = vec![BvhNode::interior(&b, 1), BvhNode::leaf(&b, 4, 3), BvhNode::leaf(&b, 0, 4)];
        let ids = [7, 2, 7, 7, 5, 9, 5];
        let out = dedup_leaves(&mut nodes, &ids);
        assert_eq!(out, vec![2, 7, 5, 9]);
        assert_eq!((nodes[2].index, nodes[2].count, nodes[1].index, nodes[1].count), (0, 2, 2, 2));
    }
}
