//! Sampling a [`Texture`] at a uv: wrap modes (glTF's three), nearest or bilinear
//! filtering within a mip level, and trilinear filtering across levels for a lookup with
//! a footprint ([`Texture::sample_lod`]; the level of detail of a footprint is
//! [`super::TextureRef::lod`]).

use super::Texture;
use crate::Color;
use dynray_geom::Vec2;

/// What happens outside `[0, 1]`: glTF's `wrapS`/`wrapT` values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// Tile: `u` and `u + 1` look the same (glTF's default, OBJ's).
    #[default]
    Repeat,
    /// Clamp to the edge texels (MTL `-clamp on`).
    ClampToEdge,
    /// Tile, mirroring every other copy, so copies meet without a seam.
    MirroredRepeat,
}

impl Wrap {
    /// Texel index `i` wrapped into `0..n` (`n > 0`).
    fn index(self, i: i64, n: i64) -> i64 {
        match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::ClampToEdge => i.clamp(0, n - 1),
            Wrap::MirroredRepeat => {
                let k = i.rem_euclid(2 * n);
                if k < n {
                    k
                } else {
                    2 * n - 1 - k
                }
            }
        }
    }
}

/// How texels are combined between their centres, and across mip levels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    /// The texel the uv falls in (glTF `magFilter: NEAREST`), for pixel art; a lookup
    /// with a footprint reads the nearest mip level (GL's `NEAREST_MIPMAP_NEAREST`), so
    /// texels stay crisp and unblended.
    Nearest,
    /// Bilinear interpolation between the four nearest texel centres; a lookup with a
    /// footprint blends the two mip levels around its level of detail (trilinear, GL's
    /// `LINEAR_MIPMAP_LINEAR`).
    #[default]
    Bilinear,
}

/// A texture's sampling state, as a glTF sampler gives it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TextureSampler {
    /// Wrap along `u` (glTF `wrapS`).
    pub wrap_u: Wrap,
    /// Wrap along `v` (glTF `wrapT`).
    pub wrap_v: Wrap,
    /// Filter for magnification and minification alike.
    pub filter: Filter,
}

/// Coordinates beyond this many texels are clamped before the integer conversion; the
/// f32 uv has long lost sub-texel precision there anyway.
const FAR: f32 = (1u64 << 40) as f32;

impl Texture {
    /// The colour at `uv` (dynray's convention: `(0, 0)` bottom-left, `v` up; see the
    /// module docs), wrapped and filtered as `sampler` says, from the image itself (mip
    /// level 0: a point lookup). A non-finite uv component is read as 0, so a bad uv
    /// gives a colour of the texture, never NaN.
    pub fn sample(&self, uv: Vec2, sampler: &TextureSampler) -> Color {
        self.sample_level(0, uv, sampler)
    }

    /// The colour at `uv` for a lookup whose footprint is `lod` (level of detail:
    /// `log₂` of the footprint's width in texels of level 0, [`super::TextureRef::lod`]).
    /// `lod ≤ 0` (and NaN) is [`Texture::sample`] exactly, bit for bit; above it,
    /// [`Filter::Bilinear`] blends levels `⌊lod⌋` and `⌊lod⌋ + 1` by the fraction
    /// (trilinear) and [`Filter::Nearest`] reads level `round(lod)`. Past the last level
    /// (`+∞` included) the 1 × 1 level, the image's mean, is read.
    pub fn sample_lod(&self, uv: Vec2, sampler: &TextureSampler, lod: f32) -> Color {
        // `!(lod > 0)` is deliberate: NaN takes the point lookup.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if !(lod > 0.0) || self.levels() == 1 {
            return self.sample(uv, sampler);
        }
        let last = self.levels() - 1;
        let lod = lod.min(last as f32);
        match sampler.filter {
            Filter::Nearest => self.sample_level((lod.round() as usize).min(last), uv, sampler),
            Filter::Bilinear => {
                let k = lod.floor();
                let f = lod - k;
                let k = k as usize;
                let fine = self.sample_level(k, uv, sampler);
                if f == 0.0 || k >= last {
                    return fine;
                }
                fine * (1.0 - f) + self.sample_level(k + 1, uv, sampler) * f
            }
        }
    }

    /// [`Texture::sample`] on mip level `level` (which must exist): the level's own
    /// texel grid over the same uv square, wrapped by its own size.
    fn sample_level(&self, level: usize, uv: Vec2, sampler: &TextureSampler) -> Color {
        let (w, h) = self.level_size(level).expect("mip level in range");
        let (w, h) = (w as i64, h as i64);
        let finite = |c: f32| if c.is_finite() { c } else { 0.0 };
        // Image coordinates in texels: x to the right, y down from the top row.
        let x = (finite(uv.x) * w as f32).clamp(-FAR, FAR);
        let y = ((1.0 - finite(uv.y)) * h as f32).clamp(-FAR, FAR);
        let at = |i: i64, j: i64| {
            let (i, j) = (sampler.wrap_u.index(i, w), sampler.wrap_v.index(j, h));
            self.level_texel(level, i as u32, j as u32)
        };
        match sampler.filter {
            Filter::Nearest => at(x.floor() as i64, y.floor() as i64),
            Filter::Bilinear => {
                // Texel centres sit at half-integers.
                let (x, y) = (x - 0.5, y - 0.5);
                let (x0, y0) = (x.floor(), y.floor());
                let (fx, fy) = (x - x0, y - y0);
                let (i, j) = (x0 as i64, y0 as i64);
                let top = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
                let bottom = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
                top * (1.0 - fy) + bottom * fy
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2 × 2: top row red, green; bottom row blue, white.
    fn quad() -> Texture {
        let texels = vec![Color::X, Color::Y, Color::Z, Color::ONE];
        Texture::from_linear("quad", 2, 2, texels).unwrap()
    }

    /// 4 × 1 ramp of greys 0, 1, 2, 3.
    fn ramp() -> Texture {
        Texture::from_linear("ramp", 4, 1, (0..4).map(|i| Color::splat(i as f32)).collect()).unwrap()
    }

    fn with(wrap: Wrap, filter: Filter) -> TextureSampler {
        TextureSampler { wrap_u: wrap, wrap_v: wrap, filter }
    }

    fn close(a: Color, b: Color) -> bool {
        (a - b).abs().max_element() < 1e-5
    }

    #[test]
    fn v_runs_up_from_the_bottom_row() {
        let t = quad();
        let s = TextureSampler::default();
        // Texel centres: (¼, ¾) is the top-left texel, (¼, ¼) the bottom-left.
        assert_eq!(t.sample(Vec2::new(0.25, 0.75), &s), Color::X, "top-left is red");
        assert_eq!(t.sample(Vec2::new(0.75, 0.75), &s), Color::Y, "top-right is green");
        assert_eq!(t.sample(Vec2::new(0.25, 0.25), &s), Color::Z, "bottom-left is blue");
        assert_eq!(t.sample(Vec2::new(0.75, 0.25), &s), Color::ONE, "bottom-right is white");
        let n = with(Wrap::Repeat, Filter::Nearest);
        assert_eq!(t.sample(Vec2::new(0.01, 0.99), &n), Color::X);
        assert_eq!(t.sample(Vec2::new(0.01, 0.01), &n), Color::Z);
    }

    #[test]
    fn bilinear_weights_between_texel_centres() {
        let t = ramp();
        let s = with(Wrap::ClampToEdge, Filter::Bilinear);
        for i in 0..4 {
            let centre = (i as f32 + 0.5) / 4.0;
            assert_eq!(t.sample(Vec2::new(centre, 0.5), &s), Color::splat(i as f32), "texel {i} centre");
        }
        // Midway between centres 1 and 2 (u = 0.5), and a quarter of the way.
        assert!(close(t.sample(Vec2::new(0.5, 0.5), &s), Color::splat(1.5)));
        assert!(close(t.sample(Vec2::new(0.4375, 0.5), &s), Color::splat(1.25)));
        // In 2-D: the centre of the quad is the mean of its four texels.
        let q = quad().sample(Vec2::new(0.5, 0.5), &TextureSampler::default());
        assert!(close(q, (Color::X + Color::Y + Color::Z + Color::ONE) / 4.0), "{q}");
    }

    #[test]
    fn edges_follow_the_wrap_mode() {
        let t = ramp();
        let edge = Vec2::new(0.0, 0.5);
        // At u = 0 the sample is half texel 0 and half its neighbour across the edge.
        assert!(close(t.sample(edge, &with(Wrap::ClampToEdge, Filter::Bilinear)), Color::splat(0.0)));
        assert!(close(t.sample(edge, &with(Wrap::Repeat, Filter::Bilinear)), Color::splat(1.5)), "0 and 3");
        assert!(close(t.sample(edge, &with(Wrap::MirroredRepeat, Filter::Bilinear)), Color::splat(0.0)));
        assert!(close(t.sample(Vec2::new(1.0, 0.5), &with(Wrap::Repeat, Filter::Bilinear)), Color::splat(1.5)));
        assert!(close(t.sample(Vec2::new(1.0, 0.5), &with(Wrap::ClampToEdge, Filter::Bilinear)), Color::splat(3.0)));
    }

    #[test]
    fn wrap_modes_tile_clamp_and_mirror() {
        let t = ramp();
        for u in [0.1f32, 0.3, 0.55, 0.8, 0.97] {
            let v = 0.5;
            let rep = with(Wrap::Repeat, Filter::Bilinear);
            assert!(close(t.sample(Vec2::new(u + 1.0, v), &rep), t.sample(Vec2::new(u, v), &rep)));
            assert!(close(t.sample(Vec2::new(u - 3.0, v), &rep), t.sample(Vec2::new(u, v), &rep)));
            let mir = with(Wrap::MirroredRepeat, Filter::Bilinear);
            assert!(close(t.sample(Vec2::new(1.0 + u, v), &mir), t.sample(Vec2::new(1.0 - u, v), &mir)), "u = {u}");
            assert!(close(t.sample(Vec2::new(-u, v), &mir), t.sample(Vec2::new(u, v), &mir)), "u = {u}");
            assert!(close(t.sample(Vec2::new(2.0 + u, v), &mir), t.sample(Vec2::new(u, v), &mir)), "u = {u}");
            let clamp = with(Wrap::ClampToEdge, Filter::Nearest);
            assert_eq!(t.sample(Vec2::new(5.0 + u, v), &clamp), Color::splat(3.0));
            assert_eq!(t.sample(Vec2::new(-5.0 - u, v), &clamp), Color::splat(0.0));
        }
        // Mirror at the texel level: index -1 is texel 0, index 4 is texel 3, 5 is 2.
        assert_eq!(Wrap::MirroredRepeat.index(-1, 4), 0);
        assert_eq!(Wrap::MirroredRepeat.index(4, 4), 3);
        assert_eq!(Wrap::MirroredRepeat.index(5, 4), 2);
        assert_eq!(Wrap::MirroredRepeat.index(8, 4), 0);
        assert_eq!(Wrap::Repeat.index(-1, 4), 3);
        assert_eq!(Wrap::ClampToEdge.index(-7, 4), 0);
    }

    #[test]
    fn wrap_applies_per_axis() {
        let t = quad();
        let s = TextureSampler { wrap_u: Wrap::Repeat, wrap_v: Wrap::ClampToEdge, filter: Filter::Nearest };
        // u wraps to the other column; v clamps to the top row.
        assert_eq!(t.sample(Vec2::new(1.25, 7.0), &s), Color::X);
        assert_eq!(t.sample(Vec2::new(1.75, -7.0), &s), Color::ONE);
    }

    #[test]
    fn bad_uvs_give_texture_colours() {
        let t = quad();
        for s in [TextureSampler::default(), with(Wrap::MirroredRepeat, Filter::Nearest)] {
            for uv in [Vec2::NAN, Vec2::new(f32::INFINITY, -f32::INFINITY), Vec2::splat(3e38), Vec2::splat(-3e38)] {
                let c = t.sample(uv, &s);
                assert!(c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0, "{uv} gave {c}");
            }
        }
    }

    /// 8 × 8 checker of 1-texel squares, black and white.
    fn checker(n: u32) -> Texture {
        let texels = (0..n * n).map(|i| Color::splat(((i % n + i / n) % 2) as f32)).collect();
        Texture::from_linear("checker", n, n, texels).unwrap()
    }

    #[test]
    fn lod_zero_and_below_is_the_point_lookup_bit_for_bit() {
        let t = checker(8);
        for s in [TextureSampler::default(), with(Wrap::MirroredRepeat, Filter::Nearest)] {
            for uv in [Vec2::new(0.3, 0.7), Vec2::new(-1.2, 5.01), Vec2::new(0.5, 0.5)] {
                for lod in [0.0, -3.0, f32::NAN, f32::NEG_INFINITY] {
                    assert_eq!(t.sample_lod(uv, &s, lod), t.sample(uv, &s), "{uv} at {lod}");
                }
            }
        }
    }

    #[test]
    fn trilinear_blends_the_two_levels_around_the_lod() {
        let t = checker(8);
        let s = TextureSampler::default();
        // On a texel centre level 0 gives the texel (white here: x + y odd), every
        // coarser level of a 1-texel checker is grey.
        let uv = Vec2::new(1.5 / 8.0, 1.0 - 0.5 / 8.0);
        assert_eq!(t.sample_lod(uv, &s, 0.0), Color::ONE);
        assert!(close(t.sample_lod(uv, &s, 0.25), Color::splat(0.875)), "¾ of white, ¼ of grey");
        assert!(close(t.sample_lod(uv, &s, 1.0), Color::splat(0.5)));
        assert!(close(t.sample_lod(uv, &s, 2.7), Color::splat(0.5)));
        // Far past the last level (and +∞): the 1 × 1 mean.
        assert!(close(t.sample_lod(uv, &s, 40.0), Color::splat(0.5)));
        assert!(close(t.sample_lod(uv, &s, f32::INFINITY), Color::splat(0.5)));
        // Nearest rounds to a level: 0.4 is still level 0's crisp texel.
        let n = with(Wrap::Repeat, Filter::Nearest);
        assert_eq!(t.sample_lod(uv, &n, 0.4), Color::ONE);
        assert!(close(t.sample_lod(uv, &n, 0.6), Color::splat(0.5)));
    }

    #[test]
    fn coarse_levels_wrap_like_the_image() {
        // A 4 × 1 ramp: level 1 is [0.5, 2.5]; at u = 0 bilinear on level 1 reads half
        // of each edge texel under repeat, the first one under clamp and mirror.
        let t = ramp();
        assert_eq!(t.level_size(1), Some((2, 1)));
        let edge = Vec2::new(0.0, 0.5);
        assert!(close(t.sample_lod(edge, &with(Wrap::Repeat, Filter::Bilinear), 1.0), Color::splat(1.5)));
        assert!(close(t.sample_lod(edge, &with(Wrap::ClampToEdge, Filter::Bilinear), 1.0), Color::splat(0.5)));
        assert!(close(t.sample_lod(edge, &with(Wrap::MirroredRepeat, Filter::Bilinear), 1.0), Color::splat(0.5)));
        // Tiling is preserved on every level.
        let rep = with(Wrap::Repeat, Filter::Bilinear);
        for u in [0.1f32, 0.35, 0.8] {
            let uv = Vec2::new(u, 0.5);
            assert!(close(t.sample_lod(uv + Vec2::X, &rep, 1.5), t.sample_lod(uv, &rep, 1.5)), "u = {u}");
        }
    }

    #[test]
    fn without_mipmaps_every_footprint_reads_level_zero() {
        let t = checker(8).without_mipmaps();
        assert_eq!(t.levels(), 1);
        let uv = Vec2::new(1.5 / 8.0, 1.0 - 0.5 / 8.0);
        assert_eq!(t.sample_lod(uv, &TextureSampler::default(), 3.0), Color::ONE);
        assert_eq!(checker(8).levels(), 4);
        assert_eq!(checker(8).memory_bytes(), (64 + 16 + 4 + 1) * 12);
    }
}
