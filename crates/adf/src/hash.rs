//! The cell table H and the offset table Φ: Lefebvre and Hoppe's perfect spatial hash
//! with seed 001's modification (§3.4).
//!
//! A key `k` (a cell's `2^ℓ + ⌊2^ℓ p⌋`, per component) goes to slot
//! `h(k) = ((k mod w) + (x, y, z)) mod m̄` of the `m̄³` table H, where
//! `(x, y, z, w) = Φ[k mod r̄]`. Lefebvre–Hoppe is the case `w = m̄`. Two keys congruent
//! both mod `m̄` and mod `r̄` share a Φ entry and a `k mod m̄`, so no translation
//! separates them (the seed's failure on deep octrees); the per-entry `w` (coprime with
//! `m̄` and `r̄`, smaller than `m̄`) is chosen so that the keys of the entry differ mod `w`.
//!
//! Generation (§3.4.2): `m̄` is the smallest edge with `m̄³ ≥ n`; `r̄` starts at
//! `⌈∛(n/6)⌉` (Lefebvre–Hoppe's σ = 1/(2d)) coprime with `m̄`. The Φ entries are solved
//! greedily, most populated first: compute `w` (Algorithm 3.1), then try translations
//! from a random one onwards, linearly, until every key of the entry lands on a free
//! slot. A failed attempt is retried with another random stream, then with a larger
//! `r̄`; past the budget generation fails with [`AdfError::HashNotFound`]. The random
//! streams are fixed (seeded by the attempt number), so the tables are reproducible.
//!
//! Each H entry holds a 4-byte identifier of its key (the low 10 bits of the three
//! components: exact for keys below 1024, i.e. internal cells down to level 9 and trees
//! of level 10, the seed's layout) and the key's block. Deeper trees (to
//! [`crate::MAX_LEVEL`]) have keys up to `2^15`; for them H gains a second 4-byte word
//! per slot with the components' higher bits ([`PerfectHash::high_ids`], empty for
//! trees of level 10 or less). An empty slot has both words 0 (real keys have every
//! component ≥ 1, so one of the words is not), so a query for a cell that does not
//! exist is answered by one mismatching fetch.

use crate::AdfError;
use bytemuck::{Pod, Zeroable};

/// One entry of H: which key lives in the slot and where its children's voxels are.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct CellEntry {
    /// [`key_id`] of the cell's key; 0 for an empty slot.
    pub id: u32,
    /// The cell's block in the voxel texture (its children's 3×3×3 samples).
    pub block: u32,
}

/// One entry of Φ: the translation `(x, y, z)` and the modulus `w` of its keys.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct PhiEntry {
    /// Translation, each component in `0..m̄`.
    pub t: [u16; 3],
    /// Modulus, `1..=m̄` (`m̄`: plain Lefebvre–Hoppe).
    pub w: u16,
}

// 8 bytes each: an RG32UI and an RGBA16UI texel.
const _: () = assert!(std::mem::size_of::<CellEntry>() == 8 && std::mem::size_of::<PhiEntry>() == 8);

/// The 4-byte identifier of a key: the low 10 bits of each component (the whole key
/// for components below 1024).
#[inline]
pub fn key_id(k: [u32; 3]) -> u32 {
    debug_assert!(k.iter().all(|&c| (1..1 << 20).contains(&c)), "key {k:?} outside the identifiers");
    (k[0] & 1023) | (k[1] & 1023) << 10 | (k[2] & 1023) << 20
}

/// The second identifier word of a key: the components' bits above the tenth (0 for
/// keys below 1024).
#[inline]
pub fn key_high_id(k: [u32; 3]) -> u32 {
    (k[0] >> 10) | (k[1] >> 10) << 10 | (k[2] >> 10) << 20
}

/// The key two identifier words were made from.
#[inline]
pub fn key_of_id(id: u32, high: u32) -> [u32; 3] {
    [0, 10, 20].map(|s| ((id >> s) & 1023) | ((high >> s) & 1023) << 10)
}

/// Attempts per offset-table size before it grows.
const TRIES_PER_SIZE: u32 = 3;
/// Offset-table sizes tried before giving up.
const SIZES: u32 = 12;

/// The two tables and their edges.
#[derive(Clone, Debug, PartialEq)]
pub struct PerfectHash {
    /// Edge of H (`m̄`).
    pub(crate) m: u32,
    /// Edge of Φ (`r̄`).
    pub(crate) r: u32,
    /// `r̄³` entries, x fastest.
    pub(crate) phi: Vec<PhiEntry>,
    /// `m̄³` entries, x fastest.
    pub(crate) table: Vec<CellEntry>,
    /// Per slot of `table`, the key's [`key_high_id`]; empty when every key is below
    /// 1024 (trees of level 10 or less).
    pub(crate) high: Vec<u32>,
    /// Attempts generation took (1 = the first succeeded).
    pub(crate) attempts: u32,
}

/// Which hash to generate: the seed's or the original (for measurements).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HashVariant {
    /// Seed 001's: a per-entry modulus `w`.
    Modified,
    /// Lefebvre–Hoppe 2006: `w = m̄` everywhere.
    LefebvreHoppe,
}

impl PerfectHash {
    /// Edge of H.
    pub fn table_edge(&self) -> u32 {
        self.m
    }

    /// Edge of Φ.
    pub fn offset_edge(&self) -> u32 {
        self.r
    }

    /// Φ, `r̄³` entries, x fastest (what a device uploads).
    pub fn offsets(&self) -> &[PhiEntry] {
        &self.phi
    }

    /// H, `m̄³` entries, x fastest (what a device uploads).
    pub fn entries(&self) -> &[CellEntry] {
        &self.table
    }

    /// The second identifier word of every slot of H, x fastest; empty for trees of
    /// level 10 or less (what a device uploads beside H).
    pub fn high_ids(&self) -> &[u32] {
        &self.high
    }

    /// The stored keys, in slot order.
    pub fn keys(&self) -> Vec<[u32; 3]> {
        (0..self.table.len()).filter_map(|s| self.key_at(s)).collect()
    }

    /// The key stored in slot `s`, `None` for an empty slot.
    #[inline]
    pub(crate) fn key_at(&self, s: usize) -> Option<[u32; 3]> {
        let id = self.table.get(s)?.id;
        let high = self.high.get(s).copied().unwrap_or(0);
        (id != 0 || high != 0).then(|| key_of_id(id, high))
    }

    /// Attempts generation took.
    pub fn attempts(&self) -> u32 {
        self.attempts
    }

    /// Bytes of H (with its second identifier words, if any) and of Φ.
    pub fn memory_bytes(&self) -> (usize, usize) {
        (self.table.len() * 8 + self.high.len() * 4, self.phi.len() * 8)
    }

    #[inline]
    fn phi_index(&self, k: [u32; 3]) -> usize {
        let r = self.r;
        ((k[0] % r) + r * ((k[1] % r) + r * (k[2] % r))) as usize
    }

    /// The slot of key `k` in H.
    #[inline]
    pub fn slot(&self, k: [u32; 3]) -> usize {
        let e = self.phi.get(self.phi_index(k)).copied().unwrap_or_default();
        let (w, m) = (e.w.max(1) as u32, self.m);
        let s = [0, 1, 2].map(|c| ((k[c] % w) + e.t[c] as u32) % m);
        (s[0] + m * (s[1] + m * s[2])) as usize
    }

    /// The block of the cell with key `k`, or `None` when no such cell is stored: one Φ
    /// fetch and one H fetch.
    #[inline]
    pub fn find(&self, k: [u32; 3]) -> Option<u32> {
        let s = self.slot(k);
        let e = self.table.get(s)?;
        let high = self.high.get(s).copied().unwrap_or(0);
        (e.id == key_id(k) && high == key_high_id(k)).then_some(e.block)
    }

    /// A perfect hash of `keys` (distinct, components in `1..2^20`), key `i` mapped to
    /// block `i`.
    pub fn generate(keys: &[[u32; 3]], variant: HashVariant) -> Result<Self, AdfError> {
        let n = keys.len();
        let mut m = ((n.max(1)) as f64).cbrt().ceil() as u32;
        while (m as usize).pow(3) < n {
            m += 1;
        }
        while m > 1 && ((m - 1) as usize).pow(3) >= n {
            m -= 1;
        }
        let mut r = coprime_from((((n as f64) / 6.0).cbrt().ceil() as u32).max(1), m);
        let mut attempts = 0;
        for _ in 0..SIZES {
            for _ in 0..TRIES_PER_SIZE {
                attempts += 1;
                if let Some(phi) = attempt(keys, m, r, variant, 0x9E37_79B9_7F4A_7C15 ^ attempts as u64) {
                    let slots = (m as usize).pow(3);
                    let wide = keys.iter().any(|k| key_high_id(*k) != 0);
                    let high = if wide { vec![0; slots] } else { Vec::new() };
                    let mut h = Self { m, r, phi, table: vec![CellEntry::default(); slots], high, attempts };
                    for (i, &k) in keys.iter().enumerate() {
                        let s = h.slot(k);
                        debug_assert!(h.key_at(s).is_none(), "two keys in slot {s}");
                        h.table[s] = CellEntry { id: key_id(k), block: i as u32 };
                        if wide {
                            h.high[s] = key_high_id(k);
                        }
                    }
                    return Ok(h);
                }
            }
            r = coprime_from((r + 1).max((r as f64 * 1.2).ceil() as u32), m);
        }
        Err(AdfError::HashNotFound { cells: n, attempts, largest: r })
    }
}

/// The smallest value `≥ from` coprime with `m`.
fn coprime_from(from: u32, m: u32) -> u32 {
    (from..).find(|&r| gcd(r, m) == 1).unwrap_or(from)
}

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// SplitMix64: a small fixed random stream (reproducible across platforms and crate
/// versions, which a library generator does not promise).
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// True when two of `keys` share `(k mod w) mod m` (Algorithm 3.1's CONTAINS_COLLISIONS).
fn collides(keys: &[[u32; 3]], w: u32, m: u32) -> bool {
    let h = |k: &[u32; 3]| k.map(|c| (c % w) % m);
    keys.iter().enumerate().any(|(i, a)| keys[..i].iter().any(|b| h(a) == h(b)))
}

/// Algorithm 3.1 (COMPUTE_W) with the coprimality the text asks for: `m̄` when the keys
/// do not collide under it, else the smallest `w < m̄` coprime with `m̄` and `r̄` that
/// separates them; `None` when none does (or for the unmodified hash).
fn compute_w(keys: &[[u32; 3]], m: u32, r: u32, variant: HashVariant) -> Option<u32> {
    if !collides(keys, m, m) {
        return Some(m);
    }
    if variant == HashVariant::LefebvreHoppe {
        return None;
    }
    (2..m).find(|&w| gcd(w, m) == 1 && gcd(w, r) == 1 && !collides(keys, w, m))
}

/// One greedy attempt (module docs); the offset table, or `None` when an entry finds no
/// translation.
fn attempt(keys: &[[u32; 3]], m: u32, r: u32, variant: HashVariant, seed: u64) -> Option<Vec<PhiEntry>> {
    let r3 = (r as usize).pow(3);
    let m3 = (m as usize).pow(3);
    let bucket = |k: &[u32; 3]| ((k[0] % r) + r * ((k[1] % r) + r * (k[2] % r))) as usize;
    // Counting sort of the keys by Φ entry.
    let mut start = vec![0u32; r3 + 1];
    for k in keys {
        start[bucket(k) + 1] += 1;
    }
    for i in 0..r3 {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut sorted = vec![[0u32; 3]; keys.len()];
    for k in keys {
        let b = bucket(k);
        sorted[fill[b] as usize] = *k;
        fill[b] += 1;
    }
    let mut order: Vec<u32> = (0..r3 as u32).filter(|&q| start[q as usize + 1] > start[q as usize]).collect();
    // Most populated first; equal sizes by index, so the order is fixed.
    order.sort_by_key(|&q| std::cmp::Reverse(start[q as usize + 1] - start[q as usize]));

    let mut rng = SplitMix(seed);
    let mut occupied = vec![false; m3];
    let mut phi = vec![PhiEntry { t: [0; 3], w: m as u16 }; r3];
    let mut bases: Vec<[u32; 3]> = Vec::new();
    let mut slots: Vec<usize> = Vec::new();
    for q in order {
        let ks = &sorted[start[q as usize] as usize..start[q as usize + 1] as usize];
        let w = compute_w(ks, m, r, variant)?;
        bases.clear();
        bases.extend(ks.iter().map(|k| k.map(|c| c % w)));
        let from = (rng.next() % m3 as u64) as usize;
        let mut found = None;
        for j in 0..m3 {
            let tl = (from + j) % m3;
            let t =
                [(tl % m as usize) as u32, ((tl / m as usize) % m as usize) as u32, (tl / (m as usize).pow(2)) as u32];
            slots.clear();
            let free = bases.iter().all(|b| {
                let s = [0, 1, 2].map(|c| (b[c] + t[c]) % m);
                let s = (s[0] + m * (s[1] + m * s[2])) as usize;
                slots.push(s);
                !occupied[s]
            });
            if free {
                found = Some(t);
                break;
            }
        }
        let t = found?;
        for &s in &slots {
            occupied[s] = true;
        }
        phi[q as usize] = PhiEntry { t: t.map(|c| c as u16), w: w as u16 };
    }
    Some(phi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_is_found_and_others_are_not() {
        // Keys of two levels of a dense octree corner plus scattered deep ones.
        let mut keys = Vec::new();
        for l in 0..5u32 {
            let n = 1 << l;
            for z in 0..n {
                for y in 0..n {
                    for x in 0..n {
                        if (x + y + z) % 3 == 0 || l < 3 {
                            keys.push([n + x, n + y, n + z]);
                        }
                    }
                }
            }
        }
        let h = PerfectHash::generate(&keys, HashVariant::Modified).unwrap();
        let mut seen = vec![false; h.table.len()];
        for (i, &k) in keys.iter().enumerate() {
            assert_eq!(h.find(k), Some(i as u32), "{k:?}");
            assert!(!std::mem::replace(&mut seen[h.slot(k)], true), "collision at {k:?}");
        }
        assert_eq!(h.find([16, 17, 16]), None, "(1+0+1) % 3 != 0: not stored");
        let k = [5, 1023, 77];
        assert_eq!((key_of_id(key_id(k), key_high_id(k)), key_high_id(k)), (k, 0));
        let deep = [1 << 15, 40_000, 1024];
        assert_eq!(key_of_id(key_id(deep), key_high_id(deep)), deep);
        assert_ne!(key_high_id(deep), 0);
    }

    #[test]
    fn compute_w_picks_a_coprime_modulus_where_lefebvre_hoppe_collides() {
        // Keys 2 apart collide mod m̄ = 2 in one Φ entry (r̄ = 1): no translation separates
        // them, and no w < 2 exists, so both variants must grow r̄ — and still find every key.
        let keys = [[2, 2, 2], [4, 2, 2], [2, 4, 2], [3, 3, 3], [5, 5, 5]];
        for variant in [HashVariant::LefebvreHoppe, HashVariant::Modified] {
            let h = PerfectHash::generate(&keys, variant).unwrap();
            assert!(h.r > 1, "{variant:?}");
            for (i, &k) in keys.iter().enumerate() {
                assert_eq!(h.find(k), Some(i as u32));
            }
        }
        assert_eq!(compute_w(&keys[..3], 2, 1, HashVariant::Modified), None, "no w < 2");
        assert_eq!(compute_w(&[[2, 2, 2], [8, 2, 2]], 6, 1, HashVariant::Modified), Some(5));
        assert_eq!(compute_w(&[[2, 2, 2], [8, 2, 2]], 6, 1, HashVariant::LefebvreHoppe), None);
    }
}
