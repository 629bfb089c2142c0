//! `dynray.render`: the engine's render entry point (`dynray_render::render`, as `dynray
//! render` calls it) into a numpy image.

use crate::errors::build_error;
use crate::pool;
use crate::scene::{load, Scene};
use dynray_render::{IntegratorKind, RenderOptions};
use dynray_scene::Shading;
use numpy::{IntoPyArray, PyArray3, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::path::PathBuf;

/// Most samples per pixel accepted, as on the command line (`render --spp`).
const MAX_SPP: u32 = 1 << 16;

/// Renders a `Scene` (from `dynray.load`) or a file path into an (height, width, 3)
/// float32 array of linear radiance, row 0 at the top: the film's values before any
/// tone mapping or sRGB encoding (the PNG the CLI writes is their sRGB encoding, values
/// above 1 clipped). Defaults are the CLI's: the file's size (or 800×600), 9 samples
/// per pixel, Whitted, the BVH, smooth shading of meshes without normals, seed 0.
#[pyfunction]
#[pyo3(signature = (scene, width = None, height = None, spp = 9, integrator = "whitted", *, accel = "bvh", seed = 0, max_depth = None, flat_shading = false, threads = None))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    width: Option<u32>,
    height: Option<u32>,
    spp: u32,
    integrator: &str,
    accel: &str,
    seed: u64,
    max_depth: Option<u32>,
    flat_shading: bool,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let loaded;
    let scene: &Scene = if let Ok(s) = scene.cast::<Scene>() {
        s.get()
    } else if let Ok(path) = scene.extract::<PathBuf>() {
        loaded = load(py, path)?;
        &loaded
    } else {
        return Err(PyTypeError::new_err("scene must be a dynray.Scene or a file path"));
    };
    let integrator: IntegratorKind = integrator.parse().map_err(PyValueError::new_err)?;
    let spec: dynray_accel::AccelSpec = accel.parse().map_err(build_error)?;
    if !(1..=MAX_SPP).contains(&spp) {
        return Err(PyValueError::new_err(format!("spp must be in 1..={MAX_SPP}, got {spp}")));
    }
    let pool = pool::pool(threads)?;
    let label = scene.path.display().to_string();
    let mut s = scene.scene.clone();
    let image = py.detach(|| -> PyResult<(Vec<f32>, u32, u32)> {
        if flat_shading {
            s.actors.iter_mut().for_each(|a| a.shading = Shading::Flat);
        }
        s.apply_shading().map_err(|e| PyValueError::new_err(format!("{label}: {e}")))?;
        let mut frame = s.frame(0.0);
        let st = &mut frame.settings;
        st.width = width.unwrap_or(st.width);
        st.height = height.unwrap_or(st.height);
        st.max_recursion_level = max_depth.unwrap_or(st.max_recursion_level);
        let max = dynray_render::MAX_IMAGE_EDGE;
        for (what, v) in [("width", st.width), ("height", st.height)] {
            if v == 0 || v > max {
                return Err(PyValueError::new_err(format!("{label}: image {what} {v} is outside 1..={max}")));
            }
        }
        let options = RenderOptions { spp, seed, integrator, ..Default::default() };
        let film = pool::run(&pool, || {
            let accel = spec.build(&frame.mesh, Some(frame.camera.position)).map_err(build_error)?;
            Ok::<_, PyErr>(dynray_render::render(&frame, accel.as_ref(), &options).0)
        })?;
        let rgb = film.pixels().iter().flat_map(|c| c.to_array()).collect();
        Ok((rgb, film.width(), film.height()))
    })?;
    let (rgb, w, h) = image;
    rgb.into_pyarray(py).reshape([h as usize, w as usize, 3])
}
