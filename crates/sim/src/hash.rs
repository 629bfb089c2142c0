//! The spatial hash of the seed's "body": points binned into cubic cells so that the
//! neighbours within a radius are found without scanning every point. Cells keep their
//! points in index order and queries return indices sorted, so everything built from a
//! query is the same whatever the thread count.

use glam::DVec3;
use std::collections::HashMap;

/// Points binned into cells of side `cell`.
#[derive(Clone, Debug)]
pub struct SpatialHash {
    cell: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
}

impl SpatialHash {
    /// Bins `points` into cells of side `cell` (> 0).
    pub fn new(points: &[DVec3], cell: f64) -> Self {
        let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (i, p) in points.iter().enumerate() {
            cells.entry(key(*p, cell)).or_default().push(i as u32);
        }
        Self { cell, cells }
    }

    /// Indices of the points of `points` (the slice the hash was built from) within
    /// `radius` of `p` (strictly closer), sorted, into `out` (cleared first).
    pub fn within(&self, points: &[DVec3], p: DVec3, radius: f64, out: &mut Vec<u32>) {
        out.clear();
        let lo = key(p - DVec3::splat(radius), self.cell);
        let hi = key(p + DVec3::splat(radius), self.cell);
        let r2 = radius * radius;
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    if let Some(list) = self.cells.get(&[x, y, z]) {
                        out.extend(list.iter().copied().filter(|&j| points[j as usize].distance_squared(p) < r2));
                    }
                }
            }
        }
        out.sort_unstable();
    }
}

fn key(p: DVec3, cell: f64) -> [i64; 3] {
    let k = (p / cell).floor();
    [k.x as i64, k.y as i64, k.z as i64]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_what_a_scan_finds() {
        let pts: Vec<DVec3> = (0..500)
            .map(|i| {
                let f = i as f64;
                DVec3::new((f * 0.37).sin() * 3.0, (f * 0.71).cos() * 2.0, (f * 0.13).sin())
            })
            .collect();
        let hash = SpatialHash::new(&pts, 0.4);
        let mut got = Vec::new();
        for (i, p) in pts.iter().enumerate().step_by(7) {
            hash.within(&pts, *p, 0.9, &mut got);
            let want: Vec<u32> =
                (0..pts.len() as u32).filter(|&j| pts[j as usize].distance_squared(*p) < 0.81).collect();
            assert_eq!(got, want, "point {i}");
        }
    }
}
