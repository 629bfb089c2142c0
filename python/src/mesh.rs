//! `dynray.Mesh`: an immutable triangle mesh built from numpy arrays (or loaded from a
//! file), shared without copying by the structures built over it.

use crate::arrays;
use dynray_geom::TriangleMesh;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::sync::Arc;

/// A triangle mesh: vertices (N, 3) and faces (M, 3).
///
/// `Mesh(vertices, faces)` takes float32 or float64 vertices (float64 rounded to float32,
/// the engine's precision) and int32, int64, uint32 or uint64 faces, in any memory order.
/// Triangle `i` is row `i` of `faces`. Raises `ValueError` for a wrong shape, a NaN or
/// infinite coordinate, an index outside the vertices or no faces, and `TypeError` for
/// another dtype. A mesh never changes; `Structure.refit` makes a new one.
#[pyclass(module = "dynray", frozen, weakref)]
pub struct Mesh {
    pub(crate) inner: Arc<TriangleMesh>,
}

impl Mesh {
    /// Wraps a validated mesh.
    pub fn from_mesh(mesh: TriangleMesh) -> Self {
        Self { inner: Arc::new(mesh) }
    }
}

/// `vertices` (N, 3) read and checked to be finite.
pub fn read_vertices(obj: &Bound<'_, PyAny>) -> PyResult<Vec<[f32; 3]>> {
    let v: Vec<[f32; 3]> = arrays::float_rows(obj, "vertices")?;
    arrays::check_finite(&v, "vertices")?;
    Ok(v)
}

#[pymethods]
impl Mesh {
    #[new]
    fn new(vertices: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>) -> PyResult<Self> {
        let positions = read_vertices(vertices)?;
        let indices = arrays::faces(faces, positions.len(), "faces")?;
        let mesh = TriangleMesh::new(positions, indices);
        mesh.validate().map_err(|e| PyValueError::new_err(format!("mesh: {e}")))?;
        Ok(Self::from_mesh(mesh))
    }

    /// Vertex positions, (N, 3) float32 (a copy).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let flat: Vec<f32> = self.inner.positions.iter().flatten().copied().collect();
        PyArray1::from_vec(py, flat).reshape([self.inner.vertex_count(), 3])
    }

    /// Vertex indices per triangle, (M, 3) uint32 (a copy).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        let flat: Vec<u32> = self.inner.indices.iter().flatten().copied().collect();
        PyArray1::from_vec(py, flat).reshape([self.inner.triangle_count(), 3])
    }

    /// Number of triangles.
    #[getter]
    fn triangle_count(&self) -> usize {
        self.inner.triangle_count()
    }

    /// Number of vertices.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.inner.vertex_count()
    }

    /// Bounding box as `((min x, y, z), (max x, y, z))`.
    #[getter]
    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let b = self.inner.bounds();
        (b.min.to_array(), b.max.to_array())
    }

    fn __len__(&self) -> usize {
        self.inner.triangle_count()
    }

    fn __repr__(&self) -> String {
        format!("Mesh({} vertices, {} triangles)", self.inner.vertex_count(), self.inner.triangle_count())
    }
}
