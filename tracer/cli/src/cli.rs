//! The `tracer` command line as clap parses it: the subcommands and their options.

use crate::{accuracy, bench, merge, render, viewer};
use clap::{Parser, Subcommand};

/// The whole command line.
#[derive(Parser, Debug)]
#[command(
    name = "tracer",
    version,
    about = "A Whitted ray tracer built on vecexpr"
)]
pub struct Cli {
    /// The subcommand and its options.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
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
