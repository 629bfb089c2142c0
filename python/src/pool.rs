//! `threads=`: work on a rayon pool of that many threads, or on rayon's global pool
//! (all cores) without it. Pools are kept per size, so a loop of small queries does not
//! start threads each time.

use pyo3::exceptions::PyValueError;
use pyo3::PyResult;
use std::sync::{Arc, Mutex};

/// Pools made so far, by thread count.
static POOLS: Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(Vec::new());

/// The pool for `threads`, or `None` for the global one; 0 threads is an error.
pub fn pool(threads: Option<usize>) -> PyResult<Option<Arc<rayon::ThreadPool>>> {
    let Some(n) = threads else { return Ok(None) };
    if n == 0 {
        return Err(PyValueError::new_err("threads must be at least 1 (or None for all cores)"));
    }
    let mut pools = POOLS.lock().unwrap_or_else(|p| p.into_inner());
    if let Some((_, p)) = pools.iter().find(|(k, _)| *k == n) {
        return Ok(Some(p.clone()));
    }
    let p = Arc::new(
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .thread_name(|i| format!("dynray-{i}"))
            .build()
            .map_err(|e| PyValueError::new_err(format!("cannot start {n} threads: {e}")))?,
    );
    pools.push((n, p.clone()));
    Ok(Some(p))
}

/// Runs `f` on `pool` (or the global pool).
pub fn run<T: Send>(pool: &Option<Arc<rayon::ThreadPool>>, f: impl FnOnce() -> T + Send) -> T {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}
