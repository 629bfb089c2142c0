//! Progress of a bench run: a bar on a terminal, one line per step otherwise (a CI log,
//! `2> bench.log`), nothing when asked for none.
//!
//! On a terminal the bar ticks on its own (a spinner and the elapsed time), so a long
//! step — the rays and their brute-force answers on the dragon take minutes — is seen to
//! be moving.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

/// Progress over a known number of steps.
pub struct Progress {
    bar: ProgressBar,
    /// Print each step's message as a line (stderr is no terminal).
    lines: bool,
    done: AtomicU64,
    len: u64,
}

/// Progress over `len` steps: a bar when `show` and stderr is a terminal, lines when
/// `show` and it is not, silence otherwise.
pub fn progress_bar(show: bool, len: u64) -> Progress {
    let terminal = std::io::stderr().is_terminal();
    let bar = if show && terminal {
        let bar = ProgressBar::new(len);
        bar.enable_steady_tick(Duration::from_millis(250));
        bar
    } else {
        ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden())
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} {bar:30} {pos}/{len} {elapsed} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    Progress { bar, lines: show && !terminal, done: AtomicU64::new(0), len }
}

impl Progress {
    /// Names the step now running.
    pub fn set_message(&self, msg: String) {
        if self.lines {
            eprintln!("dynray bench: [{}/{}] {msg}", self.done.load(Ordering::Relaxed) + 1, self.len);
        }
        self.bar.set_message(msg);
    }

    /// Counts `n` finished steps.
    pub fn inc(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
        self.bar.inc(n);
    }

    /// Removes the bar (lines stay in the log).
    pub fn finish_and_clear(&self) {
        self.bar.finish_and_clear();
    }
}
