//! `tracer merge TILES... -o OUT`: the tiles of one render ([`crate::tiles`]) put back
//! together into the full image, which equals the one-process render byte for byte; or,
//! with `--missing`, the indices of the tiles still to render.

use crate::tiles::{self, TileHeader};
use serde_json::json;
use std::path::PathBuf;
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
}

/// Runs `tracer merge`.
///
/// # Errors
/// One line naming the tiles concerned: unreadable, foreign, overlapping, duplicate or
/// missing tiles; nothing is written then.
pub fn run(args: &MergeArgs) -> Result<(), String> {
    if let Some(out) = &args.output {
        let ext = out
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("png" | "pfm" | "exr")) {
            return Err(format!(
                "{}: output must end in .png, .pfm or .exr",
                out.display()
            ));
        }
    }
    let headers: Vec<TileHeader> = args
        .tiles
        .iter()
        .map(|p| tiles::read_header(p))
        .collect::<Result<_, _>>()?;
    let set: Vec<_> = args
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
    let out = args
        .output
        .as_ref()
        .expect("clap requires -o without --missing");
    let is_exr = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    let mut rays = RayCounts::default();
    for t in &headers {
        rays += t.rays;
    }
    if is_exr {
        let header = TileHeader {
            bounds: tracer::render::PixelBounds::full(w, h),
            tile: None,
            rays,
            times_ms: [0.0, 0.0, headers.iter().map(|t| t.times_ms[2]).sum()],
            ..headers[0].clone()
        };
        tiles::write_exr(out, &image, &header)?;
    } else {
        image
            .save(out)
            .map_err(|e| format!("{}: cannot write image: {e}", out.display()))?;
    }
    if let Some(path) = &args.stats {
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
        if let Err(e) = tracer::image::write_atomic(path, |w| {
            use std::io::Write;
            w.write_all(text.as_bytes())?;
            w.write_all(b"\n")
        }) {
            // No output at all when one of them fails.
            let _ = std::fs::remove_file(out);
            return Err(format!("{}: cannot write stats: {e}", path.display()));
        }
    }
    Ok(())
}
