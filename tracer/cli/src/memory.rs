//! What a render will need in memory, estimated before the scene is built, and what the
//! machine has: a render that cannot fit is refused with one line instead of being killed
//! (or aborting on a failed allocation) halfway.
//!
//! [`Needs::estimate`] adds up the buffers of a render by the sizes the renderer
//! allocates: the image (three `f32` per pixel), the per-pixel radiance of a pass and its
//! copy when the scheduler hands out tiles (three scalars of the precision per grid point),
//! the running sums of supersampling, the eye-ray packets' blocks, the encoder's buffers,
//! and the built scene (a fixed allowance per primitive, [`BYTES_PER_PRIMITIVE`]).
//! [`available`] reads `MemAvailable` from `/proc/meminfo`, lowered to the cgroup's
//! `memory.max` headroom where one is set; elsewhere it is [`FIXED_CAP`].

use crate::output::ImageFormat;

/// The memory assumed available where `/proc/meminfo` cannot be read.
pub const FIXED_CAP: u64 = 16 << 30;

/// Bytes allowed per primitive for the built scene in `f32` (twice in `f64`): a rough
/// allowance. The built geometry and BVH of the SPD scenes take at most 94 bytes per
/// primitive of the file (gears-s4, whose polygons become several triangles; 20 to 30 in
/// the others, `bvh.bytes` of `--stats`); the rest is room for the build's temporaries.
/// The scene as read is already in memory when the check runs.
pub const BYTES_PER_PRIMITIVE: u64 = 512;

/// The buffers of one render, in bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Needs {
    /// The image: three `f32` per pixel.
    pub image: u64,
    /// Radiance per grid point, its tile copy, supersampling sums and packet blocks.
    pub trace: u64,
    /// The encoder's buffers (8-bit bytes and compressed data, or EXR blocks).
    pub encode: u64,
    /// The built scene.
    pub scene: u64,
}

/// What a render is: its size and the settings that change its buffers.
#[derive(Clone, Copy, Debug)]
pub struct Shape {
    /// Image width and height.
    pub size: (u32, u32),
    /// Bytes of one scalar: 4 (`f32`) or 8 (`f64`).
    pub scalar: u64,
    /// Rays per pixel and axis (`1`: no supersampling sums).
    pub aa: u32,
    /// SPD mode: a grid of `(w + 1) x (h + 1)` corner points.
    pub spd: bool,
    /// Eye-ray packets on.
    pub packets: bool,
    /// The output format.
    pub format: ImageFormat,
    /// Primitives in the scene.
    pub primitives: u64,
}

impl Needs {
    /// The buffers a render of `shape` allocates.
    pub fn estimate(s: &Shape) -> Self {
        let (w, h) = (u64::from(s.size.0), u64::from(s.size.1));
        let pixels = w * h;
        let points = if s.spd { (w + 1) * (h + 1) } else { pixels };
        let vec3 = 3 * s.scalar;
        // The values of a pass and their copy in the tiles of the tile scheduler.
        let mut trace = 2 * points * vec3;
        if s.aa > 1 && !s.spd {
            trace += pixels * vec3;
        }
        if s.packets {
            // Blocks of f32 radiance, rounded up to whole 4x4 blocks.
            trace += w.div_ceil(4) * 4 * h.div_ceil(4) * 4 * 12;
        }
        let encode = match s.format {
            // 8-bit bytes and at most as much compressed data again.
            ImageFormat::Png => 2 * 3 * pixels,
            ImageFormat::Pfm => 0,
            // The samples gathered into blocks, and their compressed copy.
            ImageFormat::Exr => 2 * 12 * pixels,
        };
        Self {
            image: 12 * pixels,
            trace,
            encode,
            scene: s.primitives * BYTES_PER_PRIMITIVE * (s.scalar / 4),
        }
    }

    /// All of it.
    pub fn total(&self) -> u64 {
        self.image + self.trace + self.encode + self.scene
    }

    /// `Ok` if the total fits in `available` bytes, else the message saying why not.
    ///
    /// # Errors
    /// One line with the total, its parts and what is available.
    pub fn check(&self, available: u64, what: &str) -> Result<(), String> {
        if self.total() <= available {
            return Ok(());
        }
        Err(format!(
            "{what} needs about {} of memory (image {}, trace buffers {}, encoder {}, scene {}), \
             more than the {} available",
            gib(self.total()),
            gib(self.image),
            gib(self.trace),
            gib(self.encode),
            gib(self.scene),
            gib(available)
        ))
    }
}

/// `n` bytes in GiB with two decimals.
pub fn gib(n: u64) -> String {
    format!("{:.2} GiB", n as f64 / f64::from(1u32 << 30))
}

/// The memory this process can still take: `MemAvailable`, at most the cgroup's
/// `memory.max` less its `memory.current`, or [`FIXED_CAP`] where there is no
/// `/proc/meminfo`.
pub fn available() -> u64 {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    available_from(
        read("/proc/meminfo").as_deref(),
        read("/sys/fs/cgroup/memory.max").as_deref(),
        read("/sys/fs/cgroup/memory.current").as_deref(),
    )
}

/// [`available`] from the texts of `/proc/meminfo`, the cgroup's `memory.max` (`max`
/// when unlimited) and `memory.current`, where they could be read.
pub fn available_from(meminfo: Option<&str>, max: Option<&str>, current: Option<&str>) -> u64 {
    let Some(mem) = meminfo.and_then(meminfo_available) else {
        return FIXED_CAP;
    };
    let number = |t: Option<&str>| t.and_then(|t| t.trim().parse::<u64>().ok());
    match (number(max), number(current)) {
        (Some(max), Some(cur)) => mem.min(max.saturating_sub(cur)),
        _ => mem,
    }
}

/// `MemAvailable` of a `/proc/meminfo` text, in bytes.
pub fn meminfo_available(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(w: u32, h: u32) -> Shape {
        Shape {
            size: (w, h),
            scalar: 4,
            aa: 1,
            spd: false,
            packets: false,
            format: ImageFormat::Pfm,
            primitives: 0,
        }
    }

    #[test]
    fn buffers_add_up() {
        let n = Needs::estimate(&shape(10, 10));
        assert_eq!(n.image, 1200);
        assert_eq!(n.trace, 2400);
        let aa = Needs::estimate(&Shape {
            aa: 2,
            scalar: 8,
            ..shape(10, 10)
        });
        assert_eq!(aa.trace, 3 * 100 * 24);
        let spd = Needs::estimate(&Shape {
            spd: true,
            ..shape(10, 10)
        });
        assert_eq!(spd.trace, 2 * 121 * 12);
    }

    #[test]
    fn a_huge_image_is_refused_against_a_fixed_cap() {
        let n = Needs::estimate(&shape(65536, 65536));
        let err = n.check(FIXED_CAP, "65536x65536").unwrap_err();
        assert!(
            err.starts_with("65536x65536 needs about 144.00 GiB"),
            "{err}"
        );
        assert!(Needs::estimate(&shape(512, 512))
            .check(FIXED_CAP, "x")
            .is_ok());
    }

    #[test]
    fn available_is_meminfo_within_the_cgroup_or_a_fixed_cap() {
        let info = "MemAvailable:    1000 kB\n";
        assert_eq!(available_from(Some(info), None, None), 1_024_000);
        assert_eq!(
            available_from(Some(info), Some("max\n"), Some("5\n")),
            1_024_000
        );
        assert_eq!(
            available_from(Some(info), Some("600000\n"), Some("100000\n")),
            500_000
        );
        assert_eq!(available_from(None, Some("1"), Some("0")), FIXED_CAP);
        assert_eq!(available_from(Some("junk"), None, None), FIXED_CAP);
    }

    #[test]
    fn meminfo_parses() {
        let t = "MemTotal:       16000000 kB\nMemAvailable:    8000000 kB\n";
        assert_eq!(meminfo_available(t), Some(8_192_000_000));
        assert_eq!(meminfo_available("MemTotal: 1 kB\n"), None);
    }
}
