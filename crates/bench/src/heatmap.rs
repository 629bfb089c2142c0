//! Traversal-cost heat maps: per pixel, the nodes visited plus triangles tested by the
//! primary ray, colour-mapped (viridis, dark = cheap, yellow = expensive) with a colour
//! bar and a title, as seed 004's Figure 6 shows them.

use crate::charts::err;
use crate::output::write_png;
use anyhow::{anyhow, Result};
use plotters::prelude::*;
use plotters::style::colors::colormaps::ViridisRGB;
use std::path::Path;

/// Smallest width the map is scaled up to (nearest neighbour), so tiny bench images
/// stay readable.
const MIN_MAP_WIDTH: u32 = 640;
/// Width of the colour-bar panel.
const BAR_PANEL: u32 = 150;
/// Height of the title band.
const TITLE: u32 = 70;

/// The value the colour scale tops out at (the engine's, which the viewer's live heat
/// map shares; pixels above it take the top colour, and the bar's label says so).
pub use dynray_engine::heat::scale_max;

/// A heat map measured and waiting to be drawn: maps of one run are drawn together, on
/// one colour scale, so that colours compare across structures and scenes.
pub struct Pending {
    /// Where the PNG goes.
    pub path: std::path::PathBuf,
    /// Work per pixel, row-major.
    pub work: Vec<u32>,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The map's title.
    pub title: String,
}

/// Draws every map of `maps` on one colour scale: the top colour at [`scale_max`] of all
/// their pixels together.
pub fn write_all(maps: &[Pending]) -> Result<()> {
    let all: Vec<u32> = maps.iter().flat_map(|m| m.work.iter().copied()).collect();
    let top = scale_max(&all);
    for m in maps {
        write(&m.path, &m.work, m.width, m.height, &m.title, Scale { top, shared_by: maps.len() })?;
    }
    Ok(())
}

/// The colour scale of a map: its top value, and how many maps share it.
#[derive(Clone, Copy, Debug)]
pub struct Scale {
    /// The value drawn in the top colour (higher values too).
    pub top: u32,
    /// Maps drawn on this scale (1: the map's own).
    pub shared_by: usize,
}

/// Draws the heat map of `work` (row-major, `width` × `height`) with `title` on `scale`
/// and writes it as PNG to `path`.
pub fn write(path: &Path, work: &[u32], width: u32, height: u32, title: &str, scale: Scale) -> Result<()> {
    anyhow::ensure!(
        work.len() == width as usize * height as usize,
        "heat map: {} values for {width}x{height}",
        work.len()
    );
    let Scale { top, shared_by } = scale;
    let top = top.max(1);
    let scale = MIN_MAP_WIDTH.div_ceil(width.max(1)).max(1);
    let (mw, mh) = (width * scale, height * scale);
    let size = (mw + BAR_PANEL + 30, mh + TITLE + 20);
    let clipped = work.iter().any(|&w| w > top);
    let mean = work.iter().map(|&w| w as f64).sum::<f64>() / work.len().max(1) as f64;
    let max = work.iter().copied().max().unwrap_or(0);
    let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        draw(&root, work, (width, height, scale), (top, shared_by), clipped, (mean, max), title)
            .map_err(|e| anyhow!("{}: {e}", path.display()))?;
        root.present().map_err(|e| anyhow!("{}: {e}", path.display()))?;
    }
    write_png(path, &buf, size.0, size.1)
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    work: &[u32],
    (width, height, scale): (u32, u32, u32),
    (top, shared_by): (u32, usize),
    clipped: bool,
    (mean, max): (f64, u32),
    title: &str,
) -> Result<(), String> {
    root.draw_text(title, &("sans-serif", 22).into_font().color(&BLACK), (12, 8)).map_err(err)?;
    let sub = format!("nodes visited + triangles tested per primary ray; mean {mean:.1}, max {max}");
    root.draw_text(&sub, &("sans-serif", 16).into_font().color(&BLACK), (12, 38)).map_err(err)?;
    let (x0, y0) = (10i32, TITLE as i32);
    for y in 0..height {
        for x in 0..width {
            let w = work[(y * width + x) as usize];
            let c = ViridisRGB::get_color((w.min(top) as f64 / top as f64).clamp(0.0, 1.0));
            for dy in 0..scale {
                for dx in 0..scale {
                    root.draw_pixel((x0 + (x * scale + dx) as i32, y0 + (y * scale + dy) as i32), &c).map_err(err)?;
                }
            }
        }
    }
    // Colour bar: a chart whose y axis is the work scale, filled with the colour map.
    let bar_x = x0 + (width * scale) as i32 + 10;
    let bar_area = root.clone().shrink((bar_x as u32, y0 as u32), (BAR_PANEL, height * scale));
    let shared = if shared_by > 1 { format!("; one scale for the run's {shared_by} maps") } else { String::new() };
    let label = if clipped {
        format!("nodes + triangles (≥ {top}: top colour{shared})")
    } else if shared_by > 1 {
        format!("nodes + triangles ({})", &shared[2..])
    } else {
        "nodes + triangles".into()
    };
    let mut chart = ChartBuilder::on(&bar_area)
        .margin_top(6)
        .margin_bottom(6)
        .y_label_area_size(0)
        .right_y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0f64, 0.0..top as f64)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(label)
        .y_label_formatter(&|v| format!("{v:.0}"))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    let steps = 256;
    chart
        .draw_series((0..steps).map(|i| {
            let (a, b) = (i as f64 / steps as f64, (i + 1) as f64 / steps as f64);
            Rectangle::new([(0.0, a * top as f64), (1.0, b * top as f64)], ViridisRGB::get_color(a).filled())
        }))
        .map_err(err)?;
    Ok(())
}
