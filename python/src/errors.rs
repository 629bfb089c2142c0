//! The engine's errors as Python exceptions, their messages unchanged (each names the
//! file, the structure or the argument, as the command line prints them).
//!
//! Files that cannot be opened or read raise `OSError` (Python picks the subclass from
//! the errno, e.g. `FileNotFoundError`) with `filename` set; bad content, bad parameters
//! and bad arrays raise `ValueError`; a wrong type of argument raises `TypeError`.

use dynray_accel::BuildError;
use dynray_scene::LoadError;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::PyErr;
use std::path::Path;

/// `OSError(errno, message, filename)`: Python turns errno 2 into `FileNotFoundError`.
fn os_error(path: &Path, e: &std::io::Error, message: String) -> PyErr {
    let errno = e.raw_os_error().unwrap_or(0);
    PyOSError::new_err((errno, message, path.display().to_string()))
}

/// A loader error: I/O failures as `OSError`, everything else as `ValueError`.
pub fn load_error(e: LoadError) -> PyErr {
    match &e {
        LoadError::Io { path, source } => os_error(path, source, e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// A structure that cannot be named or built (unknown name, key or value; bad mesh).
pub fn build_error(e: BuildError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// An error of the file interface (`trace_rays`), printed as the binary prints it
/// (`{e:#}`, causes joined by `: `, the file named first): `OSError` when an I/O error
/// is the cause (the message says which file), `ValueError` otherwise.
pub fn file_error(e: anyhow::Error) -> PyErr {
    let message = format!("{e:#}");
    if let Some(LoadError::Io { path, source }) = e.downcast_ref::<LoadError>() {
        return os_error(path, source, message);
    }
    match e.chain().find_map(|c| c.downcast_ref::<std::io::Error>()) {
        Some(io) => PyOSError::new_err((io.raw_os_error().unwrap_or(0), message)),
        None => PyValueError::new_err(message),
    }
}
