//! The `tracer` command line: `tracer render SCENE -o OUT [options]`, `tracer merge TILES...
//! -o OUT`, `tracer view SCENE`, `tracer bench SCENE...`, `tracer accuracy SCENE... [-o
//! REPORT_DIR]`.
//!
//! Exit status 0 on success, 2 on bad input or a failed write, with one line
//! `FILE:LINE: message` (or `FILE: message`) on stderr and no output file left behind;
//! SIGINT, SIGTERM or SIGHUP during `render` or `merge` ends it by that signal, leaving
//! no output file and no temporary one.

use clap::Parser;
use std::process::ExitCode;
use tracer_cli::cli::{Cli, Command};
use tracer_cli::{accuracy, bench, merge, output, render, viewer};

/// Parses the command line; help and version go to standard output as clap prints them,
/// and any other clap error becomes one line on standard error (its first paragraph,
/// without clap's usage and tips) and status 2.
fn parse() -> Result<Cli, ExitCode> {
    Cli::try_parse().map_err(|e| {
        use clap::error::ErrorKind::{
            DisplayHelp, DisplayHelpOnMissingArgumentOrSubcommand, DisplayVersion,
        };
        if matches!(
            e.kind(),
            DisplayHelp | DisplayVersion | DisplayHelpOnMissingArgumentOrSubcommand
        ) {
            e.exit();
        }
        let text = e.to_string();
        let first: Vec<&str> = text
            .lines()
            .take_while(|l| !l.trim().is_empty())
            .map(str::trim)
            .collect();
        eprintln!("{}", first.join(" "));
        ExitCode::from(2)
    })
}

fn main() -> ExitCode {
    let cli = match parse() {
        Ok(cli) => cli,
        Err(code) => return code,
    };
    // The commands that stage outputs: a signal removes what they have not yet put in
    // place.
    if matches!(cli.command, Command::Render(_) | Command::Merge(_)) {
        if let Err(e) = output::remove_on_signal() {
            eprintln!("cannot install the signal handlers: {e}");
            return ExitCode::from(2);
        }
    }
    let done = match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Merge(args) => merge::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::View(args) => viewer::run(&args),
        Command::Accuracy(args) => accuracy::run(&args),
    };
    match done {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("{msg}");
            ExitCode::from(2)
        }
    }
}
