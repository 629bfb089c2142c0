//! Triangle–box overlap by the separating-axis theorem (Akenine-Möller, "Fast 3D
//! triangle-box overlap testing", JGT 2001), in f64 on a box the caller widens.
//!
//! Conservative by design: touching counts as overlapping (all comparisons are strict
//! for separation), and degenerate triangles (zero area) pass whenever their segment or
//! point boxes overlap, because their zero cross products separate nothing. An extra
//! reference costs a triangle test; a missing one would lose a hit.

/// True unless some axis separates the triangle `v` from the box of centre `c` and
/// half-extent `h`.
pub fn tri_box_overlap(c: [f64; 3], h: [f64; 3], v: &[[f64; 3]; 3]) -> bool {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let v0 = sub(v[0], c);
    let v1 = sub(v[1], c);
    let v2 = sub(v[2], c);
    // 1. The box's own axes: the triangle's bounding box against the box.
    for a in 0..3 {
        let lo = v0[a].min(v1[a]).min(v2[a]);
        let hi = v0[a].max(v1[a]).max(v2[a]);
        if lo > h[a] || hi < -h[a] {
            return false;
        }
    }
    let e = [sub(v1, v0), sub(v2, v1), sub(v0, v2)];
    // 2. The nine cross products of triangle edges with the box axes.
    for edge in &e {
        for a in 0..3 {
            // axis = unit(a) × edge
            let mut axis = [0.0; 3];
            let (b, c2) = ((a + 1) % 3, (a + 2) % 3);
            axis[b] = -edge[c2];
            axis[c2] = edge[b];
            let p = |x: [f64; 3]| x[0] * axis[0] + x[1] * axis[1] + x[2] * axis[2];
            let (p0, p1, p2) = (p(v0), p(v1), p(v2));
            let r = h[0] * axis[0].abs() + h[1] * axis[1].abs() + h[2] * axis[2].abs();
            if p0.min(p1).min(p2) > r || p0.max(p1).max(p2) < -r {
                return false;
            }
        }
    }
    // 3. The triangle's plane.
    let n = [
        e[0][1] * e[1][2] - e[0][2] * e[1][1],
        e[0][2] * e[1][0] - e[0][0] * e[1][2],
        e[0][0] * e[1][1] - e[0][1] * e[1][0],
    ];
    let d = n[0] * v0[0] + n[1] * v0[1] + n[2] * v0[2];
    let r = h[0] * n[0].abs() + h[1] * n[1].abs() + h[2] * n[2].abs();
    d.abs() <= r
}

#[cfg(test)]
mod tests {
    use super::*;

    const C: [f64; 3] = [0.0; 3];
    const H: [f64; 3] = [1.0; 3];

    #[test]
    fn inside_and_outside() {
        assert!(tri_box_overlap(C, H, &[[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 0.5, 0.0]]));
        assert!(!tri_box_overlap(C, H, &[[2.0, 2.0, 2.0], [3.0, 2.0, 2.0], [2.0, 3.0, 2.0]]));
    }

    #[test]
    fn large_triangle_through_the_box_overlaps() {
        assert!(tri_box_overlap(C, H, &[[-10.0, -10.0, 0.2], [10.0, -10.0, 0.2], [0.0, 10.0, 0.2]]));
    }

    #[test]
    fn triangle_near_a_corner_is_separated_by_an_edge_axis() {
        // Its bounding box overlaps the box, but the plane x + y + z = 3.2 does not.
        assert!(!tri_box_overlap(C, H, &[[1.6, 1.6, 0.0], [0.0, 1.6, 1.6], [1.6, 0.0, 1.6]]));
        assert!(tri_box_overlap(C, H, &[[1.4, 1.4, 0.0], [0.0, 1.4, 1.4], [1.4, 0.0, 1.4]]));
    }

    #[test]
    fn touching_counts() {
        assert!(tri_box_overlap(C, H, &[[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0]]));
        assert!(tri_box_overlap(C, H, &[[1.0, 1.0, 1.0], [2.0, 1.0, 1.0], [2.0, 2.0, 1.0]]));
    }

    #[test]
    fn degenerate_triangles_are_conservative() {
        assert!(tri_box_overlap(C, H, &[[0.5; 3], [0.5; 3], [0.5; 3]]));
        assert!(!tri_box_overlap(C, H, &[[1.5; 3], [1.5; 3], [1.5; 3]]));
        assert!(tri_box_overlap(C, H, &[[-3.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 0.0, 0.0]]));
    }
}
