//! dynray for Python: every acceleration structure of the engine over numpy arrays, in
//! process (docs/python.md). The extension module `dynray._dynray`; the `dynray` package
//! re-exports it and adds `dynray.bench` (a timing against embreex).
//!
//! Queries release the GIL and run on rayon threads; inputs are read in place where the
//! layout allows (C-contiguous float32 (N, 8) rays); errors are the engine's messages as
//! `ValueError`, `TypeError` or `OSError` (`errors.rs`).

mod arrays;
mod errors;
mod hits;
mod mesh;
mod pool;
mod rays;
mod render;
mod scene;
mod structure;
mod trace_file;

use pyo3::prelude::*;

/// The structure names `build` accepts, in the engine's order (`--accel` names).
fn accel_names() -> Vec<&'static str> {
    dynray_accel::AccelKind::ALL.iter().map(|k| k.name()).collect()
}

/// The parameter keys and presets of a structure: `{"keys": {name: doc}, "presets": [...]}`.
#[pyfunction]
fn accel_params<'py>(py: Python<'py>, accel: &str) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    let kind: dynray_accel::AccelKind = accel.parse().map_err(pyo3::exceptions::PyValueError::new_err)?;
    let d = pyo3::types::PyDict::new(py);
    let keys = pyo3::types::PyDict::new(py);
    for k in dynray_accel::AccelSpec::keys(kind) {
        keys.set_item(k.name, k.doc)?;
    }
    d.set_item("keys", keys)?;
    d.set_item("presets", dynray_accel::AccelSpec::presets(kind))?;
    Ok(d)
}

#[pymodule]
fn _dynray(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<mesh::Mesh>()?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<structure::Structure>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(structure::build, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(trace_file::trace_rays, m)?)?;
    m.add_function(wrap_pyfunction!(trace_file::merge_hits, m)?)?;
    m.add_function(wrap_pyfunction!(accel_params, m)?)?;
    m.add("ACCELS", accel_names())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
