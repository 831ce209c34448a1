//! The front ends of the [`tracer`] library, behind the `tracer` command: each
//! subcommand parses its flags ([`clap`]) and calls the library.
//!
//! - [`cli`]: the command line as clap parses it, subcommands and options;
//! - [`render`]: `tracer render`, one image and its statistics;
//! - [`bench`](mod@bench): `tracer bench`, build time, ray throughput and frame time;
//! - [`accuracy`]: `tracer accuracy`, image error against render time per setting;
//! - [`viewer`]: `tracer view`, the interactive window (winit, softbuffer);
//! - [`args`]: what they share: [`Precision`], the scheduler, packet and OBJ camera
//!   options, and [`args::load_scene`], the one way every subcommand reads a scene;
//! - [`merge`]: `tracer merge`, tiles of one render put together;
//! - [`tiles`]: the split of an image into tiles and their OpenEXR files;
//! - [`output`]: the output files of `tracer render`, checked first, written together;
//! - [`memory`]: the memory a render needs against what the machine has;
//! - [`progress`]: the progress bar, plain progress lines and summary of `tracer render`;
//! - [`fuzz`]: the command line as a fuzz target, every check before the first ray.
//!
//! The library itself links none of these crates: a program that renders with `tracer`
//! compiles no argument parser, window or progress bar.

pub mod accuracy;
pub mod args;
pub mod bench;
pub mod cli;
pub mod fuzz;
pub mod memory;
pub mod merge;
pub mod output;
pub mod progress;
pub mod render;
pub mod tiles;
pub mod viewer;

pub use args::Precision;
