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
pub use nff::{load_nff, parse_nff};
pub use obj::{load_obj, ObjOptions};

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
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if name.ends_with(".obj") || name.ends_with(".obj.gz") {
        load_obj(path, obj)
    } else {
        load_nff(path)
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

/// Decompresses all gzip members of `data`.
fn gunzip(data: &[u8], name: &str) -> Result<Vec<u8>, SceneError> {
    // The last four bytes hold the size of the last member modulo 2^32 (RFC 1952,
    // ISIZE): a good first allocation for the usual single-member file, capped so that
    // a forged trailer cannot ask for much.
    let hint = data
        .last_chunk::<4>()
        .map_or(0, |b| u32::from_le_bytes(*b) as usize)
        .min(1 << 28);
    let mut out = Vec::with_capacity(hint);
    flate2::read::MultiGzDecoder::new(data)
        .read_to_end(&mut out)
        .map_err(|e| {
            let reason = error::io_reason(&e);
            SceneError::whole_file(name, format!("invalid gzip data: {reason}")).with_source(e)
        })?;
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
