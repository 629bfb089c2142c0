//! What the window shows besides the image: the traversal-cost heat map and the
//! structure's boxes drawn over the image, both as 8-bit RGBA pixels the presenter
//! uploads like the image itself.

use dynray_accel::{Accel, OutlineBox};
use dynray_geom::Vec3;
use dynray_render::{CameraBasis, CameraRays};
use dynray_scene::Frame;

/// The starting or current view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Show {
    /// The rendered image.
    Image,
    /// Nodes + triangles per primary ray, colour-mapped.
    Heatmap,
    /// The structure's boxes to this depth over the image.
    Boxes(u32),
}

/// Depth `--show boxes` draws without one.
pub const DEFAULT_BOX_DEPTH: u32 = 3;
/// Deepest level the boxes view draws (a deeper outline is a solid mesh of lines).
pub const MAX_BOX_DEPTH: u32 = 24;

impl std::str::FromStr for Show {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s.split_once(':') {
            None if s == "image" => Ok(Show::Image),
            None if s == "heatmap" => Ok(Show::Heatmap),
            None if s == "boxes" => Ok(Show::Boxes(DEFAULT_BOX_DEPTH)),
            Some(("boxes", d)) => match d.parse::<u32>() {
                Ok(d) if d <= MAX_BOX_DEPTH => Ok(Show::Boxes(d)),
                _ => Err(format!("`{d}`: the boxes' depth is a whole number in 0..={MAX_BOX_DEPTH}")),
            },
            _ => Err(format!("`{s}`: expected image, heatmap, boxes or boxes:DEPTH")),
        }
    }
}

impl std::fmt::Display for Show {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Show::Image => f.write_str("image"),
            Show::Heatmap => f.write_str("heatmap"),
            Show::Boxes(d) => write!(f, "boxes:{d}"),
        }
    }
}

/// Matplotlib's viridis at nine stops (dark = cheap, yellow = expensive), as the bench's
/// heat maps colour them.
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

/// Viridis at `t` in [0, 1].
pub fn viridis(t: f32) -> [u8; 3] {
    let x = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f32;
    let i = (x as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f32;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    std::array::from_fn(|k| (a[k] as f32 + (b[k] as f32 - a[k] as f32) * f).round() as u8)
}

/// The heat map of `frame` through `accel` as RGBA, and the work the scale tops out at.
pub fn heatmap(frame: &Frame, accel: &dyn Accel) -> (Vec<u8>, u32) {
    let work = dynray_engine::heat::work_map(frame, accel);
    let top = dynray_engine::heat::scale_max(&work);
    let rgba = work.iter().flat_map(|&w| {
        let [r, g, b] = viridis(w.min(top) as f32 / top as f32);
        [r, g, b, 255]
    });
    (rgba.collect(), top)
}

/// Colours of box depths, cycling: bright, distinct on dark and light images.
const DEPTH_COLOURS: [[u8; 3]; 6] =
    [[255, 255, 255], [255, 196, 0], [0, 220, 255], [255, 80, 160], [120, 255, 80], [180, 140, 255]];

/// Draws `boxes` as wireframes over `rgba` (`width` × `height`), seen through `frame`'s
/// camera at that size. Leaves are drawn at full strength, inner nodes fainter.
pub fn draw_boxes(rgba: &mut [u8], (width, height): (u32, u32), frame: &Frame, boxes: &[OutlineBox]) {
    let camera = CameraRays::new(&frame.camera, width, height).basis();
    let mut canvas = Canvas { rgba, width, height };
    for b in boxes {
        let colour = DEPTH_COLOURS[b.depth as usize % DEPTH_COLOURS.len()];
        let alpha = if b.leaf { 1.0 } else { 0.6 };
        let (lo, hi) = (b.bounds.min, b.bounds.max);
        let corner = |i: usize| {
            Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        };
        for (a, c) in EDGES {
            if let Some((p, q)) = project_segment(&camera, corner(a), corner(c)) {
                canvas.line(p, q, colour, alpha);
            }
        }
    }
}

/// The twelve edges of a box, as pairs of corner indices (bit 0: x, 1: y, 2: z).
const EDGES: [(usize, usize); 12] =
    [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)];

/// Smallest depth in front of the eye a perspective segment is clipped to.
const NEAR: f32 = 1e-4;

/// The image positions (pixels, y down) of segment `a`–`b`, clipped to the part in front
/// of a perspective camera; the inverse of [`CameraRays::ray_at`].
fn project_segment(camera: &CameraBasis, a: Vec3, b: Vec3) -> Option<((f32, f32), (f32, f32))> {
    let depth = |p: Vec3| (p - camera.origin).dot(camera.forward);
    let (mut a, mut b) = (a, b);
    if !camera.parallel {
        let (da, db) = (depth(a), depth(b));
        if da < NEAR && db < NEAR {
            return None;
        }
        if da < NEAR {
            a = a + (b - a) * ((NEAR - da) / (db - da));
        } else if db < NEAR {
            b = b + (a - b) * ((NEAR - db) / (da - db));
        }
    }
    Some((project(camera, a), project(camera, b)))
}

/// Image position of `p`: `s = (2 px / w − 1, 1 − 2 py / h)` solved from the ray's offset.
fn project(camera: &CameraBasis, p: Vec3) -> (f32, f32) {
    let d = p - camera.origin;
    let (sx, sy) = if camera.parallel {
        (d.dot(camera.right) / camera.right.length_squared(), d.dot(camera.up) / camera.up.length_squared())
    } else {
        let z = d.dot(camera.forward);
        (d.dot(camera.right) / (z * camera.right.length_squared()), d.dot(camera.up) / (z * camera.up.length_squared()))
    };
    ((sx + 1.0) * 0.5 * camera.width, (1.0 - sy) * 0.5 * camera.height)
}

/// RGBA pixels to draw lines on.
struct Canvas<'a> {
    rgba: &'a mut [u8],
    width: u32,
    height: u32,
}

impl Canvas<'_> {
    /// A one-pixel line from `p` to `q`, clipped to the image (Liang–Barsky), blended.
    fn line(&mut self, p: (f32, f32), q: (f32, f32), colour: [u8; 3], alpha: f32) {
        let (w, h) = (self.width as f32, self.height as f32);
        let Some((p, q)) = clip(p, q, (0.0, 0.0), (w - 1e-3, h - 1e-3)) else { return };
        let steps = (q.0 - p.0).abs().max((q.1 - p.1).abs()).ceil().max(1.0) as u32;
        for i in 0..=steps {
            let t = i as f32 / steps as f32;
            let (x, y) = (p.0 + (q.0 - p.0) * t, p.1 + (q.1 - p.1) * t);
            let (x, y) = (x as u32, y as u32);
            if x < self.width && y < self.height {
                let k = 4 * (y as usize * self.width as usize + x as usize);
                for (px, &c) in self.rgba[k..k + 3].iter_mut().zip(&colour) {
                    let old = *px as f32;
                    *px = (old + (c as f32 - old) * alpha).round() as u8;
                }
            }
        }
    }
}

/// Segment `p`–`q` clipped to the rectangle `lo`–`hi`; `None` when nothing is inside.
fn clip(p: (f32, f32), q: (f32, f32), lo: (f32, f32), hi: (f32, f32)) -> Option<((f32, f32), (f32, f32))> {
    if ![p.0, p.1, q.0, q.1].iter().all(|v| v.is_finite()) {
        return None;
    }
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for (den, num) in [(-dx, p.0 - lo.0), (dx, hi.0 - p.0), (-dy, p.1 - lo.1), (dy, hi.1 - p.1)] {
        if den == 0.0 {
            if num < 0.0 {
                return None;
            }
        } else {
            let t = num / den;
            if den < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    (t0 <= t1).then_some(((p.0 + t0 * dx, p.1 + t0 * dy), (p.0 + t1 * dx, p.1 + t1 * dy)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_scene::{Camera, Clip, Projection};

    #[test]
    fn show_parses_and_prints() {
        for s in ["image", "heatmap", "boxes:0", "boxes:7"] {
            assert_eq!(s.parse::<Show>().unwrap().to_string(), s);
        }
        assert_eq!("boxes".parse::<Show>().unwrap(), Show::Boxes(DEFAULT_BOX_DEPTH));
        assert!("boxes:x".parse::<Show>().is_err() && "boxes:99".parse::<Show>().is_err());
        assert!("wires".parse::<Show>().unwrap_err().contains("expected image"));
    }

    #[test]
    fn projection_inverts_the_camera_rays() {
        for projection in [Projection::Perspective { fov_y_deg: 50.0 }, Projection::Parallel { height: 3.0 }] {
            let cam = Camera {
                position: Vec3::new(0.3, 1.0, 4.0),
                look_at: Vec3::new(0.0, 0.2, 0.0),
                up: Vec3::Y,
                projection,
                clip: Clip::NONE,
            };
            let rays = CameraRays::new(&cam, 64, 48);
            for (px, py) in [(0.5, 0.5), (31.0, 20.25), (63.5, 47.5)] {
                let r = rays.ray_at(px, py);
                let (x, y) = project(&rays.basis(), r.origin + r.dir * 2.5);
                assert!((x - px).abs() < 1e-3 && (y - py).abs() < 1e-3, "{projection:?}: {px},{py} -> {x},{y}");
            }
        }
    }

    #[test]
    fn lines_are_clipped_to_the_image_and_behind_the_eye() {
        let mut rgba = vec![0u8; 8 * 8 * 4];
        let mut c = Canvas { rgba: &mut rgba, width: 8, height: 8 };
        c.line((-10.0, 4.5), (20.0, 4.5), [255, 0, 0], 1.0);
        let row: Vec<u8> = (0..8).map(|x| rgba[4 * (4 * 8 + x)]).collect();
        assert_eq!(row, [255; 8]);
        assert_eq!(rgba.iter().filter(|&&v| v == 255).count(), 8, "only that row");
        assert!(clip((-5.0, -5.0), (-1.0, -1.0), (0.0, 0.0), (8.0, 8.0)).is_none());

        let cam = Camera {
            position: Vec3::ZERO,
            look_at: Vec3::NEG_Z,
            up: Vec3::Y,
            projection: Projection::Perspective { fov_y_deg: 60.0 },
            clip: Clip::NONE,
        };
        let basis = CameraRays::new(&cam, 8, 8).basis();
        assert!(project_segment(&basis, Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 2.0)).is_none());
        let (p, _) = project_segment(&basis, Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, -1.0)).unwrap();
        assert!(p.0.is_finite() && p.1.is_finite());
    }

    #[test]
    fn viridis_runs_dark_to_yellow() {
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(1.0), [253, 231, 37]);
        assert_eq!(viridis(2.0), viridis(1.0));
    }
}
