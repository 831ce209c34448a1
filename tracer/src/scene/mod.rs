//! Scene files: Eric Haines' Neutral File Format (NFF, optionally gzip-compressed) and
//! Wavefront OBJ with MTL materials, read into a [`SceneDesc`].
//!
//! [`load`] picks the reader from the file name: `.obj` and `.obj.gz` go to
//! [`load_obj`] with default [`ObjOptions`], everything else (`.nff`, `.nff.gz`, ...) to
//! [`load_nff`]. Compression is recognised by the gzip magic bytes, whatever the name.
//! Every failure is a [`SceneError`] that prints as one `FILE:LINE: message` line; no
//! input makes a reader panic.
//!
//! Both formats map onto NFF's material model ([`MaterialDesc`]). Primitives that come
//! before any material (an NFF primitive before the first `f`, an OBJ face without a
//! known `usemtl`) get [`DEFAULT_MATERIAL`], a matte light grey.
//!
//! # Examples
//! ```
//! use tracer::scene::{parse_nff, Shape};
//! let text = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.1\nresolution 64 64\n\
//!             l 5 5 5\nf 1 0 0 1 0 1 0 1\ns 0 0 0 1\n";
//! let scene = parse_nff(text, "tiny.nff").unwrap();
//! assert_eq!(scene.camera.resolution, (64, 64));
//! assert!(matches!(scene.shapes[0].shape, Shape::Sphere { radius: 1.0, .. }));
//! assert_eq!(scene.shape_counts().spheres, 1);
//! ```

pub mod desc;
pub mod error;
pub mod nff;
pub mod obj;

use std::io::Read;
use std::path::Path;

pub use desc::{CameraDesc, LightDesc, MaterialDesc, SceneDesc, Shape, ShapeDesc, P3};
pub use error::SceneError;
pub use nff::{load_nff, load_nff_for, parse_nff, parse_nff_for};
pub use obj::{load_obj, load_obj_for, parse_obj, ObjOptions};

/// The most vertices one polygon (NFF `p`/`pp`, OBJ `f`) may have. It bounds what one
/// statement can make the reader allocate and the triangulation (whose ear clipping is
/// quadratic in the vertex count) must do; the largest faces in the SPD scenes have 144.
pub const MAX_POLYGON_VERTICES: usize = 1 << 16;

/// The most bytes a gzip-compressed scene may inflate to (4 GiB). Deflate compresses
/// at most about 1032:1, so without a limit a small forged file could ask for gigabytes.
pub const MAX_INFLATED_BYTES: u64 = 1 << 32;

/// The floating-point precision a scene will be rendered in, which bounds the numbers a
/// file may contain.
///
/// Why the readers check it, and not the conversion to [`crate::Scene`]: a number that
/// does not fit `f32` becomes infinite when converted, and the geometry builder then
/// drops the primitive as degenerate, so the scene silently loses it. The reader is the
/// only place that still knows the token and its line, so with [`Precision::F32`] it
/// refuses every number whose magnitude rounds to infinity in `f32` with a
/// `FILE:LINE: message` error, before anything is built; keeping a line for every
/// number of the description instead would grow every light and material of it for
/// the sake of an error. [`Precision::F64`] refuses only what `f64` cannot hold (as
/// the readers always did: `1e999`, `inf`, `nan`).
///
/// # Examples
/// ```
/// use tracer::scene::{parse_nff_for, Precision};
/// let text = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\ns 1e39 0 0 1\n";
/// let err = parse_nff_for(text, "big.nff", Precision::F32).unwrap_err();
/// assert_eq!(
///     err.to_string(),
///     "big.nff:2: number `1e39` does not fit in f32 (largest magnitude 3.4028235e38)"
/// );
/// assert!(parse_nff_for(text, "big.nff", Precision::F64).is_ok());
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Precision {
    /// Single precision: magnitudes up to `f32::MAX` (after rounding to nearest).
    F32,
    /// Double precision: every finite `f64`.
    #[default]
    F64,
}

impl std::fmt::Display for Precision {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Precision {
    /// The precision of the scalar type `T`.
    pub fn of<T: vecexpr::Real>() -> Self {
        if std::mem::size_of::<T>() <= 4 {
            Self::F32
        } else {
            Self::F64
        }
    }

    /// `"f32"` or `"f64"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::F32 => "f32",
            Self::F64 => "f64",
        }
    }

    /// Whether the finite `value` stays finite in this precision.
    pub fn fits(self, value: f64) -> bool {
        match self {
            // `as` rounds to nearest, so values just above `f32::MAX` that round down
            // to it fit, exactly as they would when the scene is converted.
            Self::F32 => (value as f32).is_finite(),
            Self::F64 => value.is_finite(),
        }
    }

    /// The message for a number `token` that does not fit.
    pub(crate) fn overflow_message(self, token: &[u8]) -> String {
        let largest = match self {
            Self::F32 => format!("{:e}", f32::MAX),
            Self::F64 => format!("{:e}", f64::MAX),
        };
        format!(
            "number `{}` does not fit in {} (largest magnitude {largest})",
            error::quote(token),
            self.name()
        )
    }
}

/// The material of primitives that precede every material statement: colour 0.8 grey,
/// fully diffuse (`kd = 1`), no specular or mirror term (`ks = 0`, `shine = 1`), opaque
/// (`t = 0`, `ior = 1`).
pub const DEFAULT_MATERIAL: MaterialDesc = MaterialDesc {
    color: [0.8, 0.8, 0.8],
    kd: 1.0,
    ks: 0.0,
    shine: 1.0,
    t: 0.0,
    ior: 1.0,
};

/// Loads a scene file, choosing the reader by name: `.obj` or `.obj.gz` (any case) is
/// read by [`load_obj`] with [`ObjOptions::default`], anything else as NFF by
/// [`load_nff`]. Gzip data is decompressed whatever the extension.
///
/// # Errors
/// A [`SceneError`] if the file cannot be read or is not a valid scene.
///
/// # Examples
/// ```
/// let err = tracer::scene::load(std::path::Path::new("no/such/file.nff")).unwrap_err();
/// assert_eq!(err.to_string(), "no/such/file.nff: cannot read file: No such file or directory");
/// ```
pub fn load(path: &Path) -> Result<SceneDesc, SceneError> {
    load_with(path, &ObjOptions::default())
}

/// [`load`] with `obj` as the options of an OBJ file (its camera, for example); an NFF
/// file carries its own camera and ignores them.
///
/// # Errors
/// As [`load`].
pub fn load_with(path: &Path, obj: &ObjOptions) -> Result<SceneDesc, SceneError> {
    load_for(path, obj, Precision::F64)
}

/// [`load_with`] for a scene to be rendered in `precision`: a number in the file that
/// does not fit it is an error naming the file and line (see [`Precision`]).
///
/// # Errors
/// As [`load`], and for a number out of `precision`'s range.
///
/// # Examples
/// ```
/// use tracer::scene::{load_for, ObjOptions, Precision};
/// let path = std::env::temp_dir().join("tracer-doc-load-for.nff");
/// std::fs::write(&path, "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n\
///                        c 0 0 0 1 0 4e38 0 1\n").unwrap();
/// let err = load_for(&path, &ObjOptions::default(), Precision::F32).unwrap_err();
/// assert_eq!(err.line(), Some(2));
/// assert!(load_for(&path, &ObjOptions::default(), Precision::F64).is_ok());
/// # std::fs::remove_file(&path).unwrap();
/// ```
pub fn load_for(
    path: &Path,
    obj: &ObjOptions,
    precision: Precision,
) -> Result<SceneDesc, SceneError> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if name.ends_with(".obj") || name.ends_with(".obj.gz") {
        load_obj_for(path, obj, precision)
    } else {
        load_nff_for(path, precision)
    }
}

/// Numbers of primitives of each kind in a scene, as [`SceneDesc::shape_counts`] gives
/// them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShapeCounts {
    /// [`Shape::Sphere`]s.
    pub spheres: usize,
    /// [`Shape::Cone`]s with equal end radii.
    pub cylinders: usize,
    /// [`Shape::Cone`]s with different end radii.
    pub cones: usize,
    /// [`Shape::Polygon`]s.
    pub polygons: usize,
    /// [`Shape::Patch`]es.
    pub patches: usize,
}

impl ShapeCounts {
    /// All primitives.
    pub fn total(&self) -> usize {
        self.spheres + self.cylinders + self.cones + self.polygons + self.patches
    }
}

impl SceneDesc {
    /// Counts the primitives of each kind.
    pub fn shape_counts(&self) -> ShapeCounts {
        let mut counts = ShapeCounts::default();
        for s in &self.shapes {
            match &s.shape {
                Shape::Sphere { .. } => counts.spheres += 1,
                Shape::Cone {
                    base_radius,
                    apex_radius,
                    ..
                } if base_radius == apex_radius => counts.cylinders += 1,
                Shape::Cone { .. } => counts.cones += 1,
                Shape::Polygon { .. } => counts.polygons += 1,
                Shape::Patch { .. } => counts.patches += 1,
            }
        }
        counts
    }
}

/// The two bytes every gzip member starts with (RFC 1952, section 2.3.1).
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// Reads `path` whole, decompressing it if it starts with the gzip magic bytes.
pub(crate) fn read_file(path: &Path, name: &str) -> Result<Vec<u8>, SceneError> {
    let data = std::fs::read(path).map_err(|e| SceneError::io(name, e))?;
    if data.starts_with(&GZIP_MAGIC) {
        gunzip(&data, name)
    } else {
        Ok(data)
    }
}

/// `data` decompressed if it starts with the gzip magic bytes, else borrowed as is.
pub(crate) fn maybe_gunzip<'a>(
    data: &'a [u8],
    name: &str,
) -> Result<std::borrow::Cow<'a, [u8]>, SceneError> {
    if data.starts_with(&GZIP_MAGIC) {
        gunzip(data, name).map(std::borrow::Cow::Owned)
    } else {
        Ok(std::borrow::Cow::Borrowed(data))
    }
}

/// Decompresses all gzip members of `data`, at most [`MAX_INFLATED_BYTES`] of them.
fn gunzip(data: &[u8], name: &str) -> Result<Vec<u8>, SceneError> {
    gunzip_at_most(data, name, MAX_INFLATED_BYTES)
}

/// The most bytes one byte of deflate data can inflate to, rounded up.
const MAX_DEFLATE_RATIO: usize = 1032;

/// Decompresses all gzip members of `data`; more than `limit` bytes is an error.
fn gunzip_at_most(data: &[u8], name: &str, limit: u64) -> Result<Vec<u8>, SceneError> {
    // The last four bytes hold the size of the last member modulo 2^32 (RFC 1952,
    // ISIZE): a good first allocation for the usual single-member file, capped so that
    // a forged trailer cannot ask for more than the data can inflate to (deflate's
    // largest ratio is about 1032:1, RFC 1951's longest match of 258 bytes in two bits
    // at best) nor for much.
    let hint = data
        .last_chunk::<4>()
        .map_or(0, |b| u32::from_le_bytes(*b) as usize)
        .min(data.len().saturating_mul(MAX_DEFLATE_RATIO))
        .min(1 << 28)
        .min(usize::try_from(limit).unwrap_or(usize::MAX));
    let mut out = Vec::with_capacity(hint);
    // One byte past the limit tells a file at the limit from one beyond it.
    flate2::read::MultiGzDecoder::new(data)
        .take(limit.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| {
            let reason = error::io_reason(&e);
            SceneError::whole_file(name, format!("invalid gzip data: {reason}")).with_source(e)
        })?;
    if out.len() as u64 > limit {
        return Err(SceneError::whole_file(
            name,
            format!("gzip data inflates to more than {limit} bytes"),
        ));
    }
    Ok(out)
}

/// Parses a command-line vector `x,y,z` (the OBJ camera options): three finite numbers
/// separated by commas, spaces around them allowed.
pub fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected x,y,z, got `{s}`"));
    }
    let mut v = [0.0; 3];
    for (o, p) in v.iter_mut().zip(parts) {
        *o = p
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("`{p}` is not a finite number"))?;
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn gzip(data: &[u8]) -> Vec<u8> {
        let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
        e.write_all(data).unwrap();
        e.finish().unwrap()
    }

    #[test]
    fn inflating_past_the_limit_is_an_error() {
        // 1 MiB of zeros compresses to about a kilobyte.
        let bomb = gzip(&vec![0; 1 << 20]);
        assert!(bomb.len() < 2048, "{}", bomb.len());
        let err = gunzip_at_most(&bomb, "z.nff.gz", 1000).unwrap_err();
        assert_eq!(
            err.to_string(),
            "z.nff.gz: gzip data inflates to more than 1000 bytes"
        );
        assert_eq!(
            gunzip_at_most(&bomb, "z.nff.gz", 1 << 20).unwrap().len(),
            1 << 20
        );
    }

    #[test]
    fn precision_fits_rounds_like_the_conversion() {
        assert!(Precision::F32.fits(f64::from(f32::MAX)));
        // Halfway to the next binade step rounds to infinity; just below it, to MAX.
        let step = f64::from(f32::MAX) - f64::from(f32::MAX.next_down());
        assert!(Precision::F32.fits(f64::from(f32::MAX) + 0.49 * step));
        assert!(!Precision::F32.fits(f64::from(f32::MAX) + 0.5 * step));
        assert!(!Precision::F32.fits(-1e39));
        assert!(Precision::F64.fits(1e300));
        assert_eq!(Precision::of::<f32>(), Precision::F32);
        assert_eq!(Precision::of::<f64>(), Precision::F64);
    }
}
