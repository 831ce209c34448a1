//! What the subcommands share: the precision, the scheduler and packet options, the OBJ
//! camera options, threshold parsing, and the one way every subcommand reads a scene.

use std::path::Path;
use tracer::packets::Packets;
use tracer::render::{Schedule, Scheduler};
use tracer::scene::{self, desc::SceneDesc, ObjOptions};

pub use tracer::scene::Precision;

/// Reads a scene file (NFF, gzip-compressed NFF, or OBJ framed by `obj`) with
/// [`tracer::scene::load_for`], refusing numbers that `precision` cannot hold; every
/// subcommand reads its scenes here.
///
/// # Errors
/// One line `FILE:LINE: message` (or `FILE: message`).
pub fn load_scene(
    path: &Path,
    obj: &ObjOptions,
    precision: Precision,
) -> Result<SceneDesc, String> {
    scene::load_for(path, obj, precision).map_err(|e| e.to_string())
}

/// The camera of an OBJ scene (an NFF scene carries its own and ignores these).
#[derive(clap::Args, Debug, Clone, Default, PartialEq)]
pub struct CameraArgs {
    /// OBJ camera position (x,y,z); NFF scenes carry their own camera.
    #[arg(long, value_parser = scene::parse_vec3, allow_hyphen_values = true)]
    pub from: Option<[f64; 3]>,
    /// OBJ camera target (x,y,z).
    #[arg(long, value_parser = scene::parse_vec3, allow_hyphen_values = true)]
    pub at: Option<[f64; 3]>,
    /// OBJ camera up vector (x,y,z).
    #[arg(long, value_parser = scene::parse_vec3, allow_hyphen_values = true)]
    pub up: Option<[f64; 3]>,
    /// OBJ camera vertical angle of view in degrees.
    #[arg(long)]
    pub angle: Option<f64>,
}

impl CameraArgs {
    /// The OBJ options these arguments give.
    pub fn obj_options(&self) -> ObjOptions {
        ObjOptions {
            from: self.from,
            at: self.at,
            up: self.up,
            angle: self.angle,
            ..ObjOptions::default()
        }
    }
}

/// Scheduler options shared by `render` and `bench`.
#[derive(clap::Args, Debug, Clone)]
pub struct ScheduleArgs {
    /// Parallel scheduler: rayon work stealing, static row blocks, or a dynamic tile queue.
    #[arg(long, value_enum, default_value_t = Scheduler::Rayon)]
    pub scheduler: Scheduler,
    /// Tile edge in pixels for --scheduler tiles.
    #[arg(long = "tile-size", value_name = "T", default_value_t = 16,
          value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub tile_size: u32,
}

impl ScheduleArgs {
    /// The schedule these arguments give.
    pub fn schedule(&self) -> Schedule {
        Schedule {
            scheduler: self.scheduler,
            tile: self.tile_size,
        }
    }
}

/// Eye-ray packet options shared by `render` and `bench`.
#[derive(clap::Args, Debug, Clone)]
pub struct PacketArgs {
    /// Trace eye rays in SIMD packets (the image is the same either way); auto: on with
    /// AVX2 or AVX-512, or with the --isa named.
    #[arg(long, value_parser = ["auto", "on", "off"], default_value = "auto")]
    pub packets: String,
    /// Instruction set of the packet kernels: the CPU's widest (auto) or a named one.
    #[arg(long, value_parser = ["auto", "sse2", "avx2", "avx512"], default_value = "auto")]
    pub isa: String,
}

impl PacketArgs {
    /// The packet choice these arguments give.
    ///
    /// # Errors
    /// As [`Packets::from_args`].
    pub fn packets(&self) -> Result<Packets, String> {
        Packets::from_args(&self.packets, &self.isa)
    }
}

/// Parses an adaptive-termination threshold in [0, 1].
///
/// # Errors
/// A message if `s` is not a number or lies outside [0, 1].
pub fn parse_threshold(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if !(0.0..=1.0).contains(&v) {
        return Err(format!("threshold must be in [0, 1], got {v}"));
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_in_range_only() {
        assert_eq!(parse_threshold("0.25"), Ok(0.25));
        assert_eq!(parse_threshold("0"), Ok(0.0));
        assert!(parse_threshold("1.5").is_err());
        assert!(parse_threshold("x").is_err());
    }

    #[test]
    fn precision_names() {
        assert_eq!(Precision::F32.to_string(), "f32");
        assert_eq!(Precision::F64.name(), "f64");
    }
}
