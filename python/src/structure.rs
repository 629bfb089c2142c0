//! `dynray.build` and `dynray.Structure`: any structure the engine has, named and
//! parameterised as `--accel` names it, queried with the GIL released.

use crate::errors::build_error;
use crate::hits::Columns;
use crate::mesh::{read_vertices, Mesh};
use crate::{pool, rays};
use dynray_accel::{Accel, AccelSpec, BatchQuery};
use dynray_geom::{TriangleMesh, Vec3};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyNotImplementedError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict};
use std::sync::{Arc, Mutex, RwLock};

/// What a query reads and a refit replaces, together.
struct State {
    accel: Box<dyn Accel>,
    mesh: Arc<TriangleMesh>,
}

/// An acceleration structure over a [`Mesh`], made by `dynray.build`.
///
/// Queries take the read lock with the GIL released, so several Python threads trace at
/// once; `refit` takes the write lock and waits for them.
#[pyclass(module = "dynray", frozen, weakref)]
pub struct Structure {
    state: RwLock<State>,
    spec: AccelSpec,
    /// The Python mesh object, kept alive as long as the structure (replaced by `refit`).
    mesh: Mutex<Py<Mesh>>,
}

/// A keyword parameter as `--accel` text: booleans `on`/`off`, everything else `str()`.
fn param_text(v: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(b) = v.cast::<PyBool>() {
        return Ok(if b.is_true() { "on" } else { "off" }.to_string());
    }
    Ok(v.str()?.to_string())
}

/// `accel` (`"bih"`, `"bih:max_prims=5"`, `"octree:high_quality"`) with `params` added
/// as `key=value`, parsed by the engine so its messages are the command line's.
fn spec_of(accel: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<AccelSpec> {
    let mut text = accel.to_string();
    for (k, v) in params.into_iter().flat_map(|p| p.iter()) {
        text.push(if text.contains(':') { ',' } else { ':' });
        text.push_str(&format!("{}={}", k.str()?, param_text(&v)?));
    }
    text.parse().map_err(build_error)
}

/// Builds a structure over `mesh`: `accel` is any `--accel` name, optionally with its
/// parameters or a preset after a colon; `**params` add parameters (`max_prims=5`,
/// `shrink=False`, `preset="fast"`). `eye` is the camera position the A-PIT and the
/// A-buffer centre their cube on (default: the mesh's centre). `threads` limits the
/// build's threads (default: all cores). Unknown names, keys and values raise
/// `ValueError` with the engine's message.
#[pyfunction]
#[pyo3(signature = (mesh, accel = "bvh", *, eye = None, threads = None, **params))]
pub fn build(
    py: Python<'_>,
    mesh: &Bound<'_, Mesh>,
    accel: &str,
    eye: Option<[f32; 3]>,
    threads: Option<usize>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Structure> {
    let spec = spec_of(accel, params)?;
    let pool = pool::pool(threads)?;
    let m = mesh.get().inner.clone();
    let built = py.detach(|| pool::run(&pool, || spec.build(&m, eye.map(Vec3::from_array))));
    let accel = built.map_err(build_error)?;
    Ok(Structure { state: RwLock::new(State { accel, mesh: m }), spec, mesh: Mutex::new(mesh.clone().unbind()) })
}

impl Structure {
    fn read(&self) -> std::sync::RwLockReadGuard<'_, State> {
        self.state.read().unwrap_or_else(|p| p.into_inner())
    }
}

#[pymethods]
impl Structure {
    /// Closest hits of a batch of rays: `intersect(rays)` with an (N, 8) array (origin,
    /// direction, tmin, tmax per row, as trace-rays reads), or `intersect(origins,
    /// directions, tmin=0, tmax=inf)` with (N, 3) arrays (origins may be one (3,) point)
    /// and numbers or (N,) arrays. Returns a dict of numpy arrays: `t` float32 (inf on a
    /// miss), `prim` int64 (-1), `u`, `v` float32 (0), and with `normal=True` / `point=True`
    /// the (N, 3) float32 unit geometric normal and hit point (NaN on a miss).
    #[pyo3(signature = (origins, directions = None, tmin = None, tmax = None, *, normal = false, point = false, threads = None))]
    #[allow(clippy::too_many_arguments)]
    fn intersect<'py>(
        slf: &Bound<'py, Self>,
        origins: &Bound<'py, PyAny>,
        directions: Option<&Bound<'py, PyAny>>,
        tmin: Option<&Bound<'py, PyAny>>,
        tmax: Option<&Bound<'py, PyAny>>,
        normal: bool,
        point: bool,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let py = slf.py();
        let rays = rays::read(origins, directions, tmin, tmax)?;
        let pool = pool::pool(threads)?;
        let (this, slice) = (slf.get(), rays.as_slice());
        let columns = py.detach(|| {
            rays::check(slice)?;
            let state = this.read();
            Ok::<_, PyErr>(pool::run(&pool, || {
                Columns::new(&state.accel.intersect_batch(slice), &state.mesh, normal, point)
            }))
        })?;
        columns.into_dict(py)
    }

    /// Any-hit (shadow) queries on the same rays as `intersect`: a bool array, true when
    /// any triangle lies on the ray within [tmin, tmax].
    #[pyo3(signature = (origins, directions = None, tmin = None, tmax = None, *, threads = None))]
    fn occluded<'py>(
        slf: &Bound<'py, Self>,
        origins: &Bound<'py, PyAny>,
        directions: Option<&Bound<'py, PyAny>>,
        tmin: Option<&Bound<'py, PyAny>>,
        tmax: Option<&Bound<'py, PyAny>>,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let py = slf.py();
        let rays = rays::read(origins, directions, tmin, tmax)?;
        let pool = pool::pool(threads)?;
        let (this, slice) = (slf.get(), rays.as_slice());
        let occ = py.detach(|| {
            rays::check(slice)?;
            let state = this.read();
            Ok::<_, PyErr>(pool::run(&pool, || state.accel.occluded_batch(slice)))
        })?;
        Ok(occ.into_pyarray(py))
    }

    /// Moves the mesh's vertices to `vertices` (same count, same faces) and refits the
    /// tree's bounds instead of rebuilding: for the structures that refit (`bvh`, `bih`,
    /// see `refits`). Others raise `NotImplementedError`; build a new structure instead.
    /// Afterwards `mesh` is a new `Mesh` with these vertices (the old one is unchanged).
    #[pyo3(signature = (vertices, *, threads = None))]
    fn refit(slf: &Bound<'_, Self>, vertices: &Bound<'_, PyAny>, threads: Option<usize>) -> PyResult<()> {
        let py = slf.py();
        let this = slf.get();
        let positions = read_vertices(vertices)?;
        let indices = {
            let state = this.read();
            if !state.accel.update_refits() {
                return Err(PyNotImplementedError::new_err(format!(
                    "{} does not refit (only bvh and bih do); build a new structure over the moved mesh",
                    state.accel.name()
                )));
            }
            if positions.len() != state.mesh.vertex_count() {
                return Err(PyValueError::new_err(format!(
                    "refit: {} vertices given, the mesh has {}",
                    positions.len(),
                    state.mesh.vertex_count()
                )));
            }
            state.mesh.indices.clone()
        };
        let moved = Arc::new(TriangleMesh::new(positions, indices));
        let pool = pool::pool(threads)?;
        py.detach(|| {
            let mut state = this.state.write().unwrap_or_else(|p| p.into_inner());
            let accel = &mut state.accel;
            pool::run(&pool, || accel.update(&moved))?;
            state.mesh = moved.clone();
            Ok::<_, dynray_accel::BuildError>(())
        })
        .map_err(build_error)?;
        *this.mesh.lock().unwrap_or_else(|p| p.into_inner()) = Py::new(py, Mesh { inner: moved })?;
        Ok(())
    }

    /// The structure's figures: nodes, leaves, max_depth, primitive_refs, leaf_sizes
    /// (leaves per triangle count), sah_cost (None where undefined), memory_bytes, and
    /// the structure's own figures under `extra`.
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.read().accel.stats();
        let d = PyDict::new(py);
        d.set_item("nodes", s.nodes)?;
        d.set_item("leaves", s.leaves)?;
        d.set_item("max_depth", s.max_depth)?;
        d.set_item("primitive_refs", s.primitive_refs)?;
        d.set_item("leaf_sizes", s.leaf_sizes)?;
        d.set_item("sah_cost", s.sah_cost)?;
        d.set_item("memory_bytes", s.memory_bytes)?;
        let extra = PyDict::new(py);
        for (k, v) in s.extra {
            extra.set_item(k, v)?;
        }
        d.set_item("extra", extra)?;
        Ok(d)
    }

    /// Checks every invariant the traversal relies on; raises `ValueError` naming the
    /// first broken one, returns `stats()` otherwise.
    fn validate<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        {
            let state = self.read();
            state.accel.validate(&state.mesh).map_err(|e| PyValueError::new_err(e.to_string()))?;
        }
        self.stats(py)
    }

    /// Bytes of every array the structure owns.
    #[getter]
    fn memory_bytes(&self) -> usize {
        self.read().accel.memory_bytes()
    }

    /// The structure's name, as `--accel` spells it.
    #[getter]
    fn name(&self) -> &'static str {
        self.read().accel.name()
    }

    /// The structure and its parameters as one `--accel` value (`"bih:max_prims=5"`).
    #[getter]
    fn accel(&self) -> String {
        self.spec.to_string()
    }

    /// True when `refit` refits this structure (bvh, bih).
    #[getter]
    fn refits(&self) -> bool {
        self.read().accel.update_refits()
    }

    /// The mesh the structure answers for (after `refit`, the moved one).
    #[getter]
    fn mesh(&self, py: Python<'_>) -> Py<Mesh> {
        self.mesh.lock().unwrap_or_else(|p| p.into_inner()).clone_ref(py)
    }

    fn __repr__(&self) -> String {
        let state = self.read();
        format!(
            "Structure({}, {} triangles, {} bytes)",
            self.spec,
            state.mesh.triangle_count(),
            state.accel.memory_bytes()
        )
    }
}
