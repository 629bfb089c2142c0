//! Answers out: closest hits as a dict of numpy arrays with trace-rays' names, dtypes and
//! miss values (docs/trace-rays.md, "Output"), built with the GIL released.

use dynray_engine::hit_file::{hit_normals, hit_points};
use dynray_geom::{Hit, TriangleMesh};
use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

/// The columns of a batch of closest hits, ready to hand to numpy without copying.
pub struct Columns {
    t: Vec<f32>,
    prim: Vec<i64>,
    u: Vec<f32>,
    v: Vec<f32>,
    normal: Option<Vec<[f32; 3]>>,
    point: Option<Vec<[f32; 3]>>,
}

impl Columns {
    /// Splits `hits` into columns (in parallel on the current pool); `normal` and `point`
    /// are computed only when asked, exactly as trace-rays writes them.
    pub fn new(hits: &[Hit], mesh: &TriangleMesh, normal: bool, point: bool) -> Self {
        Self {
            t: hits.par_iter().map(|h| h.t).collect(),
            prim: hits.par_iter().map(|h| if h.is_hit() { h.prim as i64 } else { -1 }).collect(),
            u: hits.par_iter().map(|h| h.u).collect(),
            v: hits.par_iter().map(|h| h.v).collect(),
            normal: normal.then(|| hit_normals(hits, mesh)),
            point: point.then(|| hit_points(hits, mesh)),
        }
    }

    /// `{"t", "prim", "u", "v"}` plus `"normal"`, `"point"` ((N, 3)) when computed.
    pub fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let d = PyDict::new(py);
        let n = self.t.len();
        d.set_item("t", self.t.into_pyarray(py))?;
        d.set_item("prim", self.prim.into_pyarray(py))?;
        d.set_item("u", self.u.into_pyarray(py))?;
        d.set_item("v", self.v.into_pyarray(py))?;
        for (name, rows) in [("normal", self.normal), ("point", self.point)] {
            if let Some(rows) = rows {
                let flat: Vec<f32> = rows.as_flattened().to_vec();
                d.set_item(name, flat.into_pyarray(py).reshape([n, 3])?)?;
            }
        }
        Ok(d)
    }
}
