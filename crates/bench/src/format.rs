//! Number formatting shared by report.md, the presets' tables and the command line:
//! `871,414`, `1.5 MiB`, three significant digits.

/// `871,414`: the engine's formatter, so the bench's tables and the commands' summaries agree.
pub use dynray_engine::format::thousands;

/// `1.5 MiB`.
pub fn bytes(n: usize) -> String {
    let n = n as f64;
    if n >= 1024.0 * 1024.0 {
        format!("{:.1} MiB", n / 1024.0 / 1024.0)
    } else if n >= 1024.0 {
        format!("{:.1} KiB", n / 1024.0)
    } else {
        format!("{n} B")
    }
}

/// Three significant digits at most, no exponent.
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return "—".into();
    }
    let a = v.abs();
    if a >= 100.0 {
        format!("{v:.0}")
    } else if a >= 10.0 {
        format!("{v:.1}")
    } else if a >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

/// `value (ratio)` where a ratio ours/theirs (or GPU/CPU) is known.
pub fn with_ratio(v: String, ratio: Option<f64>) -> String {
    match ratio {
        Some(r) => format!("{v} ({}×)", num(r)),
        None => v,
    }
}
