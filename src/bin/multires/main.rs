//! `multires`: the command line of the multiresolution editing library. One module per
//! subcommand; every job is a call of the library (`multires::load`, `workflow`,
//! `recipe`, `batch`, `halfedge::hierarchy::Hierarchy::{save, load}`).
//!
//! Exit codes: 0 when the job succeeded, 1 for an input or job error (one line on stderr
//! saying the file, the place and the reason), 2 for a usage error. It never panics: a
//! bug that would is caught and reported as an error.

mod args;
mod batch;
mod check;
mod convert;
mod distance;
mod edit;
mod info;
mod level;
mod output;
mod refine;
mod simplify;
mod workflow;

use std::process::ExitCode;

use clap::Parser;

use args::{Cli, Command};
use output::Output;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            let code = match e.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => 0,
                _ => 2,
            };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    // A panic (a bug) is reported as an error, never with a backtrace.
    std::panic::set_hook(Box::new(|_| {}));
    let out = Output::new(cli.quiet, cli.json);
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run(cli.command, &out)));
    match result {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            // one line: file, place and reason
            let message = e.to_string().replace(['\n', '\r'], " ");
            eprintln!("error: {message}");
            ExitCode::from(1)
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".to_owned());
            eprintln!("error: internal error (please report it): {what}");
            ExitCode::from(1)
        }
    }
}

fn run(command: Command, out: &Output) -> multires::Result<()> {
    match command {
        Command::Info(a) => info::run(a, out),
        Command::Check(a) => check::run(a, out),
        Command::Convert(a) => convert::run(a, out),
        Command::Simplify(a) => simplify::run(a, out),
        Command::Level(a) => level::run(a, out),
        Command::Edit(a) => edit::run(a, out),
        Command::Refine(a) => refine::run(a, out),
        Command::Workflow(a) => workflow::run(a, out),
        Command::Batch(a) => batch::run(a, out),
        Command::Distance(a) => distance::run(a, out),
    }
}
