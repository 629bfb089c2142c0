//! Deterministic per-pixel sampling: where a pixel's samples fall, and the random numbers
//! an integrator draws for them.
//!
//! Every number depends only on (seed, pixel, sample index, draw), never on which thread
//! renders the pixel or in what order, so an image is the same whatever the thread count.
//!
//! - Sub-pixel positions: one sample is the pixel centre (the seeds' measurements and the
//!   golden images keep their one ray through each centre); `n > 1` samples are
//!   correlated multi-jittered (Kensler, "Correlated Multi-Jittered Sampling", Pixar
//!   tech memo 13-01, 2013): stratified in a near-square `m × k` grid *and* in both 1D
//!   projections, for any `n`, not only squares.
//! - Further dimensions (light samples, bounce directions): a PCG32 stream (O'Neill 2014,
//!   XSH-RR output) whose stream selector is the pixel and whose state is seeded by the
//!   sample index, so samples of one pixel are decorrelated from each other and from
//!   neighbouring pixels.

/// Random numbers for one pixel sample, seeded by `(seed, pixel, sample)`.
#[derive(Clone, Debug)]
pub struct Sampler {
    state: u64,
    inc: u64,
    /// Sub-pixel position of this sample, in `[0, 1)²` within its pixel.
    offset: (f32, f32),
    /// Samples of the pattern this one belongs to (`count` of [`Sampler::new`]).
    count: u32,
}

/// PCG32's multiplier (Knuth's MMIX LCG constant, as in the PCG reference code).
const PCG_MULT: u64 = 6_364_136_223_846_793_005;

impl Sampler {
    /// The sampler of sample `sample` out of `count` of pixel `(x, y)` of an image
    /// `width` pixels wide, under image seed `seed`.
    pub fn new(seed: u64, width: u32, x: u32, y: u32, sample: u32, count: u32) -> Self {
        let pixel = y as u64 * width as u64 + x as u64;
        let stream = mix64(seed ^ mix64(pixel.wrapping_add(0x9e37_79b9_7f4a_7c15)));
        let mut s = Self { state: 0, inc: (stream << 1) | 1, offset: (0.5, 0.5), count: count.max(1) };
        // PCG's seeding sequence: step, add the initial state, step.
        s.next_u32();
        s.state = s.state.wrapping_add(mix64(sample as u64 ^ seed.rotate_left(32)));
        s.next_u32();
        if count > 1 {
            // The pattern's scramble is per pixel so neighbouring pixels do not share it.
            let scramble = (stream ^ (stream >> 32)) as u32;
            s.offset = cmj(sample % count, count, scramble);
        }
        s
    }

    /// Where in its pixel this sample lies, `[0, 1)²` (the centre, `(0.5, 0.5)`, for a
    /// single sample per pixel).
    pub fn pixel_offset(&self) -> (f32, f32) {
        self.offset
    }

    /// How many samples of its pixel the pattern this sample belongs to has (at least
    /// 1): how finely the pixel is divided among them, which sizes each sample's texture
    /// footprint ([`crate::RayCone::for_samples`]).
    pub fn pattern_count(&self) -> u32 {
        self.count
    }

    /// The next 32 random bits.
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(PCG_MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// A uniform number in `[0, 1)` (24 random bits, so never 1.0 after rounding).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    /// Two uniform numbers in `[0, 1)`.
    pub fn next_2d(&mut self) -> (f32, f32) {
        let a = self.next_f32();
        (a, self.next_f32())
    }
}

/// The uniform number in `[0, 1)` with which seed 004's cumulative integrator chooses a
/// child at the hit of path `path` at ray level `level` of the camera sample whose key
/// is `key` (the first [`Sampler::next_u32`] of that sample's sampler).
///
/// Stateless, and built from 32-bit integer operations only, so that a GPU kernel
/// computes the same bits (crates/gpu/shaders/whitted_shade.wgsl `choice_random`):
/// three rounds of the PCG hash (Jarzynski & Olano, "Hash Functions for GPU Rendering",
/// JCGT 9(3), 2020: one PCG32 step then the RXS-M-XS output permutation), chained
/// `pcg(key ^ pcg(level ^ pcg(path)))`; the top 24 bits scaled by 2^-24 (exact in f32).
pub fn choice_random(key: u32, level: u32, path: u32) -> f32 {
    let h = pcg_hash(key ^ pcg_hash(level ^ pcg_hash(path)));
    (h >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// The PCG hash of Jarzynski & Olano (2020), a bijection of `u32`.
fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// SplitMix64's finaliser: a bijective 64-bit mix, so distinct pixels get distinct streams.
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Kensler's hashed permutation: a bijection of `0..len` chosen by `p`, computed without
/// a table (cycle-walking over the next power of two).
fn permute(mut i: u32, len: u32, p: u32) -> u32 {
    let mut w = len - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < len {
            break;
        }
    }
    (i.wrapping_add(p)) % len
}

/// Kensler's hashed uniform number in `[0, 1)` for index `i` under scramble `p`.
fn hashed_f32(mut i: u32, p: u32) -> f32 {
    i ^= p;
    i ^= i >> 17;
    i ^= i >> 10;
    i = i.wrapping_mul(0xb365_34e5);
    i ^= i >> 12;
    i ^= i >> 21;
    i = i.wrapping_mul(0x93fc_4795);
    i ^= 0xdf6e_307f;
    i ^= i >> 17;
    i = i.wrapping_mul(1 | p >> 18);
    (i >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// Sample `s` of `n` correlated multi-jittered points in the unit square (aspect 1),
/// scrambled by `p`.
fn cmj(s: u32, n: u32, p: u32) -> (f32, f32) {
    let m = ((n as f32).sqrt().ceil() as u32).max(1);
    let k = n.div_ceil(m);
    // The n samples take n of the m·k cells, chosen by the scramble. Permuting over n
    // only (Kensler's listing) always leaves the last row's cells empty when m·k > n, so
    // the bottom band of every pixel got too few samples (8 spp: a third too few in its
    // last ninth) and images were biased at edges; a Mitsuba comparison found it.
    let s = permute(s, m * k, p.wrapping_mul(0x5163_3e2d));
    let sx = permute(s % m, m, p.wrapping_mul(0x68bc_21eb));
    let sy = permute(s / m, k, p.wrapping_mul(0x02e5_be93));
    let jx = hashed_f32(s, p.wrapping_mul(0x967a_889b));
    let jy = hashed_f32(s, p.wrapping_mul(0x368c_c8b7));
    let x = ((s % m) as f32 + (sy as f32 + jx) / k as f32) / m as f32;
    let y = ((s / m) as f32 + (sx as f32 + jy) / m as f32) / k as f32;
    // Rounding can reach 1.0 exactly; keep the sample inside its pixel.
    (x.min(ONE_BELOW), y.min(ONE_BELOW))
}

/// The largest `f32` below 1.
const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sample_is_the_pixel_centre() {
        assert_eq!(Sampler::new(7, 640, 3, 4, 0, 1).pixel_offset(), (0.5, 0.5));
    }

    #[test]
    fn same_inputs_same_numbers_other_pixels_other_numbers() {
        let draw = |x, y, s| {
            let mut r = Sampler::new(1, 64, x, y, s, 16);
            (r.pixel_offset(), [r.next_u32(), r.next_u32(), r.next_u32()])
        };
        assert_eq!(draw(5, 6, 3), draw(5, 6, 3));
        assert_ne!(draw(5, 6, 3).1, draw(6, 5, 3).1);
        assert_ne!(draw(5, 6, 3).1, draw(5, 6, 4).1);
        assert_ne!(draw(5, 6, 3).0, draw(5, 6, 4).0);
    }

    #[test]
    fn multi_jittered_positions_are_stratified_in_both_projections() {
        for n in [2u32, 4, 5, 7, 8, 9, 16, 33, 64] {
            let pts: Vec<_> = (0..n).map(|s| Sampler::new(3, 10, 1, 2, s, n).pixel_offset()).collect();
            for &(x, y) in &pts {
                assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y), "n {n}: ({x}, {y})");
            }
            // When n = m·k exactly, every column and every row of the n-cell 1D
            // partitions holds one point (the "multi-jittered" property).
            let m = (n as f32).sqrt().ceil() as u32;
            if n % m == 0 {
                let mut xs: Vec<u32> = pts.iter().map(|p| (p.0 * n as f32) as u32).collect();
                let mut ys: Vec<u32> = pts.iter().map(|p| (p.1 * n as f32) as u32).collect();
                xs.sort_unstable();
                ys.sort_unstable();
                assert_eq!(xs, (0..n).collect::<Vec<_>>(), "n {n}: x strata");
                assert_eq!(ys, (0..n).collect::<Vec<_>>(), "n {n}: y strata");
            }
        }
    }

    #[test]
    fn uniform_numbers_stay_in_range_and_average_a_half() {
        let mut r = Sampler::new(9, 1, 0, 0, 0, 1);
        let n = 100_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let x = r.next_f32();
            assert!((0.0..1.0).contains(&x));
            sum += x as f64;
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.01, "{}", sum / n as f64);
    }

    /// Regression: with `m·k > n` cells (8, 128 spp…) the last row of cells was never
    /// used, so over many pixels the bottom band of a pixel was undersampled.
    #[test]
    fn positions_are_uniform_over_pixels_for_any_count() {
        for n in [2u32, 3, 5, 7, 8, 10, 128] {
            let (mut low, mut high, mut total) = (0u32, 0u32, 0u32);
            for px in 0..4000 {
                for s in 0..n {
                    let (x, y) = Sampler::new(5, 100, px % 100, px / 100, s, n).pixel_offset();
                    high += (y >= 0.9) as u32;
                    low += (x < 0.1) as u32;
                    total += 1;
                }
            }
            let (fh, fl) = (high as f64 / total as f64, low as f64 / total as f64);
            assert!(
                (fh - 0.1).abs() < 0.006 && (fl - 0.1).abs() < 0.006,
                "n {n}: {fh} of samples in y >= 0.9, {fl} in x < 0.1"
            );
        }
    }

    /// Pinned values: the GPU's `choice_random` must give these bits too (the GPU
    /// cumulative test compares images that depend on them).
    #[test]
    fn choice_numbers_are_pinned_and_uniform() {
        assert_eq!(pcg_hash(0), 129_708_002);
        assert_eq!(pcg_hash(1), 2_831_084_092);
        let (mut sum, n) = (0.0f64, 100_000u32);
        for i in 0..n {
            let u = choice_random(i / 7, i % 7 + 1, i % 3);
            assert!((0.0..1.0).contains(&u));
            sum += u as f64;
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.01, "{}", sum / n as f64);
        assert_ne!(choice_random(5, 2, 1).to_bits(), choice_random(5, 2, 2).to_bits());
        assert_ne!(choice_random(5, 2, 1).to_bits(), choice_random(5, 3, 1).to_bits());
    }

    #[test]
    fn permutation_is_a_bijection() {
        for len in [1u32, 2, 3, 10, 17, 64, 100] {
            let mut seen: Vec<u32> = (0..len).map(|i| permute(i, len, 0xdead_beef)).collect();
            seen.sort_unstable();
            assert_eq!(seen, (0..len).collect::<Vec<_>>());
        }
    }
}
