//! The film: a width × height grid that accumulates radiance samples, row-major, y down.
//!
//! Each pixel keeps a sum of weighted samples and the sum of their weights (a box filter
//! one pixel wide: a sample counts towards the pixel it falls in, and only that one), so
//! anti-aliasing, progressive and multi-pass integrators all add into the same film and
//! the image is `sum / weight`. One sample of weight 1 per pixel resolves to that sample
//! exactly (`c / 1.0 == c`), which keeps one-sample renders bit-identical to the value
//! the integrator returned.

use dynray_scene::Color;

/// Accumulated samples, row 0 at the top of the image.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    sum: Vec<Color>,
    weight: Vec<f32>,
}

impl Film {
    /// An empty (black, zero-weight) film. A zero dimension gives a film without pixels
    /// (nothing to render or write).
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self { width, height, sum: vec![Color::ZERO; n], weight: vec![0.0; n] }
    }

    /// A film holding `sum` and `weight` per pixel (row-major), as another device
    /// accumulated them (the GPU's live image). Panics unless both have `width · height`
    /// entries.
    pub fn from_sums(width: u32, height: u32, sum: Vec<Color>, weight: Vec<f32>) -> Self {
        let n = width as usize * height as usize;
        assert!(
            sum.len() == n && weight.len() == n,
            "{} sums and {} weights for {width}x{height}",
            sum.len(),
            weight.len()
        );
        Self { width, height, sum, weight }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Every pixel's value (`sum / weight`, black where nothing was added), row-major
    /// from the top-left corner.
    pub fn pixels(&self) -> Vec<Color> {
        self.sum.iter().zip(&self.weight).map(|(&s, &w)| resolve(s, w)).collect()
    }

    /// Pixel `(x, y)`'s value; `None` outside the film.
    pub fn get(&self, x: u32, y: u32) -> Option<Color> {
        (x < self.width && y < self.height).then(|| {
            let i = self.index(x, y);
            resolve(self.sum[i], self.weight[i])
        })
    }

    /// Adds a sample of radiance `c` with weight `w` to pixel `(x, y)`; samples outside
    /// the film are ignored (callers iterate the film's own bounds).
    pub fn add(&mut self, x: u32, y: u32, c: Color, w: f32) {
        if x < self.width && y < self.height {
            let i = self.index(x, y);
            self.sum[i] += c * w;
            self.weight[i] += w;
        }
    }

    /// Adds `sum`, the total of samples whose weights add up to `weight`, to pixel
    /// `(x, y)` (what a tile computed for it); outside the film it is ignored.
    pub fn add_sum(&mut self, x: u32, y: u32, sum: Color, weight: f32) {
        if x < self.width && y < self.height {
            let i = self.index(x, y);
            self.sum[i] += sum;
            self.weight[i] += weight;
        }
    }

    /// Adds every pixel of `other` (its sums and weights) into this film: a progressive
    /// frame's samples into the accumulated image. Panics unless the sizes match.
    pub fn add_film(&mut self, other: &Film) {
        assert_eq!((self.width, self.height), (other.width, other.height), "films of different sizes");
        for (s, o) in self.sum.iter_mut().zip(&other.sum) {
            *s += *o;
        }
        for (w, o) in self.weight.iter_mut().zip(&other.weight) {
            *w += *o;
        }
    }

    /// Sets pixel `(x, y)` to exactly `c` (weight 1), discarding what it held.
    pub fn set(&mut self, x: u32, y: u32, c: Color) {
        if x < self.width && y < self.height {
            let i = self.index(x, y);
            self.sum[i] = c;
            self.weight[i] = 1.0;
        }
    }

    /// Adds every sample of `other` (a film of the same size: another pass) into this one.
    ///
    /// # Panics
    /// When the sizes differ: merging films of different images is a caller bug.
    pub fn merge(&mut self, other: &Film) {
        assert_eq!(
            (self.width, self.height),
            (other.width, other.height),
            "merging a {}x{} film into a {}x{} one",
            other.width,
            other.height,
            self.width,
            self.height
        );
        for (s, o) in self.sum.iter_mut().zip(&other.sum) {
            *s += *o;
        }
        for (w, o) in self.weight.iter_mut().zip(&other.weight) {
            *w += *o;
        }
    }

    /// Total weight added to pixel `(x, y)` (the sample count for unit weights).
    pub fn weight(&self, x: u32, y: u32) -> Option<f32> {
        (x < self.width && y < self.height).then(|| self.weight[self.index(x, y)])
    }

    fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    /// The film as 8-bit sRGB, 3 bytes per pixel, row-major: what PNG and BMP files hold.
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.pixels().iter().flat_map(|c| c.to_array().map(linear_to_srgb8)).collect()
    }
}

/// A pixel's value from its sums: a division, so one unit-weight sample comes back
/// unchanged; no weight means no sample, shown black.
fn resolve(sum: Color, weight: f32) -> Color {
    if weight > 0.0 {
        sum / weight
    } else {
        Color::ZERO
    }
}

/// Encodes one linear channel with the sRGB transfer curve (IEC 61966-2-1), clamped to
/// `[0, 1]` and rounded to 8 bits. NaN encodes as 0 so a bad pixel is visible as black
/// instead of poisoning the file.
///
/// sRGB rather than a plain 2.2 power: it is what viewers assume for untagged PNG/BMP,
/// and its linear toe keeps dark gradients from banding.
pub fn linear_to_srgb8(c: f32) -> u8 {
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5).clamp(0.0, 255.0) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_end_points_and_mid_grey() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(1.0), 255);
        assert_eq!(linear_to_srgb8(7.0), 255);
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        // 18 % grey is about 118 in sRGB.
        assert_eq!(linear_to_srgb8(0.18), 118);
    }

    #[test]
    fn samples_average_and_one_unit_sample_is_kept_bit_for_bit() {
        let mut f = Film::new(2, 1);
        let c = Color::new(0.1, 0.7, 1.0 / 3.0);
        f.add(0, 0, c, 1.0);
        assert_eq!(f.get(0, 0).unwrap().to_array().map(f32::to_bits), c.to_array().map(f32::to_bits));
        f.add(1, 0, Color::ONE, 1.0);
        f.add(1, 0, Color::ZERO, 1.0);
        f.add(1, 0, Color::splat(3.0), 2.0);
        assert_eq!(f.get(1, 0), Some(Color::splat(1.75)));
        assert_eq!(f.weight(1, 0), Some(4.0));
        let mut g = Film::new(2, 1);
        g.add(0, 0, Color::ZERO, 1.0);
        g.merge(&f);
        assert_eq!(g.get(0, 0), Some(c * 0.5));
        assert_eq!(Film::new(1, 1).get(0, 0), Some(Color::ZERO));
    }

    #[test]
    fn set_get_and_out_of_range() {
        let mut f = Film::new(3, 2);
        f.set(2, 1, Color::new(1.0, 2.0, 3.0));
        f.set(3, 0, Color::ONE);
        assert_eq!(f.get(2, 1), Some(Color::new(1.0, 2.0, 3.0)));
        assert_eq!(f.get(3, 0), None);
        assert_eq!(f.pixels()[5], Color::new(1.0, 2.0, 3.0));
        assert_eq!(f.to_srgb8().len(), 18);
    }
}
