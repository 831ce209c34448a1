//! What the subcommands share: the precision, the scheduler and packet options, the OBJ
//! camera options, threshold parsing, and the one way every subcommand reads a scene.

use std::path::Path;
use tracer::packets::Packets;
use tracer::render::{Schedule, Scheduler};
use tracer::scene::{self, desc::SceneDesc, CameraDesc, ObjOptions, Shape};

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

/// The camera options: they frame an OBJ scene and override an NFF scene's camera.
#[derive(clap::Args, Debug, Clone, Default, PartialEq)]
pub struct CameraArgs {
    /// Camera position (x,y,z); overrides an NFF scene's `from`.
    #[arg(long, value_parser = scene::parse_vec3, allow_hyphen_values = true)]
    pub from: Option<[f64; 3]>,
    /// Camera target (x,y,z); overrides an NFF scene's `at`.
    #[arg(long, value_parser = scene::parse_vec3, allow_hyphen_values = true)]
    pub at: Option<[f64; 3]>,
    /// Camera up vector (x,y,z); overrides an NFF scene's `up`.
    #[arg(long, value_parser = scene::parse_vec3, allow_hyphen_values = true)]
    pub up: Option<[f64; 3]>,
    /// Vertical angle of view in degrees, in (0, 180); overrides an NFF scene's `angle`.
    #[arg(long, allow_negative_numbers = true)]
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

    /// The names of the options given (`from`, `at`, `up`, `angle`), in that order.
    pub fn given(&self) -> Vec<&'static str> {
        [
            ("from", self.from.is_some()),
            ("at", self.at.is_some()),
            ("up", self.up.is_some()),
            ("angle", self.angle.is_some()),
        ]
        .into_iter()
        .filter_map(|(n, g)| g.then_some(n))
        .collect()
    }

    /// Replaces the fields of `camera` these arguments give (an NFF scene's camera), and
    /// checks the result as the OBJ reader checks its options.
    ///
    /// # Errors
    /// A message for an angle outside (0, 180), `from` equal to `at`, or `up` parallel
    /// to the view direction.
    pub fn apply(&self, camera: &mut CameraDesc) -> Result<(), String> {
        let mut c = camera.clone();
        if let Some(v) = self.from {
            c.from = v;
        }
        if let Some(v) = self.at {
            c.at = v;
        }
        if let Some(v) = self.up {
            c.up = v;
        }
        if let Some(a) = self.angle {
            if !(a > 0.0 && a < 180.0) {
                return Err(format!(
                    "--angle must be between 0 and 180 degrees, got {a}"
                ));
            }
            c.angle_deg = a;
        }
        let dir = [0, 1, 2].map(|k| c.at[k] - c.from[k]);
        if dir == [0.0; 3] {
            return Err("the camera's `from` equals its `at`".into());
        }
        let cross = [
            dir[1] * c.up[2] - dir[2] * c.up[1],
            dir[2] * c.up[0] - dir[0] * c.up[2],
            dir[0] * c.up[1] - dir[1] * c.up[0],
        ];
        let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if len(cross) <= 1e-12 * len(dir) * len(c.up) {
            return Err("the camera's `up` is parallel to its view direction".into());
        }
        *camera = c;
        Ok(())
    }
}

/// Whether `path` is read as OBJ (as [`scene::load_for`] decides).
pub fn is_obj(path: &Path) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    name.ends_with(".obj") || name.ends_with(".obj.gz")
}

/// Reads a scene with the camera options: they frame an OBJ scene and override the
/// camera of an NFF scene. Returns the scene and a warning for an OBJ scene that looks
/// z-up (its bounding box at least [`Z_UP_RATIO`] times taller in z than in y) when no
/// `--up` was given.
///
/// # Errors
/// As [`load_scene`], and `FILE: message` for camera options that give no valid camera.
pub fn load_scene_with_camera(
    path: &Path,
    camera: &CameraArgs,
    precision: Precision,
) -> Result<(SceneDesc, Option<String>), String> {
    let mut desc = load_scene(path, &camera.obj_options(), precision)?;
    if !is_obj(path) {
        camera
            .apply(&mut desc.camera)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        return Ok((desc, None));
    }
    let warning = match (camera.up, bounds(&desc)) {
        (None, Some((lo, hi))) => {
            let (dy, dz) = (hi[1] - lo[1], hi[2] - lo[2]);
            (dz > Z_UP_RATIO * dy).then(|| {
                format!(
                    "{}: warning: the model is {} times taller in z than in y; \
                     if it is z-up, pass --up 0,0,1",
                    path.display(),
                    if dy > 0.0 {
                        format!("{:.1}", dz / dy)
                    } else {
                        "infinitely many".to_string()
                    }
                )
            })
        }
        _ => None,
    };
    Ok((desc, warning))
}

/// How much taller in z than in y an OBJ model's bounding box must be to be warned
/// about as probably z-up.
pub const Z_UP_RATIO: f64 = 2.0;

/// The bounding box of the vertices of a scene's polygons and patches.
pub fn bounds(desc: &SceneDesc) -> Option<([f64; 3], [f64; 3])> {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for s in &desc.shapes {
        let points: &[[f64; 3]] = match &s.shape {
            Shape::Polygon { vertices } | Shape::Patch { vertices, .. } => vertices,
            Shape::Sphere { center, .. } => std::slice::from_ref(center),
            Shape::Cone { base, .. } => std::slice::from_ref(base),
        };
        for p in points {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    (lo[0] <= hi[0]).then_some((lo, hi))
}

/// A value parser for a whole number from `lo` to `hi`, with a message of its own for
/// anything else (a negative number included).
pub fn whole(
    lo: u32,
    hi: u32,
) -> impl Fn(&str) -> Result<u32, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        s.trim()
            .parse::<i64>()
            .ok()
            .filter(|v| (i64::from(lo)..=i64::from(hi)).contains(v))
            .map(|v| v as u32)
            .ok_or_else(|| format!("expected a whole number from {lo} to {hi}, got `{s}`"))
    }
}

/// The image size from `--width` and `--height` for a scene of `resolution`: both given,
/// both used; one given, the other follows the scene's aspect ratio (rounded, at least
/// 1); neither, the scene's.
///
/// # Errors
/// If the derived side exceeds `max`.
pub fn image_size(
    width: Option<u32>,
    height: Option<u32>,
    resolution: (u32, u32),
    max: u32,
) -> Result<(u32, u32), String> {
    let (sw, sh) = (
        f64::from(resolution.0.max(1)),
        f64::from(resolution.1.max(1)),
    );
    let derive = |given: u32, ratio: f64, name: &str| -> Result<u32, String> {
        let v = (f64::from(given) * ratio).round().max(1.0);
        if v > f64::from(max) {
            return Err(format!(
                "the scene's aspect ratio makes the {name} {v}, more than {max}; give both --width and --height"
            ));
        }
        Ok(v as u32)
    };
    Ok(match (width, height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, derive(w, sh / sw, "height")?),
        (None, Some(h)) => (derive(h, sw / sh, "width")?, h),
        (None, None) => resolution,
    })
}

/// Scheduler options shared by `render` and `bench`.
#[derive(clap::Args, Debug, Clone)]
pub struct ScheduleArgs {
    /// Parallel scheduler: rayon work stealing, static row blocks, or a dynamic tile queue.
    #[arg(long, value_enum, default_value_t = Scheduler::Rayon)]
    pub scheduler: Scheduler,
    /// Tile edge in pixels for --scheduler tiles (default 16; refused with the others).
    #[arg(long = "tile-size", value_name = "T", value_parser = whole(1, 4096), allow_negative_numbers = true)]
    pub tile_size: Option<u32>,
}

/// The tile edge without `--tile`.
pub const DEFAULT_TILE: u32 = 16;

impl ScheduleArgs {
    /// The schedule these arguments give.
    ///
    /// # Errors
    /// `--tile-size` with a scheduler other than `tiles`, which would ignore it.
    pub fn schedule(&self) -> Result<Schedule, String> {
        if let (Some(t), false) = (self.tile_size, self.scheduler == Scheduler::Tiles) {
            return Err(format!(
                "--tile-size {t} has no effect without --scheduler tiles"
            ));
        }
        Ok(Schedule {
            scheduler: self.scheduler,
            tile: self.tile_size.unwrap_or(DEFAULT_TILE),
        })
    }
}

/// Eye-ray packet options shared by `render` and `bench`.
#[derive(clap::Args, Debug, Clone)]
pub struct PacketArgs {
    /// Trace rays in SIMD packets: eye rays, their shadow rays, and reflection and
    /// refraction rays (the image is the same either way); auto: on with AVX2 or AVX-512,
    /// or with the --isa named.
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
    /// As [`Packets::from_args`]; a named `--isa` with `--packets off` would be ignored, so it is an error.
    pub fn packets(&self) -> Result<Packets, String> {
        if self.packets == "off" && self.isa != "auto" {
            return Err(format!(
                "--isa {} has no effect with --packets off (the instruction set is the packets')",
                self.isa
            ));
        }
        Packets::from_args(&self.packets, &self.isa)
    }
}

impl PacketArgs {
    /// Packets asked for by name (`--packets on` or a named `--isa`) where none are
    /// traced, in `f64`, would be ignored, so they are an error; `auto` and `off`
    /// always apply.
    ///
    /// # Errors
    /// A message naming the option and why it cannot apply.
    pub fn check_applies(&self, precision: Precision) -> Result<(), String> {
        let flag = if self.isa != "auto" {
            format!("--isa {}", self.isa)
        } else if self.packets == "on" {
            "--packets on".to_string()
        } else {
            return Ok(());
        };
        if precision == Precision::F64 {
            return Err(format!(
                "{flag} has no effect with --precision f64 (packets trace f32 rays only)"
            ));
        }
        Ok(())
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
    fn sizes_follow_the_aspect_ratio() {
        assert_eq!(
            image_size(Some(100), None, (640, 480), 65536),
            Ok((100, 75))
        );
        assert_eq!(image_size(None, Some(75), (640, 480), 65536), Ok((100, 75)));
        assert_eq!(image_size(Some(5), None, (640, 480), 65536), Ok((5, 4)));
        assert_eq!(image_size(Some(1), None, (100, 1), 65536), Ok((1, 1)));
        assert_eq!(image_size(None, None, (7, 9), 65536), Ok((7, 9)));
        assert!(image_size(Some(60000), None, (1, 2), 65536).is_err());
    }

    #[test]
    fn whole_numbers_in_range() {
        let p = whole(1, 10);
        assert_eq!(p("3"), Ok(3));
        assert_eq!(
            p("-5"),
            Err("expected a whole number from 1 to 10, got `-5`".to_string())
        );
        assert!(p("11").is_err());
        assert!(p("x").is_err());
    }

    #[test]
    fn camera_options_override_and_are_checked() {
        let mut cam = CameraDesc {
            from: [0.0, 0.0, 5.0],
            at: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            angle_deg: 45.0,
            hither: 1.0,
            resolution: (8, 8),
        };
        let args = CameraArgs {
            from: Some([1.0, 2.0, 3.0]),
            angle: Some(30.0),
            ..CameraArgs::default()
        };
        args.apply(&mut cam).unwrap();
        assert_eq!((cam.from, cam.angle_deg), ([1.0, 2.0, 3.0], 30.0));
        assert_eq!(args.given(), ["from", "angle"]);
        let parallel = CameraArgs {
            up: Some([1.0, 2.0, 3.0]),
            at: Some([2.0, 4.0, 6.0]),
            ..CameraArgs::default()
        };
        assert!(parallel.apply(&mut cam).is_err());
        let wide = CameraArgs {
            angle: Some(180.0),
            ..CameraArgs::default()
        };
        assert!(wide.apply(&mut cam).is_err());
        assert_eq!(cam.angle_deg, 30.0);
    }

    #[test]
    fn precision_names() {
        assert_eq!(Precision::F32.to_string(), "f32");
        assert_eq!(Precision::F64.name(), "f64");
    }
}
