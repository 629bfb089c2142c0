//! The `dynray` command line: parses arguments and dispatches; all work lives in the
//! library crates and in `commands/`.

mod cli;
mod commands;

use clap::Parser;
use std::process::ExitCode;

/// Exit codes: 0 success, 1 a failure the message explains (bad input, unwritable
/// output, ...), 2 a usage error (clap's own code).
fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match commands::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            // A closed pipe (`dynray info x | head`) is not an error worth a message.
            if err.chain().any(|e| {
                e.downcast_ref::<std::io::Error>().is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
            }) {
                return ExitCode::SUCCESS;
            }
            eprintln!("dynray: {err:#}");
            ExitCode::FAILURE
        }
    }
}
