//! `wheelrail` command-line interface: evaluate operating points, sweep traction–creepage curves, write
//! local contact fields. Invalid input prints one line naming the value and its range and exits with 2.

mod commands;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // a closed output pipe (`wheelrail … | head`) ends the program quietly, as it does other Unix tools,
    // instead of a panic at the next print
    #[cfg(unix)]
    // SAFETY: sets the default disposition of one signal at start-up, before any other thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let args = match commands::Cli::try_parse() {
        Ok(a) => a,
        Err(e) => {
            // clap prints help/version to stdout (exit 0) and usage errors to stderr (exit 2)
            let _ = e.print();
            return ExitCode::from(e.exit_code().clamp(0, 255) as u8);
        }
    };
    match commands::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(commands::exit_code(&e))
        }
    }
}
