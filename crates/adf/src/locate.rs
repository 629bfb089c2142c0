//! Stackless point location (seed 001 §3.5): the deepest internal cell containing a
//! point, found by probing levels through the hash — `S(ℓ, p) = 2^ℓ + ⌊2^ℓ p⌋`, one Φ
//! and one H fetch per level — never by walking pointers. The leaf holding the point is
//! that cell's child (leaves are implicit: H stores internal cells only).
//!
//! Existence is monotone along a root-to-leaf path (a full tree), so the three searches
//! return the same cell: [`Search::Linear`] probes up from the root,
//! [`Search::Binary`] bisects the level range, [`Search::CoherentLinear`] starts at the
//! level found for the previous point and walks up or down from there.

use crate::Adf;
use dynray_geom::Vec3;

/// How point location searches the levels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Search {
    /// Level 1, 2, … until a cell is missing.
    Linear,
    /// Bisection of `1 ..= max_level − 1`.
    Binary,
    /// From the previous answer's level, up while cells exist or down until one does.
    CoherentLinear,
}

/// The deepest internal cell containing a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Located {
    /// Its level (the leaf is one deeper).
    pub level: u32,
    /// Its block in the voxel texture.
    pub block: u32,
    /// Levels probed (hash lookups) to find it.
    pub probes: u32,
}

impl Adf {
    /// The point's integer coordinates at the finest resolution, `⌊2^L p⌋` for `p` in the
    /// unit cube (clamped into `[0, 2^L)`, so `p = 1` stays in the last cell).
    #[inline]
    pub fn fine_coords(&self, u: Vec3) -> [u32; 3] {
        let n = (1u32 << self.max_level) as f32;
        let top = (1u32 << self.max_level) - 1;
        u.to_array().map(|c| ((c * n).max(0.0) as u32).min(top))
    }

    /// The block of the level-`level` cell containing fine coordinates `q`, if it is an
    /// internal cell.
    #[inline]
    pub(crate) fn probe(&self, level: u32, q: [u32; 3]) -> Option<u32> {
        let shift = self.max_level - level;
        self.hash.find(q.map(|c| (1 << level) + (c >> shift)))
    }

    /// The deepest internal cell containing fine coordinates `q`; `hint` is the level
    /// to start from for [`Search::CoherentLinear`] (and receives the answer's level).
    pub fn locate_fine(&self, q: [u32; 3], search: Search, hint: &mut u32) -> Located {
        let deepest = self.max_level - 1;
        // The root is always internal (the build splits it): level 0 needs no probe.
        let root = self.probe(0, q).unwrap_or(0);
        let found = match search {
            Search::Linear => {
                let (mut best, mut probes) = ((0, root), 0);
                for l in 1..=deepest {
                    probes += 1;
                    match self.probe(l, q) {
                        Some(b) => best = (l, b),
                        None => break,
                    }
                }
                Located { level: best.0, block: best.1, probes }
            }
            Search::Binary => {
                let (mut lo, mut hi, mut best, mut probes) = (1i64, deepest as i64, (0, root), 0);
                while lo <= hi {
                    let mid = (lo + hi) / 2;
                    probes += 1;
                    match self.probe(mid as u32, q) {
                        Some(b) => {
                            best = (mid as u32, b);
                            lo = mid + 1;
                        }
                        None => hi = mid - 1,
                    }
                }
                Located { level: best.0, block: best.1, probes }
            }
            Search::CoherentLinear => {
                let mut l = (*hint).min(deepest);
                let mut probes = 1;
                match if l == 0 { Some(root) } else { self.probe(l, q) } {
                    Some(mut b) => {
                        while l < deepest {
                            probes += 1;
                            match self.probe(l + 1, q) {
                                Some(nb) => {
                                    l += 1;
                                    b = nb;
                                }
                                None => break,
                            }
                        }
                        Located { level: l, block: b, probes }
                    }
                    None => loop {
                        l -= 1;
                        if l == 0 {
                            break Located { level: 0, block: root, probes };
                        }
                        probes += 1;
                        if let Some(b) = self.probe(l, q) {
                            break Located { level: l, block: b, probes };
                        }
                    },
                }
            }
        };
        *hint = found.level;
        found
    }
}
