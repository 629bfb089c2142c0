//! `dynray.render`: the engine's render job (`dynray_engine::RenderJob`, as `dynray
//! render` runs it) into a numpy image.

use crate::errors::{build_error, file_error};
use crate::pool;
use crate::scene::Scene;
use dynray_engine::{Loaded, RenderJob, TimeChoice};
use dynray_render::IntegratorKind;
use numpy::{IntoPyArray, PyArray3, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::path::PathBuf;

/// Renders a `Scene` (from `dynray.load`) or a file path into an (height, width, 3)
/// float32 array of linear radiance, row 0 at the top: the film's values before any
/// tone mapping or sRGB encoding (the PNG the CLI writes is their sRGB encoding, values
/// above 1 clipped; `dynray render … -o x.exr` writes these very values). Defaults are
/// the CLI's: the file's size (or 800×600), its samples per pixel (else 9), Whitted, the
/// BVH, smooth shading of meshes without normals, seed 0, frame 0. `time` (seconds) or
/// `frame` pick the instant of an animated scene, its physics simulated to it;
/// `max_depth` counts as `--max-depth` does (path segments for the path tracer).
#[pyfunction]
#[pyo3(signature = (scene, width = None, height = None, spp = None, integrator = "whitted", *, accel = "bvh", seed = 0, max_depth = None, flat_shading = false, time = None, frame = None, threads = None))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    width: Option<u32>,
    height: Option<u32>,
    spp: Option<u32>,
    integrator: &str,
    accel: &str,
    seed: u64,
    max_depth: Option<u32>,
    flat_shading: bool,
    time: Option<f32>,
    frame: Option<u32>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let source = if let Ok(s) = scene.cast::<Scene>() {
        let s = s.get();
        Source::Scene(Box::new(s.scene.clone()), s.path.display().to_string())
    } else if let Ok(path) = scene.extract::<PathBuf>() {
        Source::File(path)
    } else {
        return Err(PyTypeError::new_err("scene must be a dynray.Scene or a file path"));
    };
    let integrator: IntegratorKind = integrator.parse().map_err(PyValueError::new_err)?;
    let job = RenderJob {
        width,
        height,
        max_depth,
        accel: accel.parse().map_err(build_error)?,
        integrator,
        spp,
        seed,
        flat_shading,
        when: TimeChoice { time, frame, ..Default::default() },
        ..RenderJob::default()
    };
    job.check().map_err(|e| PyValueError::new_err(format!("{e:#}")))?;
    let pool = pool::pool(threads)?;
    let image = py.detach(|| -> PyResult<(Vec<f32>, u32, u32)> {
        let loaded = match source {
            Source::Scene(scene, label) => Loaded::from_scene(*scene, label),
            Source::File(path) => Loaded::open(Some(&path)).map_err(file_error)?,
        };
        let rendered = pool::run(&pool, || job.run(loaded, None)).map_err(file_error)?;
        let film = rendered.film;
        let rgb = film.pixels().iter().flat_map(|c| c.to_array()).collect();
        Ok((rgb, film.width(), film.height()))
    })?;
    let (rgb, w, h) = image;
    rgb.into_pyarray(py).reshape([h as usize, w as usize, 3])
}

/// What is rendered: a loaded `Scene`'s model, or a file read as the CLI reads it (a
/// `.adf` field included).
enum Source {
    Scene(Box<dynray_scene::Scene>, String),
    File(PathBuf),
}
