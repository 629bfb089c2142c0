//! `dynray.trace_rays`: the command line's file interface (`dynray trace-rays`), the same
//! job (`dynray_engine::TraceJob`), for scripts that have files rather than arrays.

use crate::errors::{build_error, file_error};
use crate::pool;
use dynray_engine::hit_file::HitField;
use dynray_engine::jobs::trace::Notice;
use dynray_engine::{BackendChoice, Query, TimeChoice, TraceJob};
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// Reads `mesh_path` (any format dynray reads, unshaded) and the (N, 8) `.npy` rays,
/// builds `accel`, traces, and writes `out_path` (`.npz`) exactly as `dynray trace-rays
/// MESH --rays RAYS -o OUT --accel ACCEL [--occluded | --fields …]` does. `fields`
/// defaults to `["t", "prim", "u", "v"]`. `time` (seconds) or `frame` pick the instant of
/// an animated file (frame 0 by default), its physics simulated to it, as `--time` and
/// `--frame` do. `rows=(a, b)` traces only rows `a..b` of the file (b exclusive, as
/// `rays[a:b]`), reading no other row, and records them in an int64 array `rows` =
/// `[a, b, N]`, as `--rows a..b` does; `merge_hits` joins such parts. The CLI's notes
/// (converted rays) and load warnings are issued as `UserWarning`s. Returns the counts
/// and times (ms) as a dict.
#[pyfunction]
#[pyo3(signature = (mesh_path, rays_path, out_path, accel = "bvh", occluded = false, fields = None, *, time = None, frame = None, threads = None, rows = None))]
#[allow(clippy::too_many_arguments)]
pub fn trace_rays<'py>(
    py: Python<'py>,
    mesh_path: PathBuf,
    rays_path: PathBuf,
    out_path: PathBuf,
    accel: &str,
    occluded: bool,
    fields: Option<Vec<String>>,
    time: Option<f32>,
    frame: Option<u32>,
    threads: Option<usize>,
    rows: Option<(u64, u64)>,
) -> PyResult<Bound<'py, PyDict>> {
    let spec: dynray_accel::AccelSpec = accel.parse().map_err(build_error)?;
    let query = match (occluded, fields) {
        (true, Some(_)) => return Err(PyValueError::new_err("fields cannot be given with occluded=True")),
        (true, None) => Query::Occluded,
        (false, None) => Query::Closest(HitField::DEFAULT.to_vec()),
        (false, Some(names)) => Query::Closest(
            names.iter().map(|n| n.parse::<HitField>()).collect::<Result<_, _>>().map_err(PyValueError::new_err)?,
        ),
    };
    let pool = pool::pool(threads)?;
    let job = TraceJob {
        mesh: mesh_path,
        rays: rays_path,
        rows: rows.map(|(a, b)| a..b),
        output: out_path,
        accel: spec,
        query,
        when: TimeChoice { time, frame, ..Default::default() },
        backend: BackendChoice::cpu(),
    };
    let mut notices = Vec::new();
    let result = py.detach(|| pool::run(&pool, || job.run(&mut |n| notices.push(n))));
    for n in notices {
        let (Notice::Note(m) | Notice::Warning(m)) = n;
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &std::ffi::CString::new(m).unwrap_or_default(), 1)?;
    }
    let s = result.map_err(file_error)?;
    let d = PyDict::new(py);
    d.set_item("rays", s.rays)?;
    d.set_item(if s.occluded { "occluded" } else { "hits" }, s.hits)?;
    d.set_item("accel", s.accel)?;
    for (k, t) in [("read_ms", s.read), ("build_ms", s.build), ("trace_ms", s.trace), ("write_ms", s.write)] {
        d.set_item(k, t.as_secs_f64() * 1e3)?;
    }
    Ok(d)
}

/// Joins the slice archives `parts` (written with `rows=(a, b)` or `trace-rays --rows`,
/// in any order) into `out_path`, exactly the archive one run over every row writes, as
/// `dynray merge-hits PART… -o OUT` does. Gaps, overlaps, parts of different ray files or
/// queries, and an output that is one of the parts raise `ValueError` naming the files
/// (`OSError` when a part cannot be read). Returns the parts and rays merged and the
/// arrays written.
#[pyfunction]
pub fn merge_hits<'py>(py: Python<'py>, parts: Vec<PathBuf>, out_path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let s = py.detach(|| dynray_engine::merge_hits(&parts, &out_path)).map_err(file_error)?;
    let d = PyDict::new(py);
    d.set_item("parts", s.parts)?;
    d.set_item("rays", s.rays)?;
    d.set_item("arrays", s.arrays)?;
    d.set_item("merge_ms", s.time.as_secs_f64() * 1e3)?;
    Ok(d)
}
