//! Triangle–box overlap by the separating-axis theorem (Akenine-Möller, "Fast 3D
//! triangle-box overlap testing", JGT 2001), in f64: the one test every builder that
//! inserts triangles into cells (grid, octree) uses.
//!
//! Conservative by design, because a false "overlap" costs a wasted reference while a
//! false "no overlap" would lose hits: the box is closed (touching counts: separation
//! needs strict inequalities); on every axis, the triangle's own plane normal included,
//! all three projected vertices are compared (not one vertex, whose rounding could
//! separate a triangle lying in the box's face); degenerate triangles (zero area) pass
//! whenever their segment or point meets the box, because their zero cross products
//! separate nothing. Callers widen the box by their own slack, which leaves rounding
//! (~1e-16 relative in f64) no room to separate a triangle that touches the cell.
//!
//! (The grid and the octree each had a copy; the octree's tested the plane with one
//! vertex, `|n·v0| <= r`, the grid's with all three: this is the grid's, the more
//! conservative.)

use crate::Triangle;

type V = [f64; 3];

fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: V, b: V) -> V {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// True unless some axis separates the triangle `tri` (vertices in f64) from the closed
/// box `centre ± half`.
pub fn triangle_box_overlap(tri: &[[f64; 3]; 3], centre: [f64; 3], half: [f64; 3]) -> bool {
    let v = [sub(tri[0], centre), sub(tri[1], centre), sub(tri[2], centre)];
    // 1. The box's own axes (the triangle's bounding box against the box).
    for a in 0..3 {
        let lo = v[0][a].min(v[1][a]).min(v[2][a]);
        let hi = v[0][a].max(v[1][a]).max(v[2][a]);
        if lo > half[a] || hi < -half[a] {
            return false;
        }
    }
    let e = [sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])];
    // 2. The nine edge × box-axis directions.
    for edge in &e {
        for a in 0..3 {
            let mut unit = [0.0; 3];
            unit[a] = 1.0;
            if separated(&v, cross(*edge, unit), half) {
                return false;
            }
        }
    }
    // 3. The triangle's plane.
    !separated(&v, cross(e[0], e[1]), half)
}

/// True when the projections of the triangle and the box on `axis` are disjoint.
fn separated(v: &[V; 3], axis: V, half: V) -> bool {
    let (p0, p1, p2) = (dot(v[0], axis), dot(v[1], axis), dot(v[2], axis));
    let r = half[0] * axis[0].abs() + half[1] * axis[1].abs() + half[2] * axis[2].abs();
    p0.min(p1).min(p2) > r || p0.max(p1).max(p2) < -r
}

impl Triangle {
    /// [`triangle_box_overlap`] of this triangle (its vertices widened to f64).
    pub fn overlaps_box(&self, centre: [f64; 3], half: [f64; 3]) -> bool {
        let p = |v: crate::Vec3| [v.x as f64, v.y as f64, v.z as f64];
        triangle_box_overlap(&[p(self.p0), p(self.p1), p(self.p2)], centre, half)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec3;

    const C: [f64; 3] = [0.0; 3];
    const H: [f64; 3] = [1.0; 3];

    #[test]
    fn inside_and_outside() {
        assert!(triangle_box_overlap(&[[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 0.5, 0.0]], C, H));
        assert!(!triangle_box_overlap(&[[2.0, 2.0, 2.0], [3.0, 2.0, 2.0], [2.0, 3.0, 2.0]], C, H));
    }

    #[test]
    fn large_triangle_through_the_box_overlaps() {
        assert!(triangle_box_overlap(&[[-10.0, -10.0, 0.2], [10.0, -10.0, 0.2], [0.0, 10.0, 0.2]], C, H));
    }

    #[test]
    fn triangle_near_a_corner_is_separated_by_an_edge_axis() {
        // Its bounding box overlaps the box, but the plane x + y + z = 3.2 does not.
        assert!(!triangle_box_overlap(&[[1.6, 1.6, 0.0], [0.0, 1.6, 1.6], [1.6, 0.0, 1.6]], C, H));
        assert!(triangle_box_overlap(&[[1.4, 1.4, 0.0], [0.0, 1.4, 1.4], [1.4, 0.0, 1.4]], C, H));
    }

    #[test]
    fn touching_counts() {
        assert!(triangle_box_overlap(&[[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0]], C, H));
        assert!(triangle_box_overlap(&[[1.0, 1.0, 1.0], [2.0, 1.0, 1.0], [2.0, 2.0, 1.0]], C, H));
    }

    #[test]
    fn degenerate_triangles_are_conservative() {
        assert!(triangle_box_overlap(&[[0.5; 3], [0.5; 3], [0.5; 3]], C, H));
        assert!(!triangle_box_overlap(&[[1.5; 3], [1.5; 3], [1.5; 3]], C, H));
        assert!(triangle_box_overlap(&[[-3.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 0.0, 0.0]], C, H));
    }

    #[test]
    fn separates_and_touches_through_the_triangle_type() {
        let t = Triangle::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0));
        // Box beyond the hypotenuse: bounding boxes overlap, the triangle does not.
        assert!(!t.overlaps_box([1.6, 1.6, 0.0], [0.3, 0.3, 0.3]));
        // Box touching the hypotenuse at one corner counts (closed boxes).
        assert!(t.overlaps_box([1.5, 1.5, 0.0], [0.5, 0.5, 0.5]));
        assert!(t.overlaps_box([0.5, 0.5, 0.0], [0.1, 0.1, 0.1]));
        // Box above the plane.
        assert!(!t.overlaps_box([0.5, 0.5, 1.0], [0.5, 0.5, 0.4]));
    }

    #[test]
    fn a_triangle_in_a_box_face_is_kept_whatever_vertex_rounds() {
        // Lies in the face z = 1 of the box, with coordinates whose plane projections
        // round differently per vertex: must overlap (the cell's neighbour holds it too).
        let t = [[0.1, 0.7, 1.0], [0.9, 0.3, 1.0], [0.3, 0.123456789, 1.0]];
        assert!(triangle_box_overlap(&t, C, H));
    }
}
