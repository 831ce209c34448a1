//! The command line as a fuzz target: bytes become an argument vector, clap parses it as
//! `tracer` does ([`crate::cli::Cli`]), and each subcommand makes every check it makes
//! before its first ray, with the functions the commands themselves call:
//! [`render::prepare`], [`bench::prepare`], [`accuracy::prepare`]; `tracer merge` runs
//! whole (its tiles are small). `tracer view` is parsed only (it opens a window).
//!
//! Every path of the command line is taken inside a [`Sandbox`] directory, which holds
//! small scenes, a camera path and tiles; a path that leaves it (absolute, or with `..`)
//! skips the input. Nothing is rendered and nothing is written outside the sandbox;
//! whatever a run leaves in it is removed before the next. The AFL++ target is
//! `tracer/fuzz/src/bin/cli.rs`; the cli tests replay the committed corpus.

use crate::cli::{Cli, Command};
use crate::tiles::{self, TileHeader};
use crate::{accuracy, bench, merge, render};
use clap::Parser;
use std::collections::HashSet;
use std::ffi::OsString;
use std::fs;
use std::io;
use std::path::{Component, Path, PathBuf};
use tracer::render::PixelBounds;
use tracer::{Image, RayCounts};

/// What became of one input.
#[derive(Debug, PartialEq)]
pub enum Outcome {
    /// clap refused the command line (or printed help or the version): its message.
    Refused(String),
    /// A path leaves the sandbox, or the command is `tracer view`: nothing was checked.
    Outside,
    /// The checks before the first ray passed, or the message of the first that failed.
    Checked(Result<(), String>),
    /// `tracer merge` wrote its outputs.
    Wrote,
}

/// The files of a sandbox, relative to the `tracer` package's directory; each is copied
/// in under its own file name. `cube-mtl.bin` is split at its NUL byte into `cube.obj`
/// and the `cube.mtl` it names.
pub const FILES: &[&str] = &[
    "scenes/tetra-s1.nff",
    "scenes/balls-s1.nff",
    "scenes/showcase.nff",
    "fuzz/corpus/nff/tetra-s1.nff.gz",
    "fuzz/corpus/obj/cube-mtl.bin",
    "cli/tests/data/viewer-path.txt",
];

/// A directory with the files the fuzzed command lines name: the [`FILES`], a camera
/// path `path.txt` that `render --script` takes, a directory `sub`, the tiles
/// `tile-0.exr` and `tile-1.exr` (an 8 x 6 image split in two), `other-0.exr` (tile 0 of
/// a different render) and `part.exr` (a region without a tile index). Removed when
/// dropped.
pub struct Sandbox {
    dir: PathBuf,
    keep: HashSet<OsString>,
}

impl Sandbox {
    /// Creates `dir` (emptied first if it exists) with the [`FILES`] read from `tracer`,
    /// the `tracer` package's directory, and the tiles.
    ///
    /// # Errors
    /// A file that cannot be read or written.
    pub fn new(dir: &Path, tracer: &Path) -> io::Result<Self> {
        if dir.exists() {
            fs::remove_dir_all(dir)?;
        }
        fs::create_dir_all(dir.join("sub"))?;
        for file in FILES {
            let data = fs::read(tracer.join(file))?;
            let name = Path::new(file).file_name().unwrap_or_default();
            if name == "cube-mtl.bin" {
                let nul = data.iter().position(|&b| b == 0).unwrap_or(data.len());
                fs::write(dir.join("cube.obj"), &data[..nul])?;
                fs::write(dir.join("cube.mtl"), data.get(nul + 1..).unwrap_or(&[]))?;
            } else {
                fs::write(dir.join(name), data)?;
            }
        }
        fs::write(
            dir.join("path.txt"),
            "move 0.4\nyaw 4\npitch -3\nzoom 0.9\n",
        )?;
        let tile = |name: &str, digest: &str, bounds: PixelBounds, tile: Option<(u32, u32)>| {
            let header = TileHeader {
                full: (8, 6),
                bounds,
                digest: digest.into(),
                settings: "8x6 aa 1 depth 5 threshold 0 spd false precision f32".into(),
                tile,
                rays: RayCounts::default(),
                times_ms: [1.0, 2.0, 3.0],
            };
            let mut image = Image::new(bounds.width(), bounds.height());
            for (k, p) in image.pixels.iter_mut().enumerate() {
                *p = [k as f32 / 48.0, 0.5, 1.0];
            }
            let mut out = io::BufWriter::new(fs::File::create(dir.join(name))?);
            tiles::write_exr(&mut out, &image, &header)
        };
        let rows = |y0, y1| PixelBounds {
            x0: 0,
            x1: 8,
            y0,
            y1,
        };
        tile("tile-0.exr", "a", rows(0, 3), Some((0, 2)))?;
        tile("tile-1.exr", "a", rows(3, 6), Some((1, 2)))?;
        tile("other-0.exr", "b", rows(0, 3), Some((0, 2)))?;
        tile("part.exr", "a", rows(2, 4), None)?;
        let keep = fs::read_dir(dir)?
            .map(|e| e.map(|e| e.file_name()))
            .collect::<io::Result<_>>()?;
        Ok(Self {
            dir: dir.to_path_buf(),
            keep,
        })
    }

    /// The sandbox directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// One input: split at NUL and newline bytes into arguments (a final empty one
    /// dropped), parsed, and checked by its subcommand; errors are expected, panics are
    /// bugs.
    ///
    /// # Panics
    /// If the command panics, or leaves a file behind without having succeeded.
    pub fn run(&self, data: &[u8]) -> Outcome {
        let mut words: Vec<String> = data
            .split(|&b| b == 0 || b == b'\n')
            .map(|w| String::from_utf8_lossy(w).into_owned())
            .collect();
        if words.last().is_some_and(String::is_empty) {
            words.pop();
        }
        let cli = match Cli::try_parse_from(std::iter::once("tracer".to_string()).chain(words)) {
            Ok(cli) => cli,
            Err(e) => {
                // The message `tracer` prints (help and version included).
                return Outcome::Refused(e.to_string());
            }
        };
        // What an earlier run left is not this input's doing: under AFL++ that is a run
        // the fuzzer killed at its time limit, whose temporary files no code could remove
        // (SIGKILL), found by the next input's check below in the first campaign that
        // reported it (`regressions/cli/merge-after-a-killed-run`).
        self.clean();
        let outcome = self.check(cli);
        let left = self.clean();
        // Nothing half-written: a command that failed, or stopped before its first ray,
        // leaves no file behind (not even a temporary one).
        let wrote = matches!(outcome, Outcome::Wrote);
        assert!(wrote || left.is_empty(), "files left behind: {left:?}");
        outcome
    }

    /// The subcommand's checks, its paths taken inside the sandbox.
    fn check(&self, cli: Cli) -> Outcome {
        match cli.command {
            Command::Render(mut a) => {
                let inside = self.inside(&mut a.scene)
                    && self.inside(&mut a.output)
                    && a.stats.as_mut().is_none_or(|p| self.inside(p))
                    && a.script.as_mut().is_none_or(|p| self.inside(p));
                if !inside {
                    return Outcome::Outside;
                }
                Outcome::Checked(render::prepare(&a).map(drop))
            }
            Command::Merge(mut a) => {
                let inside = a.tiles.iter_mut().all(|p| self.inside(p))
                    && a.output.as_mut().is_none_or(|p| self.inside(p))
                    && a.stats.as_mut().is_none_or(|p| self.inside(p));
                if !inside {
                    return Outcome::Outside;
                }
                match merge::run(&a) {
                    Ok(()) if !a.missing => Outcome::Wrote,
                    done => Outcome::Checked(done),
                }
            }
            Command::Bench(mut a) => {
                let inside = a.scenes.iter_mut().all(|p| self.inside(p))
                    && a.peer.as_mut().is_none_or(|p| self.inside(p));
                if !inside {
                    return Outcome::Outside;
                }
                Outcome::Checked(bench::prepare(&a).map(drop))
            }
            Command::Accuracy(mut a) => {
                let inside =
                    a.scenes.iter_mut().all(|p| self.inside(p)) && self.inside(&mut a.output);
                if !inside {
                    return Outcome::Outside;
                }
                Outcome::Checked(accuracy::prepare(&a).map(drop))
            }
            Command::View(_) => Outcome::Outside,
        }
    }

    /// Puts a relative path without `..` inside the sandbox; false for any other.
    fn inside(&self, path: &mut PathBuf) -> bool {
        let ok = path
            .components()
            .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
        if ok {
            *path = self.dir.join(&*path);
        }
        ok
    }

    /// Removes what a run left in the sandbox (the outputs of `tracer merge`, or files
    /// a command should not have left), and returns their names.
    fn clean(&self) -> Vec<PathBuf> {
        let mut left = Vec::new();
        for (dir, keep) in [(self.dir.clone(), true), (self.dir.join("sub"), false)] {
            let Ok(entries) = fs::read_dir(&dir) else {
                continue;
            };
            for e in entries.flatten() {
                if keep && self.keep.contains(&e.file_name()) {
                    continue;
                }
                let p = e.path();
                let _ = if p.is_dir() {
                    fs::remove_dir_all(&p)
                } else {
                    fs::remove_file(&p)
                };
                left.push(p);
            }
        }
        left
    }
}

impl Drop for Sandbox {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.dir);
    }
}
