//! Mipmaps: the box-filtered pyramid every [`Texture`] builds when it is made, so that a
//! lookup whose footprint covers many texels reads their average instead of one of
//! them (the moiré of a far floor).
//!
//! Each level halves the previous one's sides, rounding **up** (`⌈n / 2⌉`, never below 1)
//! down to 1 × 1. A texel of the smaller level is the exact area average of the part of
//! the larger level it covers: for an even side that is the classic pair average; for an
//! odd side `n` each new texel covers `n / ⌈n / 2⌉ < 2` old texels, the ones it cuts
//! counting by the fraction they overlap (a polyphase box filter). So
//! - every level has the mean of the image (no brightening or darkening with distance);
//! - a level reads no texel outside the image, so one pyramid is right for every wrap
//!   mode: a material's sampler wraps each level at lookup time, and the average of a
//!   tiled (or mirrored, or clamped) image is the tiled coarse level.
//!
//! Rounding up keeps level `k`'s texels no larger than `2^k` texels of level 0, so the
//! level a lookup picks by the nominal `2^k` never blurs more than asked. Texels are
//! linear RGB (sRGB is decoded at load, `decode.rs`), so averaging is in linear light.
//! The pyramid costs a third of the image's memory on top of it.

use crate::Color;

/// One level of the pyramid below level 0: `width × height` texels, row-major from the
/// top row like the image.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct MipLevel {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<Color>,
}

/// The side of the level below one of side `n`: `⌈n / 2⌉`, at least 1.
pub(super) fn half(n: u32) -> u32 {
    n.div_ceil(2).max(1)
}

/// Levels 1, 2, … down to 1 × 1 of the `width × height` image `texels` (level 0, which
/// the texture keeps itself); empty for a 1 × 1 image.
pub(super) fn pyramid(width: u32, height: u32, texels: &[Color]) -> Vec<MipLevel> {
    debug_assert_eq!(texels.len(), width as usize * height as usize, "{width} × {height} image");
    let mut levels: Vec<MipLevel> = Vec::new();
    let (mut w, mut h) = (width, height);
    while w > 1 || h > 1 {
        let src = levels.last().map_or(texels, |l| &l.texels[..]);
        let next = shrink(w, h, src);
        (w, h) = (next.width, next.height);
        levels.push(next);
    }
    levels
}

/// For each texel of a line of `m` texels standing for a line of `n` (`m ≤ n`), the
/// source texels it covers and their weights: the overlap of `[j, j + 1)` with the
/// output texel's span `[i · n/m, (i + 1) · n/m)`, divided by the span's length.
/// Computed in units of `1/m` of a source texel, so the overlaps are exact integers.
fn box_weights(n: u32, m: u32) -> Vec<Vec<(usize, f32)>> {
    let (n, m) = (n as u64, m as u64);
    (0..m)
        .map(|i| {
            // The output texel spans [i·n, (i+1)·n) in these units; source texel j spans
            // [j·m, (j+1)·m).
            let (a, b) = (i * n, (i + 1) * n);
            (a / m..b.div_ceil(m))
                .filter_map(|j| {
                    let overlap = b.min((j + 1) * m).saturating_sub(a.max(j * m));
                    (overlap > 0).then(|| (j as usize, (overlap as f64 / n as f64) as f32))
                })
                .collect()
        })
        .collect()
}

/// The level below the `w × h` level `src`: rows shrunk first, then columns.
fn shrink(w: u32, h: u32, src: &[Color]) -> MipLevel {
    let (nw, nh) = (half(w), half(h));
    let (wx, wy) = (box_weights(w, nw), box_weights(h, nh));
    let (w, nw_us) = (w as usize, nw as usize);
    // Along x: h rows of nw texels.
    let mut rows = Vec::with_capacity(h as usize * nw_us);
    for row in src.chunks_exact(w) {
        rows.extend(wx.iter().map(|taps| taps.iter().fold(Color::ZERO, |s, &(j, k)| s + row[j] * k)));
    }
    // Along y: nh rows of nw texels.
    let mut texels = Vec::with_capacity(nh as usize * nw_us);
    for taps in &wy {
        for x in 0..nw_us {
            texels.push(taps.iter().fold(Color::ZERO, |s, &(j, k)| s + rows[j * nw_us + x] * k));
        }
    }
    MipLevel { width: nw, height: nh, texels }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mean(t: &[Color]) -> Color {
        t.iter().fold(Color::ZERO, |s, c| s + *c) / t.len() as f32
    }

    fn close(a: Color, b: Color, tol: f32) -> bool {
        (a - b).abs().max_element() <= tol
    }

    /// A deterministic, uneven image (no two texels alike along a row).
    fn noise(w: u32, h: u32) -> Vec<Color> {
        (0..w * h)
            .map(|i| {
                let x = i.wrapping_mul(2_654_435_761) >> 8;
                Color::new((x % 997) as f32 / 997.0, (x % 631) as f32 / 631.0, (i % 7) as f32)
            })
            .collect()
    }

    #[test]
    fn sizes_halve_rounding_up_down_to_one_texel() {
        let sides = |w: u32, h: u32| -> Vec<(u32, u32)> {
            pyramid(w, h, &vec![Color::ONE; (w * h) as usize]).iter().map(|l| (l.width, l.height)).collect()
        };
        assert_eq!(sides(8, 8), vec![(4, 4), (2, 2), (1, 1)]);
        assert_eq!(sides(5, 3), vec![(3, 2), (2, 1), (1, 1)]);
        assert_eq!(sides(8, 1), vec![(4, 1), (2, 1), (1, 1)]);
        assert_eq!(sides(1, 7), vec![(1, 4), (1, 2), (1, 1)]);
        assert!(sides(1, 1).is_empty(), "a 1 × 1 image is its own last level");
        // Levels are ⌈log₂ max side⌉: 512 × 512 has 9 below it.
        assert_eq!(sides(512, 512).len(), 9);
        assert_eq!(sides(513, 2).len(), 10);
    }

    #[test]
    fn power_of_two_levels_average_two_by_two_blocks() {
        let t = noise(4, 4);
        let l = &pyramid(4, 4, &t)[0];
        for (y, x) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            let at = |dx: usize, dy: usize| t[(2 * y + dy) * 4 + 2 * x + dx];
            let want = (at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1)) / 4.0;
            assert!(close(l.texels[y * 2 + x], want, 1e-6), "texel ({x}, {y})");
        }
    }

    #[test]
    fn every_level_keeps_the_mean_whatever_the_sizes() {
        for (w, h) in [(7, 5), (3, 1), (1, 9), (33, 17), (64, 48), (2, 3)] {
            let t = noise(w, h);
            let m0 = mean(&t);
            for (k, l) in pyramid(w, h, &t).iter().enumerate() {
                assert_eq!(l.texels.len(), (l.width * l.height) as usize);
                assert!(close(mean(&l.texels), m0, 1e-5), "{w} × {h} level {}: {} vs {m0}", k + 1, mean(&l.texels));
            }
        }
    }

    #[test]
    fn odd_sides_weight_the_cut_texel_by_its_overlap() {
        // 3 → 2: each new texel covers 1.5 old ones: a whole one and half the middle.
        let t = [Color::splat(0.0), Color::splat(3.0), Color::splat(6.0)];
        let l = &pyramid(3, 1, &t)[0];
        assert!(close(l.texels[0], Color::splat((0.0 + 0.5 * 3.0) / 1.5), 1e-6), "{}", l.texels[0]);
        assert!(close(l.texels[1], Color::splat((0.5 * 3.0 + 6.0) / 1.5), 1e-6), "{}", l.texels[1]);
        // 5 → 3 over the ramp 0..4: spans of 5/3 texels, [1 × 0 + ⅔ × 1], [⅓ × 1 + 2 +
        // ⅓ × 3], [⅔ × 3 + 4], each divided by 5/3: still a ramp (step 1.6).
        let ramp: Vec<Color> = (0..5).map(|i| Color::splat(i as f32)).collect();
        let l = &pyramid(5, 1, &ramp)[0];
        let want = [0.4, 2.0, 3.6];
        for (got, want) in l.texels.iter().zip(want) {
            assert!(close(*got, Color::splat(want), 1e-5), "{got} vs {want}");
        }
        assert_eq!(box_weights(5, 3).iter().map(|t| t.len()).collect::<Vec<_>>(), vec![2, 3, 2]);
    }

    #[test]
    fn a_one_texel_checker_averages_to_grey_on_every_level() {
        let (w, h) = (16, 12);
        let t: Vec<Color> = (0..w * h).map(|i| Color::splat(((i % w + i / w) % 2) as f32)).collect();
        for l in pyramid(w, h, &t) {
            for c in &l.texels {
                assert!(close(*c, Color::splat(0.5), 1e-6), "{} × {}: {c}", l.width, l.height);
            }
        }
    }
}
