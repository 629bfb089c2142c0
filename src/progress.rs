//! Progress of a long command (`render`, `animate`): a bar on a terminal; anywhere else (a
//! log file, a CI or batch job's output) a plain line at most every few seconds, with the
//! elapsed time and an estimate of what is left, so a long run is never silent.
//!
//! `DYNRAY_PROGRESS_SECONDS` sets the gap between lines (default 5; 0 prints every step).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The default gap between two progress lines in a log.
const LINE_EVERY: Duration = Duration::from_secs(5);

/// A terminal bar or log lines over a known number of steps.
pub struct Progress {
    /// What the lines start with (`dynray render`, the scene's name).
    label: String,
    bar: ProgressBar,
    /// Lines instead of the bar (stderr is not a terminal).
    lines: bool,
    /// The bar shows only once the work has lasted longer than this.
    bar_after: Duration,
    every: Duration,
    started: Instant,
    /// When the last line was printed (none yet: `None`).
    last_line: Mutex<Option<Instant>>,
}

impl Progress {
    /// Progress labelled `label`, its bar drawn with `template` (indicatif's syntax) once
    /// the work has lasted `bar_after`.
    pub fn new(label: &str, template: &str, bar_after: Duration) -> Self {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
        bar.set_style(ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()));
        let every = std::env::var("DYNRAY_PROGRESS_SECONDS")
            .ok()
            .and_then(|s| s.trim().parse::<f64>().ok())
            .filter(|s| s.is_finite() && *s >= 0.0)
            .map_or(LINE_EVERY, Duration::from_secs_f64);
        Progress {
            label: label.to_string(),
            bar,
            lines: !std::io::stderr().is_terminal(),
            bar_after,
            every,
            started: Instant::now(),
            last_line: Mutex::new(None),
        }
    }

    /// Prints `text` as a line of its own, above the bar on a terminal.
    pub fn say(&self, text: &str) {
        self.bar.suspend(|| eprintln!("{}: {text}", self.label));
    }

    /// Records `done` of `total` steps. In a log, a line (`what` describes the step just
    /// done) when the gap since the last line (or the start) has passed, and for the last
    /// step when there were lines before.
    pub fn update(&self, done: usize, total: usize, what: impl FnOnce() -> String) {
        let elapsed = self.started.elapsed();
        if !self.lines {
            if self.bar.is_hidden() && elapsed >= self.bar_after && done < total {
                self.bar.set_draw_target(ProgressDrawTarget::stderr());
            }
            self.bar.set_length(total as u64);
            self.bar.set_position(done as u64);
            return;
        }
        let now = Instant::now();
        {
            let mut last = self.last_line.lock().unwrap_or_else(|e| e.into_inner());
            // The last step has its line only in a run long enough to have had others:
            // a quick command stays quiet.
            let due = now - last.unwrap_or(self.started) >= self.every;
            if !(due || (done >= total && last.is_some())) {
                return;
            }
            *last = Some(now);
        }
        let mut line = format!("{}: {} after {}", self.label, what(), duration(elapsed));
        if done > 0 && done < total {
            let left = elapsed.mul_f64((total - done) as f64 / done as f64);
            line.push_str(&format!(", about {} left", duration(left)));
        }
        eprintln!("{line}");
    }

    /// Sets the bar's message (a terminal only).
    pub fn set_message(&self, msg: String) {
        self.bar.set_message(msg);
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// A duration as a person reads it: `850 ms`, `12.3 s`, `4 min 10 s`, `2 h 5 min`.
pub fn duration(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s < 1.0 {
        format!("{:.0} ms", s * 1e3)
    } else if s < 60.0 {
        format!("{s:.1} s")
    } else if s < 3600.0 {
        let whole = s.round() as u64;
        format!("{} min {} s", whole / 60, whole % 60)
    } else {
        let minutes = (s / 60.0).round() as u64;
        format!("{} h {} min", minutes / 60, minutes % 60)
    }
}

#[cfg(test)]
mod tests {
    use super::duration;
    use std::time::Duration;

    #[test]
    fn durations_read_as_a_person_would() {
        assert_eq!(duration(Duration::from_millis(850)), "850 ms");
        assert_eq!(duration(Duration::from_millis(12_340)), "12.3 s");
        assert_eq!(duration(Duration::from_secs(250)), "4 min 10 s");
        assert_eq!(duration(Duration::from_secs(2 * 3600 + 5 * 60 + 20)), "2 h 5 min");
    }
}
