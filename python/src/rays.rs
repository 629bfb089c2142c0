//! Rays in: an (N, 8) array as `trace-rays` reads (origin, direction, tmin, tmax per
//! row), or origins and directions (N, 3) with `tmin`/`tmax` numbers or (N,) arrays.
//!
//! A C-contiguous float32 (N, 8) array is used in place: `Ray` is `#[repr(C)]` Pod of 8
//! f32s, so its buffer is a `&[Ray]` (no copy, the array stays borrowed while traced).
//! Anything else is converted once. Every ray is checked as trace-rays checks its file
//! (`dynray_engine::hit_file::check_rays`): finite origin and direction, no NaN interval.

use crate::arrays::{self, float_rows, ndarray};
use dynray_geom::{Ray, Vec3};
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// Rays borrowed from a numpy array or converted into a vector.
pub enum Rays<'py> {
    /// A C-contiguous, aligned float32 (N, 8) array, read in place.
    Borrowed(PyReadonlyArray2<'py, f32>),
    /// Converted rays.
    Owned(Vec<Ray>),
}

impl Rays<'_> {
    /// The rays as a slice.
    pub fn as_slice(&self) -> &[Ray] {
        match self {
            Rays::Borrowed(a) => bytemuck::cast_slice(a.as_slice().expect("checked contiguous when borrowed")),
            Rays::Owned(v) => v,
        }
    }
}

/// Reads the rays of a query. `directions` absent: `origins` is (N, 8) and `tmin`/`tmax`
/// must be absent too (columns 6 and 7 hold them).
pub fn read<'py>(
    origins: &Bound<'py, PyAny>,
    directions: Option<&Bound<'py, PyAny>>,
    tmin: Option<&Bound<'py, PyAny>>,
    tmax: Option<&Bound<'py, PyAny>>,
) -> PyResult<Rays<'py>> {
    let Some(directions) = directions else {
        if tmin.is_some() || tmax.is_some() {
            return Err(PyValueError::new_err(
                "tmin and tmax come from columns 6 and 7 of an (N, 8) ray array; give origins and directions to set them",
            ));
        }
        return rows8(origins);
    };
    let dirs: Vec<[f32; 3]> = float_rows(directions, "directions")?;
    let n = dirs.len();
    let o = ndarray(origins, "origins")?;
    // One origin for every ray (a pinhole camera) is allowed as shape (3,).
    let origins: Vec<[f32; 3]> = if o.shape() == [3] {
        let one: Vec<[f32; 3]> = float_rows(&o.call_method1("reshape", (1, 3))?, "origins")?;
        vec![one[0]; n]
    } else {
        float_rows(&o, "origins")?
    };
    if origins.len() != n {
        return Err(PyValueError::new_err(format!("{} origins but {n} directions", origins.len())));
    }
    let lo = match tmin {
        Some(t) => arrays::scalar_or_column(t, n, "tmin")?,
        None => vec![0.0; n],
    };
    let hi = match tmax {
        Some(t) => arrays::scalar_or_column(t, n, "tmax")?,
        None => vec![f32::INFINITY; n],
    };
    let rays = (0..n)
        .map(|i| Ray::with_interval(Vec3::from_array(origins[i]), Vec3::from_array(dirs[i]), lo[i], hi[i]))
        .collect();
    Ok(Rays::Owned(rays))
}

/// An (N, 8) ray array: in place when it can be, converted otherwise.
fn rows8<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Rays<'py>> {
    let a = ndarray(obj, "rays")?;
    arrays::rows_of(&a, 8, "rays")?;
    if let Ok(f) = a.extract::<PyReadonlyArray2<'py, f32>>() {
        // C order only (`as_slice` also takes Fortran-contiguous data), and 4-byte aligned.
        let in_place =
            f.is_c_contiguous() && f.as_slice().is_ok_and(|s| bytemuck::try_cast_slice::<f32, Ray>(s).is_ok());
        if in_place {
            return Ok(Rays::Borrowed(f));
        }
    }
    let rows: Vec<[f32; 8]> = float_rows(&a, "rays")?;
    Ok(Rays::Owned(bytemuck::cast_vec(rows)))
}

/// [`dynray_engine::hit_file::check_rays`] as a `ValueError`.
pub fn check(rays: &[Ray]) -> PyResult<()> {
    dynray_engine::hit_file::check_rays(rays).map_err(PyValueError::new_err)
}
