//! `tracer merge TILES... -o OUT`: the tiles of one render ([`crate::tiles`]) put back
//! together into the full image, which equals the one-process render byte for byte; or,
//! with `--missing`, the indices of the tiles still to render.

use crate::output::{extension, ImageFormat, Staged};
use crate::render::write_image;
use crate::tiles::{self, TileHeader};
use serde_json::json;
use std::io::Write;
use std::path::{Path, PathBuf};
use tracer::{Image, RayCounts};

/// Options of `tracer merge`.
#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// Tile files written by `tracer render --tile` (or --pixel-bounds/--crop to .exr).
    #[arg(required = true)]
    pub tiles: Vec<PathBuf>,
    /// The full image: .png, .pfm or .exr.
    #[arg(short, long, required_unless_present = "missing")]
    pub output: Option<PathBuf>,
    /// Print the indices of the split's tiles that are not among TILES, comma-separated
    /// for `sbatch --array=...` (nothing when all are there), and write nothing.
    #[arg(long, conflicts_with = "output")]
    pub missing: bool,
    /// Write the summed ray counts and the tasks' times as JSON.
    #[arg(long, value_name = "STATS.json", conflicts_with = "missing")]
    pub stats: Option<PathBuf>,
    /// PNG only: sRGB-encoded values tagged `sRGB` (as `render --srgb`) instead of the
    /// linear values tagged `gAMA` 1.0.
    #[arg(long, conflicts_with = "missing")]
    pub srgb: bool,
}

/// Runs `tracer merge`.
///
/// # Errors
/// One line naming the tiles concerned: unreadable, foreign, overlapping, duplicate or
/// missing tiles; nothing is written then.
pub fn run(args: &MergeArgs) -> Result<(), String> {
    // The outputs are checked before any tile is read, and written together or not
    // at all.
    let staged = match &args.output {
        None => None,
        Some(out) => {
            let format = ImageFormat::of(out).ok_or_else(|| {
                format!("{}: output must end in .png, .pfm or .exr", out.display())
            })?;
            if args.srgb && format != ImageFormat::Png {
                return Err(format!(
                    "{}: --srgb applies to PNG output only",
                    out.display()
                ));
            }
            if let Some(stats) = &args.stats {
                if extension(stats).as_deref() != Some("json") {
                    return Err(format!("{}: statistics must end in .json", stats.display()));
                }
            }
            let mut paths = vec![out.as_path()];
            paths.extend(args.stats.as_deref());
            Some((format, Staged::new(&paths)?))
        }
    };
    let headers: Vec<TileHeader> = args
        .tiles
        .iter()
        .map(|p| tiles::read_header(p))
        .collect::<Result<_, _>>()?;
    let set: Vec<(&Path, &TileHeader)> = args
        .tiles
        .iter()
        .map(PathBuf::as_path)
        .zip(&headers)
        .collect();
    let missing = tiles::check_set(&set)?;
    let list = missing
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(",");
    if args.missing {
        if !list.is_empty() {
            println!("{list}");
        }
        return Ok(());
    }
    if !missing.is_empty() {
        let n = headers[0].tile.map_or(0, |(_, n)| n);
        return Err(format!(
            "tiles {list} of {n} are missing (rerun them, e.g. sbatch --array={list} ...)"
        ));
    }
    let (w, h) = headers[0].full;
    let mut image = Image::new(w, h);
    for (path, header) in set {
        let part = tiles::read_exr(path)?;
        let b = header.bounds;
        if (part.width, part.height) != (b.width(), b.height()) {
            return Err(format!(
                "{}: pixels do not match the data window",
                path.display()
            ));
        }
        for (y, row) in part.pixels.chunks(part.width as usize).enumerate() {
            let at = (b.y0 as usize + y) * w as usize + b.x0 as usize;
            image.pixels[at..at + row.len()].copy_from_slice(row);
        }
    }
    let (format, mut staged) = staged.expect("clap requires -o without --missing");
    let mut rays = RayCounts::default();
    for t in &headers {
        rays += t.rays;
    }
    let header = TileHeader {
        bounds: tracer::render::PixelBounds::full(w, h),
        tile: None,
        rays,
        times_ms: [0.0, 0.0, headers.iter().map(|t| t.times_ms[2]).sum()],
        ..headers[0].clone()
    };
    staged.write(0, "image", |out| {
        write_image(&image, format, args.srgb, &header, out)
    })?;
    if args.stats.is_some() {
        let tasks: Vec<_> = args
            .tiles
            .iter()
            .zip(&headers)
            .map(|(p, t)| {
                json!({
                    "file": p.display().to_string(),
                    "tile": t.tile.map(|(i, n)| format!("{i}/{n}")),
                    "region": t.bounds,
                    "rays": t.rays,
                    "times_ms": { "parse": t.times_ms[0], "build": t.times_ms[1], "trace": t.times_ms[2] },
                })
            })
            .collect();
        let report = json!({
            "image": { "width": w, "height": h },
            "settings": headers[0].settings,
            "digest": headers[0].digest,
            "rays": rays,
            "tasks": tasks,
        });
        let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        staged.write(1, "stats", |out| {
            out.write_all(text.as_bytes())?;
            out.write_all(b"\n")
        })?;
    }
    staged.commit()
}
