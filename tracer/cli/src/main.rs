//! The `tracer` command line: `tracer render SCENE -o OUT [options]`, `tracer merge TILES...
//! -o OUT`, `tracer view SCENE`, `tracer bench SCENE...`, `tracer accuracy SCENE... [-o
//! REPORT_DIR]`.
//!
//! Exit status 0 on success, 2 on bad input or a failed write, with one line
//! `FILE:LINE: message` (or `FILE: message`) on stderr and no output file left behind.

use clap::{Parser, Subcommand};
use std::process::ExitCode;
use tracer_cli::{accuracy, bench, merge, render, viewer};

#[derive(Parser, Debug)]
#[command(
    name = "tracer",
    version,
    about = "A Whitted ray tracer built on vecexpr"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene (.nff, .nff.gz or .obj) to an image (.png, .pfm or .exr), a part of
    /// one (a tile), or frames of a camera path.
    Render(render::RenderArgs),
    /// Put the tiles of one render together into the full image.
    Merge(merge::MergeArgs),
    /// Measure build time, ray throughput by kind and frame time of scenes.
    Bench(bench::BenchArgs),
    /// Open a window that renders SCENE continuously, with a camera to fly and live knobs.
    View(viewer::ViewArgs),
    /// Measure image error against render time for every cheaper setting of each knob.
    Accuracy(accuracy::AccuracyArgs),
}

fn main() -> ExitCode {
    let done = match Cli::parse().command {
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
