//! `--timings FILE.csv` and the `t` key: one row per frame with the frame's split (pose,
//! physics, structure update, trace/shade, present), its size and rays, written
//! atomically (a temporary file renamed).

use anyhow::Result;
use std::path::Path;

/// One frame's figures.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameRow {
    /// Frame number, from 0.
    pub frame: u64,
    /// Scene time shown, seconds.
    pub time: f32,
    /// Samples per pixel the image holds after the frame.
    pub samples: u32,
    /// Rendered size.
    pub width: u32,
    /// Rendered size.
    pub height: u32,
    /// Posing and simulating, ms.
    pub pose_ms: f64,
    /// The simulation's part, ms.
    pub physics_ms: f64,
    /// The structure's update, ms (0 when none ran).
    pub update_ms: f64,
    /// What the update did (`refit`, `rebuild`, or empty).
    pub update: String,
    /// Tracing and shading, ms.
    pub render_ms: f64,
    /// Heat map or boxes, ms.
    pub view_ms: f64,
    /// Upload, panel and present, ms.
    pub present_ms: f64,
    /// The whole frame, ms.
    pub total_ms: f64,
    /// Rays traced.
    pub rays: u64,
    /// Where the image shown was resolved: `device` (the GPU backend's, on the window's
    /// device, no read-back) or `host` (a film uploaded).
    pub image: &'static str,
}

const HEADER: &str = "frame,time_s,samples,width,height,pose_ms,physics_ms,update_ms,update,render_ms,view_ms,present_ms,total_ms,rays,mrays_per_s,image";

impl FrameRow {
    fn csv(&self) -> String {
        let mrays = if self.render_ms > 0.0 { self.rays as f64 / self.render_ms / 1e3 } else { 0.0 };
        format!(
            "{},{},{},{},{},{:.3},{:.3},{:.3},{},{:.3},{:.3},{:.3},{:.3},{},{:.3},{}",
            self.frame,
            self.time,
            self.samples,
            self.width,
            self.height,
            self.pose_ms,
            self.physics_ms,
            self.update_ms,
            self.update,
            self.render_ms,
            self.view_ms,
            self.present_ms,
            self.total_ms,
            self.rays,
            mrays,
            self.image
        )
    }
}

/// Writes `rows` as CSV to `path` (temporary name, then renamed).
pub fn write(path: &Path, rows: &[FrameRow]) -> Result<()> {
    let mut text = String::with_capacity(64 * (rows.len() + 1));
    text.push_str(HEADER);
    text.push('\n');
    for r in rows {
        text.push_str(&r.csv());
        text.push('\n');
    }
    dynray_engine::output::write_atomic(path, text.as_bytes())?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_follow_the_header() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        let row =
            FrameRow { frame: 3, time: 0.5, render_ms: 2.0, rays: 4000, update: "refit".into(), ..Default::default() };
        write(&path, &[row]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0].split(',').count(), lines[1].split(',').count());
        assert!(lines[1].starts_with("3,0.5,0,0,0,"), "{}", lines[1]);
        assert!(lines[1].ends_with(",4000,2.000,"), "{}", lines[1]);
    }
}
