//! The memory one command may ask for, checked before the large allocations a request
//! implies (an image's film, a scene's generated triangles, its textures together), so
//! that an excessive request is refused up front with what was asked and what the limit
//! is — not an abort minutes later when the allocator gives up (issue 43: a 16384² render
//! aborted at 7 GB).
//!
//! The budget is `DYNRAY_MEMORY_LIMIT` (bytes, or with a `K`, `M`, `G` or `T` suffix,
//! powers of 1024) or else three quarters of the memory this process can have: the
//! machine's (`MemTotal` in /proc/meminfo) or its control group's limit, whichever is
//! smaller; 16 GiB where neither can be read.

use std::sync::OnceLock;

/// The environment variable that sets the budget.
pub const LIMIT_ENV: &str = "DYNRAY_MEMORY_LIMIT";

/// The budget where the machine's memory cannot be read.
const FALLBACK: u64 = 16 << 30;

/// The budget in bytes (read once per process).
pub fn limit() -> u64 {
    static LIMIT: OnceLock<u64> = OnceLock::new();
    *LIMIT.get_or_init(|| {
        std::env::var(LIMIT_ENV).ok().and_then(|v| parse_size(&v)).unwrap_or_else(|| machine_memory() / 4 * 3)
    })
}

/// Fails, saying what was asked and the limit, when `bytes` exceed the budget. `what`
/// names the request (`a 16384 × 16384 image`).
pub fn check(what: &str, bytes: u64) -> Result<(), String> {
    let limit = limit();
    if bytes <= limit {
        return Ok(());
    }
    Err(format!(
        "{what} needs about {}, more than the memory budget of {} (set {LIMIT_ENV} to change it; by default \
         three quarters of this machine's memory)",
        human(bytes),
        human(limit)
    ))
}

/// `8G`, `512M`, `1048576`: bytes (powers of 1024); `None` for anything else.
pub fn parse_size(text: &str) -> Option<u64> {
    let t = text.trim();
    let (digits, shift) = match t.char_indices().last()? {
        (i, 'K' | 'k') => (&t[..i], 10),
        (i, 'M' | 'm') => (&t[..i], 20),
        (i, 'G' | 'g') => (&t[..i], 30),
        (i, 'T' | 't') => (&t[..i], 40),
        _ => (t, 0),
    };
    digits.trim().parse::<u64>().ok()?.checked_mul(1u64 << shift)
}

/// Bytes as a person reads them: `7.5 GiB`, `512 MiB`.
pub fn human(bytes: u64) -> String {
    let units = [("TiB", 40), ("GiB", 30), ("MiB", 20), ("KiB", 10)];
    for (unit, shift) in units {
        if bytes >= 1 << shift {
            return format!("{:.1} {unit}", bytes as f64 / (1u64 << shift) as f64);
        }
    }
    format!("{bytes} bytes")
}

/// The memory this process can have: the machine's, or its control group's limit.
fn machine_memory() -> u64 {
    let total = std::fs::read_to_string("/proc/meminfo").ok().and_then(|m| {
        let line = m.lines().find(|l| l.starts_with("MemTotal:"))?;
        let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
        kib.checked_mul(1024)
    });
    let cgroup = std::fs::read_to_string("/sys/fs/cgroup/memory.max").ok().and_then(|s| s.trim().parse::<u64>().ok());
    match (total, cgroup) {
        (Some(t), Some(c)) => t.min(c),
        (Some(t), None) => t,
        (None, Some(c)) => c,
        (None, None) => FALLBACK / 3 * 4,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_in_powers_of_1024() {
        assert_eq!(parse_size("8G"), Some(8 << 30));
        assert_eq!(parse_size("512m"), Some(512 << 20));
        assert_eq!(parse_size(" 1048576 "), Some(1 << 20));
        assert_eq!(parse_size("2T"), Some(2 << 40));
        for bad in ["", "G", "-1G", "1.5G", "lots", "99999999999T"] {
            assert_eq!(parse_size(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_request_over_the_budget_says_what_and_how_much() {
        assert!(check("a small image", 1 << 20).is_ok());
        let e = check("a 16384 × 16384 image", u64::MAX).unwrap_err();
        assert!(e.starts_with("a 16384 × 16384 image needs about") && e.contains(LIMIT_ENV), "{e}");
        assert_eq!(human(7 << 29), "3.5 GiB");
        assert_eq!(human(100), "100 bytes");
    }
}
