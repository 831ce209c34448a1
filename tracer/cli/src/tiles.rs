//! Parts of one image rendered apart and put back together: the split of an image into
//! tiles ([`split`]), the tile index a cluster scheduler hands a task ([`TileSpec`]),
//! the OpenEXR file a tile is written to with its place and provenance in the header
//! ([`write_exr`], [`read_header`], [`read_exr`]), and the digest that tells whether
//! tiles belong together ([`Digest`]).
//!
//! A tile file is an OpenEXR image whose display window is the full image and whose
//! data window is the tile's pixel bounds (as pbrt-v4 writes crop windows), with float
//! R, G, B channels holding the linear values the renderer computed, so that putting the
//! tiles together gives the full render's values bit for bit. The header carries the
//! attributes in [`attr`].

use std::collections::HashMap;
use std::path::Path;
use tracer::effects;
use tracer::render::{PixelBounds, Settings};
use tracer::shade::trace_fx;
use tracer::{Float, Image, RayCounts, Scene};

/// The custom header attributes of a tile file.
pub mod attr {
    /// The [`Digest`](super::Digest) of the scene file and every image-affecting
    /// setting, as 16 hex digits.
    pub const DIGEST: &str = "tracer.digest";
    /// The settings in words, for a person reading the header.
    pub const SETTINGS: &str = "tracer.settings";
    /// `I/N` for tile `I` of an `N`-tile split; absent for other bounds.
    pub const TILE: &str = "tracer.tile";
    /// Ray counts `eye reflection refraction shadow`.
    pub const RAYS: &str = "tracer.rays";
    /// Milliseconds `parse build trace` of the task that rendered the tile.
    pub const TIMES_MS: &str = "tracer.times_ms";
}

/// Which tile a task renders: `I/N`, or `auto` (`auto/N`) for the index (and count)
/// that the cluster's scheduler puts in the environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileSpec {
    /// Tile `index` of `count`.
    Index {
        /// From 0.
        index: u32,
        /// Tiles in the split.
        count: u32,
    },
    /// The index from the environment; the count too unless given.
    Auto {
        /// The count, when given after `auto/`.
        count: Option<u32>,
    },
}

/// The largest number of tiles of a split.
pub const MAX_TILES: u32 = 4096;

impl TileSpec {
    /// Parses `I/N`, `auto` or `auto/N` (clap value parser).
    ///
    /// # Errors
    /// A message saying which form is expected.
    pub fn parse(text: &str) -> Result<Self, String> {
        let form = "expected I/N (tile I of N, from 0), auto or auto/N";
        let count = |n: &str| -> Result<u32, String> {
            match n.parse::<u32>() {
                Ok(n) if (1..=MAX_TILES).contains(&n) => Ok(n),
                _ => Err(format!("tile count `{n}` must be 1 to {MAX_TILES}")),
            }
        };
        match text.split_once('/') {
            None if text == "auto" => Ok(Self::Auto { count: None }),
            Some(("auto", n)) => Ok(Self::Auto {
                count: Some(count(n)?),
            }),
            Some((i, n)) => {
                let count = count(n)?;
                let index = i
                    .parse::<u32>()
                    .map_err(|_| format!("tile index `{i}`: {form}"))?;
                if index >= count {
                    return Err(format!(
                        "tile index {index} of {count}: indices run from 0 to {}",
                        count - 1
                    ));
                }
                Ok(Self::Index { index, count })
            }
            None => Err(format!("`{text}`: {form}")),
        }
    }

    /// The index and count, taking what `auto` leaves open from `env` (the process
    /// environment in use): Slurm array jobs' `SLURM_ARRAY_TASK_ID` and
    /// `SLURM_ARRAY_TASK_COUNT`, or Kubernetes Indexed Jobs' `JOB_COMPLETION_INDEX` (whose
    /// count must be given as `auto/N`).
    ///
    /// # Errors
    /// One line naming the variable that is missing or wrong.
    pub fn resolve(self, env: impl Fn(&str) -> Option<String>) -> Result<(u32, u32), String> {
        let (given, index_var) = match self {
            Self::Index { index, count } => return Ok((index, count)),
            Self::Auto { count } => (
                count,
                ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"]
                    .into_iter()
                    .find(|v| env(v).is_some()),
            ),
        };
        let Some(var) = index_var else {
            return Err(
                "--tile auto: neither SLURM_ARRAY_TASK_ID nor JOB_COMPLETION_INDEX is set".into(),
            );
        };
        let read = |name: &str| -> Result<u32, String> {
            let v = env(name).unwrap_or_default();
            v.trim()
                .parse::<u32>()
                .map_err(|_| format!("--tile auto: {name}=`{v}` is not a number"))
        };
        let index = read(var)?;
        let count = match given {
            Some(n) => n,
            None if var == "SLURM_ARRAY_TASK_ID" => read("SLURM_ARRAY_TASK_COUNT")?,
            None => {
                return Err(format!(
                    "--tile auto: {var} gives no tile count; use --tile auto/N"
                ))
            }
        };
        if count == 0 || count > MAX_TILES {
            return Err(format!(
                "--tile auto: {count} tiles; 1 to {MAX_TILES} allowed"
            ));
        }
        if index >= count {
            return Err(format!(
                "--tile auto: {var}={index} but only {count} tiles; when resubmitting some \
                 tasks of an array, give the split's count as --tile auto/N"
            ));
        }
        Ok((index, count))
    }
}

/// The bounds of tile `index` of an `count`-tile split of the image `settings` give for
/// `scene`: bands of whole rows, cut so that each holds about the same estimated work.
///
/// Rows of equal height are not equal work (on balls-s* the sky rows cost one ray a
/// pixel, the rows through the spheres several), so the work of each row is estimated
/// first from a sample of the image: `min(h, max(4 count, 64))` rows spread over its
/// height, each sampled at `min(w, 64)` pixel centres spread over its width, one eye ray
/// per sample traced with the image's camera and settings, and a row's cost taken as the
/// rays its samples traced (eye, reflection, refraction and shadow). Ray counts, unlike times, are the same on every
/// machine and thread count, so every task of a split computes the same cuts. The
/// estimate costs about `max(4 count, 64) * 64` pixels of work per task.
///
/// # Errors
/// When the image has fewer rows than `count`.
pub fn split<T: Float>(
    scene: &Scene<T>,
    settings: &Settings,
    count: u32,
) -> Result<Vec<PixelBounds>, String> {
    let (w, h) = settings.size(scene.camera.resolution);
    if count > h {
        return Err(format!(
            "{count} tiles but the image has {h} rows; a tile is at least one row"
        ));
    }
    let rows = row_costs(scene, settings, (w, h), count);
    Ok(cut(&rows, w, count))
}

/// The probe's pixels per row (fewer when the image is narrower).
const PROBE_WIDTH: u32 = 64;
/// The probe's fewest rows (fewer when the image has fewer); `4 count` when more.
const PROBE_ROWS: u32 = 64;

/// The estimated work of each of the `h` rows of a `w` x `h` image (see [`split`]).
fn row_costs<T: Float>(
    scene: &Scene<T>,
    settings: &Settings,
    (w, h): (u32, u32),
    count: u32,
) -> Vec<f64> {
    let (lw, lh) = (w.min(PROBE_WIDTH), h.min((4 * count).max(PROBE_ROWS)));
    // The full image's camera, so that the samples see the view the tiles see: a
    // smaller render of its own aspect ratio would see another part of the scene
    // (the vertical field of view is fixed, the horizontal one follows the aspect).
    let cam = scene.camera_for(w, h);
    let limits = settings.limits::<T>();
    // Sample k of n spread over m pixels: the centre of pixel floor((k + 1/2) m / n).
    let at = |k: u32, n: u32, m: u32| {
        (u64::from(2 * k + 1) * u64::from(m) / u64::from(2 * n)) as f64 + 0.5
    };
    let low: Vec<f64> = (0..lh)
        .map(|j| {
            let py = T::from_f64(at(j, lh, h));
            let mut counts = RayCounts::default();
            for i in 0..lw {
                counts.eye += 1;
                let ray = cam.ray(T::from_f64(at(i, lw, w)), py);
                trace_fx::<T, { effects::ALL }>(scene, &ray, 1, T::ONE, &limits, &mut counts);
            }
            counts.total() as f64
        })
        .collect();
    // Image row y takes the cost of sample row y * lh / h, the band of rows around it.
    (0..h as u64)
        .map(|y| low[(y * lh as u64 / h as u64) as usize].max(1.0))
        .collect()
}

/// Cuts rows of the given costs into `count` bands of consecutive rows, each at least
/// one row, band `k` ending where the running cost first reaches `(k + 1) / count` of
/// the total.
fn cut(rows: &[f64], w: u32, count: u32) -> Vec<PixelBounds> {
    let h = rows.len() as u32;
    let total: f64 = rows.iter().sum();
    let mut bounds = Vec::with_capacity(count as usize);
    let (mut y0, mut run, mut y) = (0u32, 0.0, 0u32);
    for k in 0..count {
        let last = k + 1 == count;
        let goal = total * f64::from(k + 1) / f64::from(count);
        // Leave at least one row for each band after this one.
        let limit = h - (count - k - 1);
        let mut y1 = y0 + 1;
        run += rows[y as usize];
        y += 1;
        while y1 < limit && (last || run < goal) {
            run += rows[y as usize];
            y += 1;
            y1 += 1;
        }
        bounds.push(PixelBounds {
            x0: 0,
            x1: w,
            y0,
            y1,
        });
        y0 = y1;
    }
    bounds
}

/// FNV-1a, 64 bits (Fowler, Noll and Vo; offset basis 0xcbf29ce484222325, prime
/// 0x100000001b3): a digest that is the same on every platform and Rust version, to
/// tell tiles of one render from another's. Not a defence against forgery.
#[derive(Clone, Copy, Debug)]
pub struct Digest(u64);

impl Default for Digest {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl Digest {
    /// Adds `bytes`, then a separator, so that `("ab", "c")` and `("a", "bc")` differ.
    pub fn add(&mut self, bytes: &[u8]) -> &mut Self {
        for &b in bytes.iter().chain(&[0xff]) {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
        self
    }

    /// 16 hex digits.
    pub fn hex(&self) -> String {
        format!("{:016x}", self.0)
    }
}

/// What a tile file's header says.
#[derive(Clone, Debug, PartialEq)]
pub struct TileHeader {
    /// Size of the whole image (the display window).
    pub full: (u32, u32),
    /// The pixels in the file (the data window).
    pub bounds: PixelBounds,
    /// [`attr::DIGEST`].
    pub digest: String,
    /// [`attr::SETTINGS`].
    pub settings: String,
    /// [`attr::TILE`]: index and count.
    pub tile: Option<(u32, u32)>,
    /// [`attr::RAYS`].
    pub rays: RayCounts,
    /// [`attr::TIMES_MS`]: parse, build, trace.
    pub times_ms: [f64; 3],
}

impl TileHeader {
    fn attributes(&self) -> Vec<(&'static str, String)> {
        let r = self.rays;
        let mut a = vec![
            (attr::DIGEST, self.digest.clone()),
            (attr::SETTINGS, self.settings.clone()),
            (
                attr::RAYS,
                format!("{} {} {} {}", r.eye, r.reflection, r.refraction, r.shadow),
            ),
            (
                attr::TIMES_MS,
                format!(
                    "{} {} {}",
                    self.times_ms[0], self.times_ms[1], self.times_ms[2]
                ),
            ),
        ];
        if let Some((i, n)) = self.tile {
            a.push((attr::TILE, format!("{i}/{n}")));
        }
        a
    }
}

/// Encodes `image` (the pixels `header.bounds` of a `header.full` image) as OpenEXR
/// into `out`: one layer of linear 32-bit float R, G, B, top row first, losslessly
/// compressed, the data window at the bounds, the display window the full image, and
/// the attributes of [`attr`].
///
/// # Errors
/// What the encoder or `out` reports.
///
/// # Panics
/// If `image` is not the size of the bounds.
pub fn write_exr(
    out: &mut (impl std::io::Write + std::io::Seek),
    image: &Image,
    header: &TileHeader,
) -> std::io::Result<()> {
    use exr::prelude::{
        AttributeValue, Encoding, IntegerBounds, Layer, LayerAttributes, SpecificChannels, Text,
        Vec2, WritableImage,
    };
    let b = header.bounds;
    assert_eq!((image.width, image.height), (b.width(), b.height()));
    let width = image.width as usize;
    let mut layer_attributes = LayerAttributes::named("");
    layer_attributes.layer_position = Vec2(b.x0 as i32, b.y0 as i32);
    let layer = Layer::new(
        (image.width as usize, image.height as usize),
        layer_attributes,
        Encoding::FAST_LOSSLESS,
        SpecificChannels::rgb(|p: Vec2<usize>| {
            let [r, g, b] = image.pixels[p.y() * width + p.x()];
            (r, g, b)
        }),
    );
    let mut exr_image = exr::image::Image::from_layer(layer);
    exr_image.attributes.display_window =
        IntegerBounds::new((0, 0), (header.full.0 as usize, header.full.1 as usize));
    for (k, v) in header.attributes() {
        exr_image
            .attributes
            .other
            .insert(Text::from(k), AttributeValue::Text(Text::from(v.as_str())));
    }
    exr_image
        .write()
        .non_parallel()
        .to_buffered(out)
        .map_err(std::io::Error::other)
}

/// Reads a tile file's header only.
///
/// # Errors
/// `PATH: message` when the file is unreadable, not OpenEXR, or not a tile.
pub fn read_header(path: &Path) -> Result<TileHeader, String> {
    let err = |m: String| format!("{}: {m}", path.display());
    std::fs::metadata(path).map_err(|e| err(format!("cannot read file: {e}")))?;
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| err(format!("not a readable OpenEXR file: {e}")))?;
    let h = meta
        .headers
        .first()
        .ok_or_else(|| err("no image in the file".into()))?;
    let text = |name: &str| -> Option<String> {
        let value = h
            .shared_attributes
            .other
            .get(&exr::meta::attribute::Text::from(name))
            .or_else(|| {
                h.own_attributes
                    .other
                    .get(&exr::meta::attribute::Text::from(name))
            })?;
        match value {
            exr::meta::attribute::AttributeValue::Text(t) => Some(t.to_string()),
            _ => None,
        }
    };
    let need = |name: &str| {
        text(name).ok_or_else(|| err(format!("not a tracer tile (no `{name}` attribute)")))
    };
    let display = h.shared_attributes.display_window;
    if display.position.x() != 0 || display.position.y() != 0 {
        return Err(err("display window does not start at 0,0".into()));
    }
    let pos = h.own_attributes.layer_position;
    let size = h.layer_size;
    let (x0, y0) = (
        u32::try_from(pos.x()).map_err(|_| err("negative data window".into()))?,
        u32::try_from(pos.y()).map_err(|_| err("negative data window".into()))?,
    );
    let bounds = PixelBounds {
        x0,
        x1: x0 + size.width() as u32,
        y0,
        y1: y0 + size.height() as u32,
    };
    let full = (display.size.width() as u32, display.size.height() as u32);
    if !bounds.fits(full.0, full.1) {
        return Err(err(format!(
            "data window {bounds} outside the {} x {} image",
            full.0, full.1
        )));
    }
    let numbers = |name: &str, n: usize| -> Result<Vec<f64>, String> {
        let v: Vec<f64> = need(name)?
            .split_whitespace()
            .map(str::parse)
            .collect::<Result<_, _>>()
            .map_err(|_| err(format!("bad `{name}` attribute")))?;
        if v.len() == n {
            Ok(v)
        } else {
            Err(err(format!("bad `{name}` attribute")))
        }
    };
    let rays = numbers(attr::RAYS, 4)?;
    let times = numbers(attr::TIMES_MS, 3)?;
    let tile = match text(attr::TILE) {
        None => None,
        Some(t) => match TileSpec::parse(&t) {
            Ok(TileSpec::Index { index, count }) => Some((index, count)),
            _ => return Err(err(format!("bad `{}` attribute `{t}`", attr::TILE))),
        },
    };
    Ok(TileHeader {
        full,
        bounds,
        digest: need(attr::DIGEST)?,
        settings: need(attr::SETTINGS)?,
        tile,
        rays: RayCounts {
            eye: rays[0] as u64,
            reflection: rays[1] as u64,
            refraction: rays[2] as u64,
            shadow: rays[3] as u64,
        },
        times_ms: [times[0], times[1], times[2]],
    })
}

/// Reads a tile's pixels (its data window), row-major.
///
/// # Errors
/// `PATH: message`.
pub fn read_exr(path: &Path) -> Result<Image, String> {
    use exr::prelude::{read, ReadChannels, ReadLayers, Vec2};
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| Image::new(size.width() as u32, size.height() as u32),
            |img: &mut Image, p: Vec2<usize>, (r, g, b): (f32, f32, f32)| {
                let w = img.width as usize;
                img.pixels[p.y() * w + p.x()] = [r, g, b];
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| format!("{}: cannot read tile pixels: {e}", path.display()))?;
    Ok(image.layer_data.channel_data.pixels)
}

/// The output path of frame or tile `k`: `%d` or `%0Nd` (N a digit) in the file name is
/// replaced by `k` (zero-padded to N digits); a path without one is returned as it is.
pub fn numbered(path: &Path, k: u32) -> std::path::PathBuf {
    let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
        return path.to_path_buf();
    };
    let Some(at) = name.find('%') else {
        return path.to_path_buf();
    };
    let rest = &name[at + 1..];
    let (digits, tail) = match rest.as_bytes() {
        [b'0', d @ b'1'..=b'9', b'd', ..] => ((d - b'0') as usize, &rest[3..]),
        [b'd', ..] => (0, &rest[1..]),
        _ => return path.to_path_buf(),
    };
    path.with_file_name(format!("{}{k:0digits$}{tail}", &name[..at]))
}

/// Does the file name hold a `%d` or `%0Nd` pattern ([`numbered`])?
pub fn has_number(path: &Path) -> bool {
    numbered(path, 0) != path
}

/// Checks that `tiles` (headers with their paths) make one image: the same digest and
/// size, disjoint bounds that cover every pixel. Returns the tile indices missing from
/// an `I/N` split (empty when it is complete), or the reason they do not belong
/// together.
///
/// # Errors
/// One line naming the tiles concerned.
pub fn check_set(tiles: &[(&Path, &TileHeader)]) -> Result<Vec<u32>, String> {
    let Some(&(p0, first)) = tiles.first() else {
        return Err("no tiles given".into());
    };
    for &(p, t) in &tiles[1..] {
        if t.digest != first.digest || t.full != first.full {
            return Err(format!(
                "{} is not a tile of the render of {} (scene or settings differ: {} against {})",
                p.display(),
                p0.display(),
                t.settings,
                first.settings
            ));
        }
        if t.tile.map(|(_, n)| n) != first.tile.map(|(_, n)| n) {
            return Err(format!(
                "{} and {} come from different splits",
                p.display(),
                p0.display()
            ));
        }
    }
    // Overlaps: an index seen twice, or bounds that intersect.
    let mut seen: HashMap<u32, &Path> = HashMap::new();
    for (k, &(p, t)) in tiles.iter().enumerate() {
        if let Some((i, _)) = t.tile {
            if let Some(q) = seen.insert(i, p) {
                return Err(format!(
                    "tile {i} given twice: {} and {}",
                    q.display(),
                    p.display()
                ));
            }
        }
        for &(q, u) in &tiles[..k] {
            let (a, b) = (t.bounds, u.bounds);
            if a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1 {
                return Err(format!(
                    "{} ({}) and {} ({}) overlap",
                    q.display(),
                    b,
                    p.display(),
                    a
                ));
            }
        }
    }
    let area: u64 = tiles
        .iter()
        .map(|(_, t)| u64::from(t.bounds.width()) * u64::from(t.bounds.height()))
        .sum();
    let full = u64::from(first.full.0) * u64::from(first.full.1);
    let missing: Vec<u32> = match first.tile {
        Some((_, n)) => (0..n).filter(|i| !seen.contains_key(i)).collect(),
        None => Vec::new(),
    };
    if area != full && missing.is_empty() {
        return Err(format!(
            "the tiles cover {area} of the {full} pixels of the {} x {} image",
            first.full.0, first.full.1
        ));
    }
    Ok(missing)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_parse_and_resolve() {
        assert_eq!(
            TileSpec::parse("3/8"),
            Ok(TileSpec::Index { index: 3, count: 8 })
        );
        assert!(TileSpec::parse("8/8").unwrap_err().contains("from 0 to 7"));
        assert!(TileSpec::parse("x").is_err());
        assert!(TileSpec::parse("1/0").is_err());
        let slurm = |v: &str| match v {
            "SLURM_ARRAY_TASK_ID" => Some("2".to_string()),
            "SLURM_ARRAY_TASK_COUNT" => Some("4".to_string()),
            _ => None,
        };
        let auto = TileSpec::parse("auto").unwrap();
        assert_eq!(auto.resolve(slurm), Ok((2, 4)));
        // A rerun of task 7 alone: Slurm says one task; the count must be given.
        let rerun = |v: &str| match v {
            "SLURM_ARRAY_TASK_ID" => Some("7".to_string()),
            "SLURM_ARRAY_TASK_COUNT" => Some("1".to_string()),
            _ => None,
        };
        assert!(auto.resolve(rerun).unwrap_err().contains("auto/N"));
        assert_eq!(
            TileSpec::parse("auto/8").unwrap().resolve(rerun),
            Ok((7, 8))
        );
        let k8s = |v: &str| (v == "JOB_COMPLETION_INDEX").then(|| "5".to_string());
        assert!(auto.resolve(k8s).is_err());
        assert_eq!(TileSpec::parse("auto/6").unwrap().resolve(k8s), Ok((5, 6)));
        assert!(auto
            .resolve(|_| None)
            .unwrap_err()
            .contains("SLURM_ARRAY_TASK_ID"));
    }

    #[test]
    fn cuts_cover_every_row_once_and_follow_the_cost() {
        for count in 1..=9 {
            for rows in [
                vec![1.0; 9],
                vec![1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 20.0, 20.0],
            ] {
                if count > rows.len() as u32 {
                    continue;
                }
                let b = cut(&rows, 5, count);
                assert_eq!(b.len(), count as usize);
                assert_eq!(b[0].y0, 0);
                assert_eq!(b.last().unwrap().y1, rows.len() as u32);
                for w in b.windows(2) {
                    assert_eq!(w[0].y1, w[1].y0);
                }
                assert!(b.iter().all(|t| t.height() >= 1 && t.width() == 5));
            }
        }
        // Two expensive rows at the bottom get a tile each of the three.
        let b = cut(&[1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 20.0, 20.0], 1, 3);
        assert_eq!((b[0].y0, b[0].y1, b[1].y1, b[2].y1), (0, 7, 8, 9));
    }

    #[test]
    fn row_costs_see_the_whole_width_of_the_image() {
        // A mirror sphere near the right edge of the upper half of a 4:1 image, sky
        // elsewhere: only samples spread over the image's own width (not a probe image
        // of another aspect ratio, which sees another width of the scene) find it.
        let nff = "v\nfrom 0 0 -10\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\n\
                   resolution 64 64\nb 0 0 0\nl 0 0 -10\nf 1 1 1 0.5 0.5 10 0 1\n\
                   s 13 2 0 1.5\n";
        let desc = tracer::scene::parse_nff(nff, "edge.nff").unwrap();
        let scene = Scene::<f32>::from_desc(&desc, &tracer::geometry::AccelOptions::default());
        let settings = Settings {
            width: Some(256),
            height: Some(64),
            ..Settings::default()
        };
        let rows = row_costs(&scene, &settings, (256, 64), 2);
        let sky = rows[63];
        assert_eq!(sky, 64.0, "a sky row costs one eye ray per sample");
        assert!(rows[..32].iter().any(|&c| c > sky), "{rows:?}");
        // The cut follows: the band holding the sphere is the shorter.
        let bands = cut(&rows, 256, 2);
        assert!(bands[0].height() < bands[1].height(), "{bands:?}");
    }

    #[test]
    fn numbered_names() {
        let p = Path::new("out/frame-%04d.png");
        assert_eq!(numbered(p, 7), Path::new("out/frame-0007.png"));
        assert_eq!(numbered(Path::new("t-%d.exr"), 12), Path::new("t-12.exr"));
        assert_eq!(numbered(Path::new("plain.png"), 3), Path::new("plain.png"));
        assert!(has_number(p) && !has_number(Path::new("a.png")));
    }

    #[test]
    fn digest_separates_fields() {
        let a = Digest::default().add(b"ab").add(b"c").hex();
        let b = Digest::default().add(b"a").add(b"bc").hex();
        assert_ne!(a, b);
        assert_eq!(a.len(), 16);
    }
}
