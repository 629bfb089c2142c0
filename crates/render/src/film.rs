//! The film: a width × height grid of linear RGB `f32` radiance, row-major, y down.

use dynray_scene::Color;

/// Linear RGB pixels, row 0 at the top of the image.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    pixels: Vec<Color>,
}

impl Film {
    /// A black film. A zero dimension gives an empty film (nothing to render or write).
    pub fn new(width: u32, height: u32) -> Self {
        Self { width, height, pixels: vec![Color::ZERO; width as usize * height as usize] }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// All pixels, row-major from the top-left corner.
    pub fn pixels(&self) -> &[Color] {
        &self.pixels
    }

    /// Pixel `(x, y)`; `None` outside the film.
    pub fn get(&self, x: u32, y: u32) -> Option<Color> {
        (x < self.width && y < self.height).then(|| self.pixels[self.index(x, y)])
    }

    /// Sets pixel `(x, y)`; writes outside the film are ignored (callers iterate the
    /// film's own bounds, so this never happens in the renderer).
    pub fn set(&mut self, x: u32, y: u32, c: Color) {
        if x < self.width && y < self.height {
            let i = self.index(x, y);
            self.pixels[i] = c;
        }
    }

    fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    /// The film as 8-bit sRGB, 3 bytes per pixel, row-major: what PNG and BMP files hold.
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|c| c.to_array().map(linear_to_srgb8)).collect()
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
