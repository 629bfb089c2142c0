//! Exact triangle–box overlap (separating-axis test of Akenine-Möller, 2001), in f64.
//!
//! Used only by the grid builder to decide which cells a triangle goes into. Any false
//! "overlap" costs a wasted reference; a false "no overlap" would lose hits, so the test
//! runs in f64 on a cell box already widened by `INSERT_SLACK`, which leaves rounding
//! (~1e-16 relative) no room to separate a triangle that touches the cell.

use dynray_geom::Triangle;

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

/// True when the triangle touches the closed box `centre ± half`.
pub fn triangle_overlaps_box(tri: &Triangle, centre: V, half: V) -> bool {
    let p = |v: dynray_geom::Vec3| sub([v.x as f64, v.y as f64, v.z as f64], centre);
    let v = [p(tri.p0), p(tri.p1), p(tri.p2)];
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
            let axis = cross(*edge, unit);
            if separated(&v, axis, half) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_geom::Vec3;

    #[test]
    fn separates_and_touches() {
        let t = Triangle::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0));
        // Box beyond the hypotenuse: bounding boxes overlap, the triangle does not.
        assert!(!triangle_overlaps_box(&t, [1.6, 1.6, 0.0], [0.3, 0.3, 0.3]));
        // Box touching the hypotenuse at one corner counts (closed boxes).
        assert!(triangle_overlaps_box(&t, [1.5, 1.5, 0.0], [0.5, 0.5, 0.5]));
        assert!(triangle_overlaps_box(&t, [0.5, 0.5, 0.0], [0.1, 0.1, 0.1]));
        // Box above the plane.
        assert!(!triangle_overlaps_box(&t, [0.5, 0.5, 1.0], [0.5, 0.5, 0.4]));
    }
}
