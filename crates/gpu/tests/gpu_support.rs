//! The device every GPU test shares, and the skip rule: without an adapter a test prints
//! why and passes, unless `DYNRAY_REQUIRE_GPU=1` (CI sets it) makes that a failure.
#![allow(dead_code)]

use dynray_gpu::GpuContext;
use std::sync::Arc;

/// The shared device, or `None` (after saying why) on a machine without one.
pub fn device() -> Option<Arc<GpuContext>> {
    match GpuContext::shared() {
        Ok(ctx) => Some(ctx),
        Err(e) if std::env::var("DYNRAY_REQUIRE_GPU").is_ok_and(|v| v == "1") => {
            panic!("DYNRAY_REQUIRE_GPU=1 but {e}")
        }
        Err(e) => {
            skipped(&e.to_string());
            None
        }
    }
}

/// A device of its own opened with `options` (the f32 path's test), under the same rule.
pub fn device_with(options: &dynray_gpu::GpuOptions) -> Option<Arc<GpuContext>> {
    match GpuContext::new(options) {
        Ok(ctx) => Some(Arc::new(ctx)),
        Err(e) if std::env::var("DYNRAY_REQUIRE_GPU").is_ok_and(|v| v == "1") => {
            panic!("DYNRAY_REQUIRE_GPU=1 but {e}")
        }
        Err(e) => {
            skipped(&e.to_string());
            None
        }
    }
}

/// Says that the running test skipped, and why, where a plain `cargo test` shows it (a
/// `SKIPPED` line beside the `ok`): libtest captures the print macros' output, not writes
/// to the stderr handle.
fn skipped(why: &str) {
    use std::io::Write;
    let test = std::thread::current().name().unwrap_or("a GPU test").to_string();
    let _ = writeln!(std::io::stderr(), "SKIPPED {test}: {why}");
}
