//! A chart's legend, drawn in a strip of its own beside the plots: a legend inside a plot
//! hides the lines or bars under it, and a margin reserved inside the axis range (the
//! first version) left a stretch of empty axis that read as missing data.

use plotters::coord::Shift;
use plotters::prelude::*;

/// What an entry's sample looks like.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Swatch {
    /// A measured series: a thick line with a marker.
    Line,
    /// A reference level: a thin line without a marker.
    Reference,
    /// A bar.
    Bar,
}

/// One legend row.
#[derive(Clone, Debug)]
pub struct Entry {
    /// Text.
    pub name: String,
    /// Colour of the series.
    pub color: RGBColor,
    /// Sample drawn before the text.
    pub swatch: Swatch,
}

const FONT_PX: u32 = 14;
const ROW_PX: i32 = 22;
const SAMPLE_PX: i32 = 26;

/// Width the strip needs for `entries`, from the text's length (a chart's size is fixed
/// before anything is drawn, so this is an estimate: DejaVu Sans averages under 0.62 em per
/// character).
pub fn width(entries: &[Entry]) -> u32 {
    let chars = entries.iter().map(|e| e.name.chars().count()).max().unwrap_or(0) as u32;
    (chars * FONT_PX * 62 / 100 + SAMPLE_PX as u32 + 36).clamp(120, 420)
}

/// Draws the entries top-down in `area`, starting `top` pixels below its top edge.
pub fn draw<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, entries: &[Entry], top: i32) -> Result<(), String> {
    let font = ("sans-serif", FONT_PX).into_font().color(&BLACK);
    for (i, e) in entries.iter().enumerate() {
        let y = top + i as i32 * ROW_PX;
        let (x0, x1) = (8, 8 + SAMPLE_PX);
        let c = e.color;
        match e.swatch {
            Swatch::Line => {
                area.draw(&PathElement::new(vec![(x0, y), (x1, y)], c.stroke_width(3))).map_err(|e| e.to_string())?;
                area.draw(&Circle::new(((x0 + x1) / 2, y), 3, c.filled())).map_err(|e| e.to_string())?;
            }
            Swatch::Reference => {
                area.draw(&PathElement::new(vec![(x0, y), (x1, y)], c.stroke_width(1))).map_err(|e| e.to_string())?;
            }
            Swatch::Bar => {
                area.draw(&Rectangle::new([(x0 + 6, y - 7), (x1 - 6, y + 7)], c.filled()))
                    .map_err(|e| e.to_string())?;
            }
        }
        let text_h = area.estimate_text_size(&e.name, &font).map_err(|e| e.to_string())?.1 as i32;
        area.draw(&Text::new(e.name.clone(), (x1 + 8, y - text_h / 2), font.clone())).map_err(|e| e.to_string())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn width_grows_with_the_longest_name_within_bounds() {
        let e = |n: &str| Entry { name: n.into(), color: BLACK, swatch: Swatch::Line };
        assert_eq!(width(&[]), 120);
        let short = width(&[e("bvh")]);
        let long = width(&[e("bvh"), e("kd-tree Ropes++: time to image")]);
        assert!(long > short, "{long} <= {short}");
        assert_eq!(width(&[e(&"x".repeat(500))]), 420);
    }
}
