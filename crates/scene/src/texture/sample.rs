//! Sampling a [`Texture`] at a uv: wrap modes (glTF's three) and nearest or bilinear
//! filtering. There are no mipmaps: a texture seen from far away aliases, and
//! supersampling (`--spp`) is what smooths it.

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

/// How texels are combined between their centres.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    /// The texel the uv falls in (glTF `magFilter: NEAREST`), for pixel art and
    /// lookup tables.
    Nearest,
    /// Bilinear interpolation between the four nearest texel centres.
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
    /// module docs), wrapped and filtered as `sampler` says. A non-finite uv component
    /// is read as 0, so a bad uv gives a colour of the texture, never NaN.
    pub fn sample(&self, uv: Vec2, sampler: &TextureSampler) -> Color {
        let finite = |c: f32| if c.is_finite() { c } else { 0.0 };
        let (w, h) = (self.width() as i64, self.height() as i64);
        // Image coordinates in texels: x to the right, y down from the top row.
        let x = (finite(uv.x) * w as f32).clamp(-FAR, FAR);
        let y = ((1.0 - finite(uv.y)) * h as f32).clamp(-FAR, FAR);
        let at = |i: i64, j: i64| {
            let (i, j) = (sampler.wrap_u.index(i, w), sampler.wrap_v.index(j, h));
            self.texel(i as u32, j as u32)
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
}
