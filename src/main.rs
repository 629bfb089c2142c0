//! The `dynray` command line: parses arguments and dispatches; all work lives in the
//! library crates and in `commands/`.

mod cli;
mod commands;
mod interrupt;
mod progress;

use clap::Parser;
use std::process::ExitCode;

/// Exit codes: 0 success (also when the reader of stdout went away: `dynray info x |
/// head -1`), 1 a failure the message explains (bad input, unwritable output, ...), 2 a
/// usage error (clap's own code, and an option combination a job's check refuses).
fn main() -> ExitCode {
    quiet_vulkan_layers_without_a_session();
    interrupt::remove_temporaries_on_signals();
    let args = cli::Cli::parse();
    match commands::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            // A closed pipe is not an error worth a message.
            if err.chain().any(|e| {
                e.downcast_ref::<std::io::Error>().is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
            }) {
                return ExitCode::SUCCESS;
            }
            eprintln!("dynray: {}", message(&err));
            if err.downcast_ref::<commands::UsageError>().is_some() {
                ExitCode::from(2)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

/// Without a desktop session (XDG_RUNTIME_DIR unset: CI, ssh, containers), Mesa's
/// device-select Vulkan layer fails to reach a Wayland display and prints "error:
/// XDG_RUNTIME_DIR is invalid or not set" for every device opened, which reads like a
/// dynray failure. It only orders the adapters, which wgpu chooses among itself, so it is
/// switched off then (`NODEVICE_SELECT=1`, unless the user set it). Called first in
/// `main`, while the process has one thread, as changing the environment requires.
fn quiet_vulkan_layers_without_a_session() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() && std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

/// The error and its causes joined by `: `, each cause once: library errors often put
/// their source's text in their own message too (`dir.ply: Is a directory (os error
/// 21)` caused by `Is a directory (os error 21)`), and a person should not read it twice.
fn message(err: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in err.chain() {
        let text = cause.to_string();
        if text.is_empty() || out.contains(&text) {
            continue;
        }
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(&text);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::message;

    #[test]
    fn each_cause_is_printed_once() {
        let io = std::io::Error::other("Is a directory (os error 21)");
        let err = anyhow::Error::new(io).context("dir.ply: Is a directory (os error 21)").context("cannot load");
        assert_eq!(message(&err), "cannot load: dir.ply: Is a directory (os error 21)");
        let err = anyhow::anyhow!("the mesh has no triangles").context("the mesh has no triangles");
        assert_eq!(message(&err), "the mesh has no triangles");
        let err = anyhow::anyhow!("root cause").context("outer");
        assert_eq!(message(&err), "outer: root cause");
    }
}
