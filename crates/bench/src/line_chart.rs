//! A generic chart of line series in side-by-side panels (one panel per scene, say), for
//! the presets' sweeps: seed 000's leaf-size sweep, seed 004's speed-up by resolution.

use crate::charts::{err, series_color, short, Chart, TickedAxis};
use crate::legend::{self, Entry, Swatch};
use plotters::coord::Shift;
use plotters::prelude::*;

/// One line: a name, its points, and whether it is a reference level (drawn as a thin line
/// without markers).
pub struct Series {
    /// Legend text.
    pub name: String,
    /// Points (x, y); non-finite or non-positive y (on a log axis) are skipped.
    pub points: Vec<(f64, f64)>,
    /// A horizontal reference (e.g. the kd-tree's figure in a BIH sweep).
    pub reference: bool,
}

/// One panel.
pub struct Panel {
    /// Panel title.
    pub title: String,
    /// Lines of the panel; colours are given by position, so equal positions across
    /// panels mean the same thing.
    pub series: Vec<Series>,
}

/// Panels side by side under a caption, sharing axis descriptions.
pub struct LineChart {
    /// Caption over all panels.
    pub caption: String,
    /// X axis description.
    pub x_desc: String,
    /// Y axis description.
    pub y_desc: String,
    /// Base-2 logarithmic x axis with ticks at powers of two (resolutions).
    pub log2_x: bool,
    /// Logarithmic y axis for panels whose values span more than a decade (builds next to
    /// renders); a panel with a narrower span stays linear, where a log axis would show
    /// no tick labels. The axis description then says "(log scale)".
    pub log_y: bool,
    /// Start a linear y axis at zero (speed-ups, times); otherwise fit the data.
    pub y_from_zero: bool,
    /// The panels.
    pub panels: Vec<Panel>,
}

impl Chart for LineChart {
    fn size(&self) -> (u32, u32) {
        (620 * self.panels.len().clamp(1, 3) as u32 + 40 + legend::width(&self.legend()), 560)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let body = root.titled(&self.caption, ("sans-serif", 22)).map_err(err)?;
        let entries = self.legend();
        let legend_w = legend::width(&entries);
        let (plots, strip) = body.split_horizontally(body.dim_in_pixel().0.saturating_sub(legend_w));
        // The first row sits level with the top of the plots (below the panel titles).
        legend::draw(&strip, &entries, 50)?;
        let areas = plots.split_evenly((1, self.panels.len().max(1)));
        for (panel, area) in self.panels.iter().zip(&areas) {
            self.draw_panel(panel, area)?;
        }
        Ok(())
    }
}

/// X ticks: every distinct x when there are few (a sweep's MaxPrims, a resolution, a
/// level), else about eight at a round step.
/// Ticks along an axis are at least its span over this apart, so labels never overlap
/// (timings 19.19 and 23.34 ms on a 19–298 ms axis once printed over each other).
const MAX_TICKS: f64 = 12.0;

/// `sorted` thinned so that neighbours are at least `gap` apart, keeping the first and
/// the last.
fn spaced(sorted: &[f64], gap: f64) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::with_capacity(sorted.len());
    for &x in sorted {
        match out.last() {
            Some(&prev) if x - prev < gap => {
                // The last value always gets its tick, in place of a too-close one.
                if x == sorted[sorted.len() - 1] && out.len() > 1 {
                    out.pop();
                    out.push(x);
                }
            }
            _ => out.push(x),
        }
    }
    out
}

fn x_ticks(xs: &[f64], xmin: f64, xmax: f64) -> Vec<f64> {
    let mut d: Vec<f64> = xs.to_vec();
    d.sort_by(f64::total_cmp);
    d.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs().max(1.0));
    if d.len() <= 16 {
        return spaced(&d, (xmax - xmin) / MAX_TICKS);
    }
    let raw = (xmax - xmin) / 8.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * mag).find(|s| *s >= raw).unwrap_or(10.0 * mag);
    let first = (xmin / step).ceil() as i64;
    let last = (xmax / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

impl LineChart {
    /// One legend for every panel: series at the same position are the same thing in
    /// every panel (that is what gives them the same colour), so the entry at position `i`
    /// is the first panel's series `i` that has points.
    fn legend(&self) -> Vec<Entry> {
        let n = self.panels.iter().map(|p| p.series.len()).max().unwrap_or(0);
        (0..n)
            .filter_map(|i| {
                let s = self.panels.iter().filter_map(|p| p.series.get(i)).find(|s| !s.points.is_empty())?;
                let swatch = if s.reference { Swatch::Reference } else { Swatch::Line };
                Some(Entry { name: s.name.clone(), color: series_color(i), swatch })
            })
            .collect()
    }

    fn draw_panel<DB: DrawingBackend>(&self, p: &Panel, area: &DrawingArea<DB, Shift>) -> Result<(), String> {
        // A log2 x axis is drawn as a linear axis over log2(x), labelled 2^k.
        let tx = |x: f64| if self.log2_x { x.max(1e-300).log2() } else { x };
        let ok = |y: f64| y.is_finite() && (!self.log_y || y > 0.0);
        let series: Vec<Series> = p
            .series
            .iter()
            .map(|s| Series {
                name: s.name.clone(),
                points: s.points.iter().filter(|(x, y)| x.is_finite() && ok(*y)).map(|&(x, y)| (tx(x), y)).collect(),
                reference: s.reference,
            })
            .collect();
        let pts = || series.iter().flat_map(|s| s.points.iter().copied());
        let (xmin, xmax) = pts().fold((f64::MAX, f64::MIN), |(a, b), (x, _)| (a.min(x), b.max(x)));
        let (ymin, ymax) = pts().fold((f64::MAX, f64::MIN), |(a, b), (_, y)| (a.min(y), b.max(y)));
        if xmin > xmax {
            return Ok(());
        }
        let xs: Vec<f64> = pts().map(|(x, _)| x).collect();
        let pad = ((xmax - xmin) * 0.04).max(0.25);
        let xr = TickedAxis::new(xmin - pad..xmax + pad, x_ticks(&xs, xmin, xmax));
        let mut b = ChartBuilder::on(area);
        b.caption(&p.title, ("sans-serif", 17)).margin(12).x_label_area_size(45).y_label_area_size(60);
        let log2 = self.log2_x;
        let xfmt = move |v: &f64| if log2 { short(2f64.powf(*v)) } else { short(*v) };
        let panel = Panel { title: p.title.clone(), series };
        if self.log_y && ymin > 0.0 && ymax / ymin > 10.0 {
            let mut chart = b.build_cartesian_2d(xr, (ymin / 1.3..ymax * 1.5).log_scale()).map_err(err)?;
            chart
                .configure_mesh()
                .x_desc(&self.x_desc)
                .y_desc(format!("{} (log scale)", self.y_desc).trim())
                .x_label_formatter(&xfmt)
                .y_label_formatter(&|v| short(*v))
                .label_style(("sans-serif", 13))
                .draw()
                .map_err(err)?;
            draw_series(&mut chart, &panel)
        } else {
            let ylo = if self.y_from_zero { 0.0 } else { ymin - (ymax - ymin).max(ymax.abs() * 0.05) * 0.1 };
            let yhi = ymax + (ymax - ylo).max(1e-9) * 0.12;
            let mut chart = b.build_cartesian_2d(xr, ylo..yhi).map_err(err)?;
            chart
                .configure_mesh()
                .x_desc(&self.x_desc)
                .y_desc(&self.y_desc)
                .x_label_formatter(&xfmt)
                .y_label_formatter(&|v| short(*v))
                .label_style(("sans-serif", 13))
                .draw()
                .map_err(err)?;
            draw_series(&mut chart, &panel)
        }
    }
}

/// The panel's lines and markers on an already configured chart (linear or log y).
fn draw_series<'a, DB: DrawingBackend + 'a, X: Ranged<ValueType = f64>, Y: Ranged<ValueType = f64>>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    p: &Panel,
) -> Result<(), String> {
    for (i, s) in p.series.iter().enumerate() {
        if s.points.is_empty() {
            continue; // nothing measured (its colour stays reserved, as in the other panels)
        }
        let c = series_color(i);
        let style = if s.reference { c.stroke_width(1) } else { c.stroke_width(2) };
        chart.draw_series(LineSeries::new(s.points.clone(), style)).map_err(err)?;
        if !s.reference {
            chart.draw_series(s.points.iter().map(|&q| Circle::new(q, 3, c.filled()))).map_err(err)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {

    #[test]
    fn data_point_ticks_are_thinned_so_labels_do_not_overlap() {
        let xs = [19.19, 23.34, 43.29, 59.66, 97.78, 298.28];
        assert_eq!(super::x_ticks(&xs, 19.19, 298.28), [19.19, 43.29, 97.78, 298.28]);
        assert_eq!(super::x_ticks(&[1.0, 2.0, 3.0], 1.0, 3.0), [1.0, 2.0, 3.0]);
        // The last point keeps its tick even when close to the one before.
        assert_eq!(super::x_ticks(&[0.0, 50.0, 99.0, 100.0], 0.0, 100.0), [0.0, 50.0, 100.0]);
    }

    use super::*;

    #[test]
    fn few_distinct_x_are_the_ticks_many_get_a_round_step() {
        assert_eq!(x_ticks(&[1.0, 5.0, 5.0, 10.0, 30.0, 1.0], 1.0, 30.0), vec![1.0, 5.0, 10.0, 30.0]);
        let frames: Vec<f64> = (1..=60).map(f64::from).collect();
        assert_eq!(x_ticks(&frames, 1.0, 60.0), vec![10.0, 20.0, 30.0, 40.0, 50.0, 60.0]);
    }
}
