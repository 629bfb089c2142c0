//! numpy arrays in: any array-like becomes an ndarray (`numpy.asarray`), then its shape
//! and dtype are checked and its rows read in whatever memory order it has (C, Fortran,
//! strided views), with errors that name the argument.

use numpy::{PyArrayDescrMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// `obj` as a numpy array (lists and other array-likes through `numpy.asarray`).
pub fn ndarray<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    if let Ok(a) = obj.cast::<PyUntypedArray>() {
        return Ok(a.clone());
    }
    let a = obj
        .py()
        .import("numpy")?
        .call_method1("asarray", (obj,))
        .map_err(|e| PyTypeError::new_err(format!("{what}: not an array ({e})")))?;
    a.cast_into::<PyUntypedArray>().map_err(|_| PyTypeError::new_err(format!("{what}: not an array")))
}

/// The array's dtype as numpy prints it (`float16`, `int8`, …), for messages.
pub fn dtype_name(a: &Bound<'_, PyUntypedArray>) -> String {
    a.dtype().to_string()
}

/// Checks that `a` is (K, cols) and returns K.
pub fn rows_of(a: &Bound<'_, PyUntypedArray>, cols: usize, what: &str) -> PyResult<usize> {
    match a.shape() {
        [k, c] if *c == cols => Ok(*k),
        shape => Err(PyValueError::new_err(format!("{what} must have shape (N, {cols}), found {shape:?}"))),
    }
}

/// A (K, C) real numeric array as rows of f32 (float64 rounded to nearest, the engine's
/// precision, as `astype(np.float32)` rounds; integers and float16 through float64).
pub fn float_rows<const C: usize>(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[f32; C]>> {
    let a = ndarray(obj, what)?;
    rows_of(&a, C, what)?;
    if let Ok(a) = a.extract::<PyReadonlyArray2<'_, f32>>() {
        // `as_slice` also accepts Fortran-contiguous arrays: only C order is read flat.
        if a.is_c_contiguous() {
            if let Ok(flat) = a.as_slice() {
                return Ok(flat.chunks_exact(C).map(|r| std::array::from_fn(|j| r[j])).collect());
            }
        }
        return Ok(a.as_array().rows().into_iter().map(|r| std::array::from_fn(|j| r[j])).collect());
    }
    if let Ok(a) = a.extract::<PyReadonlyArray2<'_, f64>>() {
        return Ok(a.as_array().rows().into_iter().map(|r| std::array::from_fn(|j| r[j] as f32)).collect());
    }
    let wide = as_float64(&a, what)?;
    let wide = wide.extract::<PyReadonlyArray2<'_, f64>>()?;
    Ok(wide.as_array().rows().into_iter().map(|r| std::array::from_fn(|j| r[j] as f32)).collect())
}

/// Any other real numeric array (integers of any width, float16) as float64, which holds
/// them exactly or rounds as numpy would; booleans, complex numbers and objects are refused.
fn as_float64<'py>(a: &Bound<'py, PyUntypedArray>, what: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    if !matches!(a.dtype().kind(), b'i' | b'u' | b'f') {
        return Err(PyTypeError::new_err(format!(
            "{what} must be a real numeric array (floats or integers), found {}",
            dtype_name(a)
        )));
    }
    let wide = a.call_method1("astype", ("float64",))?;
    Ok(wide.cast_into::<PyUntypedArray>()?)
}

/// Checks every coordinate is finite, naming the first bad row.
pub fn check_finite<const C: usize>(rows: &[[f32; C]], what: &str) -> PyResult<()> {
    match rows.iter().position(|r| !r.iter().all(|c| c.is_finite())) {
        Some(i) => Err(PyValueError::new_err(format!("{what} row {i} has a non-finite value {:?}", rows[i]))),
        None => Ok(()),
    }
}

/// A (M, 3) int32, int64, uint32 or uint64 array of vertex indices, each checked to lie
/// in `0..vertices`.
pub fn faces(obj: &Bound<'_, PyAny>, vertices: usize, what: &str) -> PyResult<Vec<[u32; 3]>> {
    let a = ndarray(obj, what)?;
    rows_of(&a, 3, what)?;
    fn read<T: numpy::Element + Copy + TryInto<i128>>(
        a: &Bound<'_, PyUntypedArray>,
        vertices: usize,
        what: &str,
    ) -> Option<PyResult<Vec<[u32; 3]>>> {
        let a = a.extract::<PyReadonlyArray2<'_, T>>().ok()?;
        let view = a.as_array();
        let mut out = Vec::with_capacity(view.nrows());
        for (row, r) in view.rows().into_iter().enumerate() {
            let mut tri = [0u32; 3];
            for (j, &x) in r.iter().enumerate() {
                let i: i128 = x.try_into().unwrap_or(-1);
                if !(0..vertices as i128).contains(&i) {
                    let msg = format!("{what} row {row}: index {i} is outside 0..{vertices} (the vertices)");
                    return Some(Err(PyValueError::new_err(msg)));
                }
                tri[j] = i as u32;
            }
            out.push(tri);
        }
        Some(Ok(out))
    }
    read::<i32>(&a, vertices, what)
        .or_else(|| read::<i64>(&a, vertices, what))
        .or_else(|| read::<u32>(&a, vertices, what))
        .or_else(|| read::<u64>(&a, vertices, what))
        .unwrap_or_else(|| {
            Err(PyTypeError::new_err(format!(
                "{what} must be int32, int64, uint32 or uint64, found {}",
                dtype_name(&a)
            )))
        })
}

/// A number or an (N,) real numeric array, as N values.
pub fn scalar_or_column(obj: &Bound<'_, PyAny>, n: usize, what: &str) -> PyResult<Vec<f32>> {
    if let Ok(x) = obj.extract::<f64>() {
        return Ok(vec![x as f32; n]);
    }
    let a = ndarray(obj, what)?;
    if a.shape() != [n] {
        return Err(PyValueError::new_err(format!(
            "{what} must be a number or have shape ({n},), found {:?}",
            a.shape()
        )));
    }
    if let Ok(a) = a.extract::<PyReadonlyArray1<'_, f32>>() {
        return Ok(a.as_array().to_vec());
    }
    if let Ok(a) = a.extract::<PyReadonlyArray1<'_, f64>>() {
        return Ok(a.as_array().iter().map(|&x| x as f32).collect());
    }
    let wide = as_float64(&a, what)?;
    let wide = wide.extract::<PyReadonlyArray1<'_, f64>>()?;
    Ok(wide.as_array().iter().map(|&x| x as f32).collect())
}
