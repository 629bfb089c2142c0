//! Charts of a run, each written as SVG and (with a font) PNG: build time against
//! triangle count and Mrays/s per structure and scene. (The presets draw their own charts
//! with `line_chart`.)

use crate::legend::{self, Entry, Swatch};
use crate::output::{write_atomic, write_png};
use crate::results::SceneResult;
use anyhow::{anyhow, Result};
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// A chart that can draw itself on any plotters backend.
pub trait Chart {
    /// Pixel size of the PNG (and the SVG's nominal size).
    fn size(&self) -> (u32, u32);
    /// Draws onto `root` (already filled white).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// `e.to_string()`, for plotters' backend-generic errors.
pub fn err<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Writes `chart` as `dir/stem.svg` and, when `png`, `dir/stem.png`; returns the names.
pub fn save<C: Chart>(chart: &C, dir: &Path, stem: &str, png: bool) -> Result<Vec<String>> {
    let size = chart.size();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{stem}.svg: {e}"))?;
        chart.draw(&root).map_err(|e| anyhow!("{stem}.svg: {e}"))?;
        root.present().map_err(|e| anyhow!("{stem}.svg: {e}"))?;
    }
    write_atomic(&dir.join(format!("{stem}.svg")), svg.as_bytes())?;
    let mut names = vec![format!("{stem}.svg")];
    if png {
        let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
            root.fill(&WHITE).map_err(|e| anyhow!("{stem}.png: {e}"))?;
            chart.draw(&root).map_err(|e| anyhow!("{stem}.png: {e}"))?;
            root.present().map_err(|e| anyhow!("{stem}.png: {e}"))?;
        }
        write_png(&dir.join(format!("{stem}.png")), &buf, size.0, size.1)?;
        names.push(format!("{stem}.png"));
    }
    Ok(names)
}

/// Colour of series `i` (plotters' 20-colour palette, distinct and print-safe).
pub fn series_color(i: usize) -> RGBColor {
    let c = Palette99::pick(i).to_rgba();
    RGBColor(c.0, c.1, c.2)
}

/// What the standard run's charts draw: its scenes, in the order of its structures and
/// ray kinds (the report's `scenes` and `config`).
#[derive(Clone, Copy)]
pub struct StandardRun<'a> {
    /// The measured scenes.
    pub scenes: &'a [SceneResult],
    /// The structures, in colour order.
    pub accels: &'a [String],
    /// The ray kinds, one panel each.
    pub rays: &'a [String],
    /// Threads the run used.
    pub threads: usize,
    /// The standard run's camera (`--framing`).
    pub framing: &'a str,
}

/// Build time (ms) against triangle count, one series per structure, log–log.
pub struct BuildVsTriangles<'a>(pub StandardRun<'a>);

impl Chart for BuildVsTriangles<'_> {
    fn size(&self) -> (u32, u32) {
        (760 + legend::width(&accel_legend(&self.0, Swatch::Line)), 600)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let entries = accel_legend(&self.0, Swatch::Line);
        let (root, strip) = root.split_horizontally(root.dim_in_pixel().0.saturating_sub(legend::width(&entries)));
        legend::draw(&strip, &entries, 70)?;
        let root = &root;
        let scenes = self.0.scenes;
        let accels: Vec<String> = self.0.accels.to_vec();
        let pts = |a: &str| -> Vec<(f64, f64)> {
            scenes
                .iter()
                .filter_map(|s| {
                    s.structures.iter().find(|r| r.accel == a).map(|r| (s.triangles as f64, r.build_ms.max(1e-3)))
                })
                .collect()
        };
        let all: Vec<(f64, f64)> = accels.iter().flat_map(|a| pts(a)).collect();
        let (x0, x1) = bounds(all.iter().map(|p| p.0));
        let (y0, y1) = bounds(all.iter().map(|p| p.1));
        let mut chart = ChartBuilder::on(root)
            .caption("Build time vs triangle count", ("sans-serif", 26))
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d((x0 / 1.5..x1 * 1.5).log_scale(), (y0 / 2.0..y1 * 2.0).log_scale())
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("triangles")
            .y_desc("build time (ms, median)")
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 18))
            .x_label_formatter(&|v| short(*v))
            .y_label_formatter(&|v| short(*v))
            .draw()
            .map_err(err)?;
        for (i, a) in accels.iter().enumerate() {
            let c = series_color(i);
            let mut p = pts(a);
            p.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart.draw_series(LineSeries::new(p.clone(), c.stroke_width(2))).map_err(err)?;
            chart.draw_series(p.into_iter().map(|q| Circle::new(q, 4, c.filled()))).map_err(err)?;
        }
        Ok(())
    }
}

/// Mrays/s per structure and scene: one panel per ray kind, grouped bars.
pub struct MraysChart<'a>(pub StandardRun<'a>);

impl Chart for MraysChart<'_> {
    /// One full-width panel per ray kind, so each scene's group of bars has room for its
    /// name (two columns of panels crowded eight scene names into overlapping labels).
    fn size(&self) -> (u32, u32) {
        let rows = self.0.rays.len().max(1) as u32;
        (1260 + legend::width(&accel_legend(&self.0, Swatch::Bar)), 60 + 320 * rows)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let r = &self.0;
        let title = format!("Throughput (Mrays/s, {} threads, framing {}, higher is better)", r.threads, r.framing);
        let root = root.titled(&title, ("sans-serif", 26)).map_err(err)?;
        let entries = accel_legend(r, Swatch::Bar);
        let (root, strip) = root.split_horizontally(root.dim_in_pixel().0.saturating_sub(legend::width(&entries)));
        legend::draw(&strip, &entries, 50)?;
        let kinds = r.rays;
        let panels = root.split_evenly((kinds.len().max(1), 1));
        let accels = r.accels;
        let ns = r.scenes.len().max(1);
        for (kind, area) in kinds.iter().zip(panels.iter()) {
            // Each scene's share of hits beside its name: throughput depends on it.
            let names: Vec<String> = r
                .scenes
                .iter()
                .map(|sc| match sc.structures.iter().find_map(|st| st.kinds.iter().find(|k| &k.kind == kind)) {
                    Some(k) if k.rays > 0 => {
                        let word = if kind == "shadow" { "occluded" } else { "hit" };
                        format!("{} ({:.0} % {word})", sc.name, 100.0 * k.hits as f64 / k.rays as f64)
                    }
                    _ => sc.name.clone(),
                })
                .collect();
            let value = |si: usize, a: &str| -> f64 {
                r.scenes[si]
                    .structures
                    .iter()
                    .find(|s| s.accel == a)
                    .and_then(|s| s.kinds.iter().find(|k| &k.kind == kind))
                    .map(|k| k.mrays_per_s)
                    .unwrap_or(0.0)
            };
            let ymax = (0..r.scenes.len())
                .flat_map(|si| accels.iter().map(move |a| value(si, a)))
                .fold(0.0f64, f64::max)
                .max(1e-6)
                * 1.1;
            // A label at the centre of each scene's group of bars, and nowhere else.
            let centres: Vec<f64> = (0..ns).map(|i| i as f64 + 0.5).collect();
            let mut chart = ChartBuilder::on(area)
                .caption(format!("{kind} rays"), ("sans-serif", 20))
                .margin(12)
                .x_label_area_size(32)
                .y_label_area_size(70)
                .build_cartesian_2d(TickedAxis::new(0.0..ns as f64, centres), 0.0..ymax)
                .map_err(err)?;
            chart
                .configure_mesh()
                .disable_x_mesh()
                .x_label_formatter(&|x| names.get(x.floor() as usize).cloned().unwrap_or_default())
                .y_desc("Mrays/s")
                .y_label_formatter(&|v| short(*v))
                .label_style(("sans-serif", 14))
                .axis_desc_style(("sans-serif", 16))
                .draw()
                .map_err(err)?;
            let na = accels.len().max(1) as f64;
            let w = 0.8 / na;
            for (ai, a) in accels.iter().enumerate() {
                let c = series_color(ai);
                let bars = (0..r.scenes.len()).map(|si| {
                    let x = si as f64 + 0.1 + ai as f64 * w;
                    Rectangle::new([(x, 0.0), (x + w * 0.92, value(si, a))], c.filled())
                });
                chart.draw_series(bars).map_err(err)?;
            }
        }
        Ok(())
    }
}

/// The run's structures, in colour order, as legend entries.
fn accel_legend(r: &StandardRun<'_>, swatch: Swatch) -> Vec<Entry> {
    let e = |(i, a): (usize, &String)| Entry { name: a.clone(), color: series_color(i), swatch };
    r.accels.iter().enumerate().map(e).collect()
}

/// A linear `f64` axis whose ticks are given: labels sit exactly at a sweep's values or at
/// the centre of a bar group. (plotters' `with_key_points` does this for integer axes, but
/// over `f64` it loses the label formatter `configure_mesh` needs.)
pub struct TickedAxis {
    inner: RangedCoordf64,
    ticks: Vec<f64>,
}

impl TickedAxis {
    /// `range` with tick marks and labels at `ticks` (and no light grid lines).
    pub fn new(range: std::ops::Range<f64>, ticks: Vec<f64>) -> Self {
        TickedAxis { inner: range.into(), ticks }
    }
}

impl Ranged for TickedAxis {
    type ValueType = f64;
    // Labels come from the chart's own formatter; the default (Debug) is never shown.
    type FormatOption = DefaultFormatting;

    fn range(&self) -> std::ops::Range<f64> {
        self.inner.range()
    }
    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }
    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.ticks.clone()
        }
    }
}

/// Smallest and largest finite positive value (1, 10 when there is none).
fn bounds(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v.filter(|x| x.is_finite() && *x > 0.0).fold((f64::MAX, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    if hi <= 0.0 {
        (1.0, 10.0)
    } else {
        (lo, hi)
    }
}

/// `12k`, `1.5M`, `0.3`: short tick labels.
pub fn short(v: f64) -> String {
    let a = v.abs();
    if a >= 1e6 {
        format!("{}M", trim(v / 1e6))
    } else if a >= 1e3 {
        format!("{}k", trim(v / 1e3))
    } else {
        trim(v)
    }
}

fn trim(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}
