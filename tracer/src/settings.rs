//! The options every layer reads: render [`Settings`] with their scheduler, packet and
//! effect choices, and the recursion limits ([`TraceLimits`]) derived from them.
//!
//! This module sits at the bottom of the crate and imports none of the tracer's other
//! modules but [`crate::arith`]; scene, geometry, shading, rendering and the front ends
//! all read it (as pbrt-v4's `options.h`).

use crate::arith::Arith;
use serde::Serialize;
use vecexpr::simd::Isa;
use vecexpr::Real;

/// Render settings. `None` sizes use the scene's own resolution.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Image width (default: the scene's).
    pub width: Option<u32>,
    /// Image height (default: the scene's).
    pub height: Option<u32>,
    /// Antialiasing: an `aa` x `aa` regular grid of rays per pixel (1 = one ray through
    /// the pixel centre).
    pub aa: u32,
    /// Maximum ray depth (eye rays are depth 1).
    pub depth: u32,
    /// Adaptive termination threshold on a ray's accumulated weight; 0 disables it.
    pub threshold: f64,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// SPD testing rules: 513x513 corner rays averaged into 512x512 pixels (in general
    /// (w+1) x (h+1) corner rays), depth 5, no adaptive cutoff, transmitters spawn
    /// reflection rays.
    pub spd: bool,
    /// The renderer specialised for the scene's effects, or the general one (the image
    /// is the same).
    pub effects: EffectsMode,
    /// How pixels are distributed over threads.
    pub schedule: Schedule,
    /// Approximate arithmetic in shading (default: exact).
    pub arith: Arith,
    /// Eye rays in SIMD packets ([`Packets::auto`] by default); the image is the same
    /// either way ([`crate::packets`]).
    pub packets: Packets,
    /// Render only these pixels of the image (`None`: all). Each pixel is bit for bit the
    /// pixel of the full render: the same rays, samples and order of operations.
    pub region: Option<PixelBounds>,
}

/// A rectangle of pixels, `x0..x1` by `y0..y1` (half-open, as pbrt-v4's
/// `--pixelbounds`), with `(0, 0)` the top-left pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub struct PixelBounds {
    /// First column.
    pub x0: u32,
    /// One past the last column.
    pub x1: u32,
    /// First row.
    pub y0: u32,
    /// One past the last row.
    pub y1: u32,
}

impl PixelBounds {
    /// Every pixel of a `width` x `height` image.
    pub fn full(width: u32, height: u32) -> Self {
        Self {
            x0: 0,
            x1: width,
            y0: 0,
            y1: height,
        }
    }

    /// Columns.
    pub fn width(&self) -> u32 {
        self.x1.saturating_sub(self.x0)
    }

    /// Rows.
    pub fn height(&self) -> u32 {
        self.y1.saturating_sub(self.y0)
    }

    /// Does it hold at least one pixel?
    pub fn is_empty(&self) -> bool {
        self.width() == 0 || self.height() == 0
    }

    /// Does it lie inside a `width` x `height` image?
    pub fn fits(&self, width: u32, height: u32) -> bool {
        self.x0 <= self.x1 && self.y0 <= self.y1 && self.x1 <= width && self.y1 <= height
    }
}

impl std::fmt::Display for PixelBounds {
    /// `x0,x1,y0,y1`, the form the command line takes.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.x1, self.y0, self.y1)
    }
}

/// The parallel scheduler.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Scheduler {
    /// rayon work stealing over rows.
    #[default]
    Rayon,
    /// One contiguous block of rows per thread, fixed in advance.
    Static,
    /// Square tiles taken one at a time from a shared atomic counter.
    Tiles,
}

/// Scheduler and tile size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Schedule {
    /// Which scheduler.
    pub scheduler: Scheduler,
    /// Tile edge in pixels for [`Scheduler::Tiles`] (at least 1).
    pub tile: u32,
}

impl Default for Schedule {
    /// rayon over rows; 16x16 tiles when tiles are chosen.
    fn default() -> Self {
        Self {
            scheduler: Scheduler::Rayon,
            tile: 16,
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            width: None,
            height: None,
            aa: 1,
            depth: 5,
            threshold: 0.0,
            threads: None,
            spd: false,
            effects: EffectsMode::Auto,
            schedule: Schedule::default(),
            arith: Arith::EXACT,
            packets: Packets::default(),
            region: None,
        }
    }
}

impl Settings {
    /// The image size these settings give for a scene of `resolution` (its camera's).
    pub fn size(&self, resolution: (u32, u32)) -> (u32, u32) {
        let (w, h) = resolution;
        (self.width.unwrap_or(w), self.height.unwrap_or(h))
    }

    /// The recursion limits in effect (SPD mode forces depth 5 and no threshold).
    pub fn limits<T: Real>(&self) -> TraceLimits<T> {
        if self.spd {
            TraceLimits {
                max_depth: 5,
                threshold: T::ZERO,
                spd: true,
                arith: self.arith,
            }
        } else {
            TraceLimits {
                max_depth: self.depth.max(1),
                threshold: T::from_f64(self.threshold.max(0.0)),
                spd: false,
                arith: self.arith,
            }
        }
    }
}

/// How eye rays are traced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Packets {
    /// One ray at a time.
    Off,
    /// In packets of the instruction set's width.
    On(Isa),
}

impl Default for Packets {
    /// [`Packets::auto`].
    fn default() -> Self {
        Self::auto()
    }
}

impl Packets {
    /// Packets of the widest instruction set of the running CPU when that is AVX2 or
    /// AVX-512; off on a CPU with SSE2 only (where packets of four rays execute 0.84 to
    /// 1.10 times the instructions of single rays, so no clear gain) and off x86-64.
    pub fn auto() -> Self {
        match Isa::detect() {
            Some(isa) if isa >= Isa::Avx2 => Self::On(isa),
            _ => Self::Off,
        }
    }

    /// The instruction set, when on.
    pub fn isa(self) -> Option<Isa> {
        match self {
            Self::Off => None,
            Self::On(isa) => Some(isa),
        }
    }

    /// `off` or the instruction set's name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Off => "off",
            Self::On(isa) => isa.name(),
        }
    }

    /// From the command line's `--packets auto|on|off` and `--isa auto|sse2|avx2|avx512`:
    /// `auto` packets are [`Packets::auto`] unless an instruction set is named.
    ///
    /// # Errors
    /// A message naming the instruction sets available when the CPU lacks the one asked
    /// for, or when the words are not among those above.
    pub fn from_args(packets: &str, isa_name: &str) -> Result<Self, String> {
        let isa = match isa_name {
            "auto" => Isa::detect(),
            name => {
                let Some(isa) = Isa::from_name(name) else {
                    return Err(format!("--isa {name}: expected auto, sse2, avx2 or avx512"));
                };
                if !isa.is_available() {
                    let have: Vec<&str> = Isa::available().iter().map(|i| i.name()).collect();
                    return Err(format!(
                        "--isa {name}: this CPU does not support {name} (available: {})",
                        if have.is_empty() {
                            "none".to_string()
                        } else {
                            have.join(", ")
                        }
                    ));
                }
                Some(isa)
            }
        };
        match (packets, isa) {
            ("off", _) => Ok(Self::Off),
            ("auto", Some(named)) if isa_name != "auto" => Ok(Self::On(named)),
            ("auto", _) => Ok(Self::auto()),
            ("on", Some(isa)) => Ok(Self::On(isa)),
            ("on", None) => Err("--packets on: no SIMD instruction set on this CPU".into()),
            (other, _) => Err(format!("--packets {other}: expected auto, on or off")),
        }
    }
}

/// How the renderer is chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum EffectsMode {
    /// The specialised renderer for the effects the scene and settings need.
    #[default]
    Auto,
    /// The general renderer, with every effect compiled in.
    All,
}

impl EffectsMode {
    /// `"auto"` or `"all"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::All => "all",
        }
    }
}

/// How deep and how far the recursion goes, and SPD's counting rules.
#[derive(Clone, Copy, Debug)]
pub struct TraceLimits<T: Real> {
    /// Maximum ray depth: eye rays are depth 1 and rays at this depth spawn no
    /// secondary rays (so 1 means local shading only).
    pub max_depth: u32,
    /// Adaptive termination: a secondary ray is spawned only if its accumulated weight
    /// (product of the $K_r$/$K_t$ along its path) is at least this. 0 disables it.
    pub threshold: T,
    /// SPD rules: transmitting surfaces spawn a reflection ray even when `Ks` is 0.
    pub spd: bool,
    /// Approximate arithmetic in shading (exact by default).
    pub arith: Arith,
}
