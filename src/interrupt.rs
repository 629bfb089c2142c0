//! SIGINT (Ctrl-C) and SIGTERM (a batch system's cancel, `kill`) end a run without
//! leaving the temporary file of an output being written: a watcher thread removes the
//! registered temporaries ([`dynray_geom::file::remove_temporaries`]), then exits with
//! 128 + the signal's number, as the shell reports a process killed by it.

/// Starts the watcher (once, at the start of `main`). Without it (not Unix, or signals
/// that cannot be watched) a signal ends the process as it would have anyway.
pub fn remove_temporaries_on_signals() {
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGINT, SIGTERM};
        let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
            return;
        };
        let _ = std::thread::Builder::new().name("signals".into()).spawn(move || {
            if let Some(signal) = signals.forever().next() {
                dynray_geom::file::remove_temporaries();
                std::process::exit(128 + signal);
            }
        });
    }
}
