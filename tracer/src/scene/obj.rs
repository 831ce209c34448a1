//! Reader for Wavefront OBJ geometry with MTL materials.
//!
//! # Geometry
//! Each `f` statement becomes one primitive, kept as the polygon the file gives (not
//! triangulated): a face whose every vertex carries a normal (`v//vn` or `v/vt/vn`)
//! becomes a smooth-shaded [`Shape::Patch`], any other face a [`Shape::Polygon`]. This
//! keeps one primitive per face (as [`Hit::prim_id`](crate::ray::Hit::prim_id) promises) and
//! leaves concave faces to the polygon code, which handles them, where a triangle fan
//! would not. Indices may be negative (relative to the vertices read so far) and
//! positive ones may point forward. `v x y z w` divides by `w`; per-vertex colours
//! (`v x y z r g b`) and texture coordinates are ignored, as are points (`p`), lines
//! (`l`), groups, smoothing groups and free-form geometry. Line continuations (`\`) are
//! not supported.
//!
//! # Materials
//! `mtllib` files are read relative to the OBJ file's directory; a library that cannot
//! be read is an error. Faces before any `usemtl`, or whose `usemtl` names no material
//! in the libraries read so far (the SPD exports name `txt001` without any library), get
//! [`DEFAULT_MATERIAL`]. MTL statements map onto NFF's model ([`MaterialDesc`]) as:
//!
//! | field | from |
//! |---|---|
//! | `color` | `Kd` (one value means grey), else the default grey |
//! | `ks` | mean of `Ks` if `illum` is 3 to 9 (a ray-traced reflection mode), else 0: NFF's `Ks` is also the mirror weight, so the highlight-only model `illum 2` would otherwise turn every glossy OBJ into a mirror |
//! | `t` | `1 - d` (dissolve), else `Tr`, else 0 |
//! | `kd` | `1 - ks - t`, so the three weights sum to 1 |
//! | `shine` | `Ns`, else the default |
//! | `ior` | `Ni`, else 1 |
//!
//! All weights are clamped to [0, 1]. Other statements (`Ka`, `Ke`, `Tf`, maps) are
//! ignored.
//!
//! # Camera and light
//! OBJ has neither. By default the camera looks at the centre of the bounding box of
//! all face vertices from the direction $(1, 1, 1)$, with up $+y$ (OBJ's convention), a
//! 45° angle, at the distance where the box's bounding sphere just fits the narrower
//! side of the image, at 512×512. A single white light sits at the eye. [`ObjOptions`]
//! overrides any of these.
//!
//! Errors carry the OBJ or MTL file and line (`FILE:LINE: message`), except camera
//! option errors and a file without faces, which name only the OBJ file.
//!
//! # Limits
//! A face has at most [`MAX_POLYGON_VERTICES`] vertices; with [`Precision::F32`] every
//! number (and every `v x y z w` after dividing by `w`, and the camera framed from
//! them) must stay finite in `f32`. Faces whose vertices coincide or are collinear are
//! degenerate but legal: kept here, dropped and counted by the geometry builder.

use std::collections::{HashMap, HashSet};
use std::io;
use std::path::Path;

use super::error::quote;
use super::nff::{is_parallel, looks_numeric, parse_real, MAX_RESOLUTION};
use super::{
    CameraDesc, LightDesc, MaterialDesc, Precision, SceneDesc, SceneError, Shape, ShapeDesc,
    DEFAULT_MATERIAL, MAX_POLYGON_VERTICES, P3,
};

/// Camera and light settings for an OBJ scene; `None` fields get the default framing
/// described in the [module docs](self).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjOptions {
    /// Eye position (default: on the $(1, 1, 1)$ diagonal from `at`, far enough for the
    /// model to fit).
    pub from: Option<P3>,
    /// Point at the image centre (default: the centre of the bounding box).
    pub at: Option<P3>,
    /// Up direction (default $+y$).
    pub up: Option<P3>,
    /// Full angle of view in degrees, in (0, 180) (default 45).
    pub angle: Option<f64>,
    /// Image size in pixels, each side 1 to 65536 (default 512×512).
    pub resolution: Option<(u32, u32)>,
    /// The scene's only light (default: white, at the eye).
    pub light: Option<LightDesc>,
}

/// Default angle of view in degrees.
const DEFAULT_ANGLE: f64 = 45.0;
/// Default image size.
const DEFAULT_RESOLUTION: (u32, u32) = (512, 512);

/// Reads an OBJ file (gzip-compressed or not), its material libraries, and frames it
/// with a camera and light according to `options`.
///
/// # Errors
/// A [`SceneError`] if the OBJ file or a material library cannot be read or is
/// malformed, the file has no faces, or an option is invalid (a non-finite value, an
/// angle outside (0, 180), a resolution outside 1 to 65536, `from` equal to `at`, or
/// `up` parallel to the view direction).
///
/// # Examples
/// ```no_run
/// use tracer::scene::{load_obj, ObjOptions};
/// let options = ObjOptions { up: Some([0.0, 0.0, 1.0]), ..ObjOptions::default() };
/// let scene = load_obj(std::path::Path::new("model.obj"), &options)?;
/// println!("{} faces", scene.shapes.len());
/// # Ok::<(), tracer::scene::SceneError>(())
/// ```
pub fn load_obj(path: &Path, options: &ObjOptions) -> Result<SceneDesc, SceneError> {
    load_obj_for(path, options, Precision::F64)
}

/// [`load_obj`] for a scene to be rendered in `precision`: every number must stay
/// finite in it (see [`Precision`]).
///
/// # Errors
/// As [`load_obj`], and for a number out of `precision`'s range.
pub fn load_obj_for(
    path: &Path,
    options: &ObjOptions,
    precision: Precision,
) -> Result<SceneDesc, SceneError> {
    let name = path.display().to_string();
    let data = super::read_file(path, &name)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut libraries = |lib: &str| {
        let path = dir.join(lib);
        std::fs::read(&path).map(|data| (path.display().to_string(), data))
    };
    let mut reader = ObjReader::new(&name, precision, &mut libraries);
    reader.read(&data)?;
    reader.finish(options)
}

/// Parses OBJ data (decompressed first if it starts with the gzip magic bytes) without
/// touching the file system: `library` returns the contents of the material library a
/// `mtllib` statement names. `file_name` labels errors; errors in a library name it as
/// `mtllib` gave it.
///
/// # Errors
/// As [`load_obj_for`]; a library that `library` cannot give is an error at the
/// `mtllib` line.
///
/// # Examples
/// ```
/// use tracer::scene::{parse_obj, ObjOptions, Precision};
/// let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
/// let library = |name: &str| match name {
///     "m.mtl" => Ok(b"newmtl red\nKd 1 0 0\n".to_vec()),
///     _ => Err(std::io::ErrorKind::NotFound.into()),
/// };
/// let scene = parse_obj(obj, "t.obj", &ObjOptions::default(), Precision::F32, library)?;
/// assert_eq!(scene.materials[scene.shapes[0].material as usize].color, [1.0, 0.0, 0.0]);
/// # Ok::<(), tracer::scene::SceneError>(())
/// ```
pub fn parse_obj(
    data: impl AsRef<[u8]>,
    file_name: &str,
    options: &ObjOptions,
    precision: Precision,
    mut library: impl FnMut(&str) -> io::Result<Vec<u8>>,
) -> Result<SceneDesc, SceneError> {
    let data = super::maybe_gunzip(data.as_ref(), file_name)?;
    let mut libraries = |lib: &str| library(lib).map(|data| (lib.to_owned(), data));
    let mut reader = ObjReader::new(file_name, precision, &mut libraries);
    reader.read(&data)?;
    reader.finish(options)
}

/// Splits `data` into 1-based numbered lines (without the line break) with any `#`
/// comment removed.
fn lines(data: &[u8]) -> impl Iterator<Item = (u32, &[u8])> {
    data.split(|&b| b == b'\n').zip(1u32..).map(|(line, n)| {
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        let line = match line.iter().position(|&b| b == b'#') {
            Some(i) => &line[..i],
            None => line,
        };
        (n, line)
    })
}

/// Whitespace-separated words of a line.
fn words(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|b| b.is_ascii_whitespace())
        .filter(|w| !w.is_empty())
}

/// The text after the first word, trimmed (names may contain spaces).
fn rest_of_line(line: &[u8]) -> String {
    let line = line.trim_ascii_start();
    let start = line
        .iter()
        .position(|b| b.is_ascii_whitespace())
        .unwrap_or(line.len());
    String::from_utf8_lossy(line[start..].trim_ascii()).into_owned()
}

/// One face as read: where it is and which material it uses.
struct Face {
    line: u32,
    /// Range of its corners in [`ObjReader::corners`].
    start: usize,
    len: usize,
    /// Every corner has a normal index.
    smooth: bool,
    /// `None` for the default material.
    material: Option<u32>,
}

/// A face corner: 0-based position index and normal index (`usize::MAX` for none).
/// Positive file indices are checked against the final counts, since they may point
/// forward.
#[derive(Clone, Copy)]
struct Corner {
    position: usize,
    normal: usize,
}

/// No normal index.
const NONE: usize = usize::MAX;

/// Gives a material library's contents and the name its errors carry.
type Libraries<'a> = dyn FnMut(&str) -> io::Result<(String, Vec<u8>)> + 'a;

struct ObjReader<'a> {
    file: &'a str,
    precision: Precision,
    libraries: &'a mut Libraries<'a>,
    positions: Vec<P3>,
    normals: Vec<P3>,
    texcoords: usize,
    corners: Vec<Corner>,
    faces: Vec<Face>,
    materials: Vec<MaterialDesc>,
    material_names: HashMap<String, u32>,
    /// The names of the libraries read: a library named again is not read again.
    libraries_read: HashSet<String>,
    current: Option<u32>,
}

impl<'a> ObjReader<'a> {
    fn new(file: &'a str, precision: Precision, libraries: &'a mut Libraries<'a>) -> Self {
        Self {
            file,
            precision,
            libraries,
            positions: Vec::new(),
            normals: Vec::new(),
            texcoords: 0,
            corners: Vec::new(),
            faces: Vec::new(),
            materials: Vec::new(),
            material_names: HashMap::new(),
            libraries_read: HashSet::new(),
            current: None,
        }
    }

    fn error(&self, line: u32, message: impl Into<String>) -> SceneError {
        SceneError::at(self.file, line, message)
    }

    fn read(&mut self, data: &[u8]) -> Result<(), SceneError> {
        for (n, line) in lines(data) {
            let mut w = words(line);
            let Some(keyword) = w.next() else { continue };
            match keyword {
                b"v" => {
                    let (values, count) = numbers::<7>(w, self.file, n, self.precision)?;
                    let [x, y, z, a, ..] = values;
                    let p = match count {
                        3 | 6 => [x, y, z],
                        4 => {
                            if a == 0.0 {
                                return Err(self.error(n, "vertex weight `w` must not be zero"));
                            }
                            let p = [x / a, y / a, z / a];
                            if !p.iter().all(|&c| self.precision.fits(c)) {
                                return Err(self.error(
                                    n,
                                    format!(
                                        "vertex does not fit in {} after dividing by `w`",
                                        self.precision.name()
                                    ),
                                ));
                            }
                            p
                        }
                        _ => {
                            return Err(self.error(
                                n,
                                format!("expected 3, 4 or 6 numbers after `v`, found {count}"),
                            ))
                        }
                    };
                    self.positions.push(p);
                }
                b"vn" => {
                    let (values, count) = numbers::<4>(w, self.file, n, self.precision)?;
                    if count != 3 {
                        return Err(
                            self.error(n, format!("expected 3 numbers after `vn`, found {count}"))
                        );
                    }
                    self.normals.push([values[0], values[1], values[2]]);
                }
                b"vt" => {
                    let (_, count) = numbers::<4>(w, self.file, n, self.precision)?;
                    if !(1..=3).contains(&count) {
                        return Err(self.error(
                            n,
                            format!("expected 1 to 3 numbers after `vt`, found {count}"),
                        ));
                    }
                    self.texcoords += 1;
                }
                b"f" => self.face(w, n)?,
                b"usemtl" => {
                    let name = rest_of_line(line);
                    if name.is_empty() {
                        return Err(self.error(n, "expected a material name after `usemtl`"));
                    }
                    self.current = self.material_names.get(&name).copied();
                }
                b"mtllib" => self.mtllib(line, n)?,
                _ => {}
            }
        }
        Ok(())
    }

    /// `f v[/vt[/vn]] ...`.
    fn face<'d>(&mut self, refs: impl Iterator<Item = &'d [u8]>, n: u32) -> Result<(), SceneError> {
        let start = self.corners.len();
        let mut smooth = true;
        for r in refs {
            let mut parts = r.split(|&b| b == b'/');
            let bad = || self.error(n, format!("invalid vertex reference `{}`", quote(r)));
            let v = parts.next().filter(|p| !p.is_empty()).ok_or_else(bad)?;
            let vt = parts.next().filter(|p| !p.is_empty());
            let vn = parts.next().filter(|p| !p.is_empty());
            if parts.next().is_some() {
                return Err(bad());
            }
            let position = self.index(v, "vertex", self.positions.len(), n)?;
            if let Some(vt) = vt {
                self.index(vt, "texture coordinate", self.texcoords, n)?;
            }
            let normal = match vn {
                Some(vn) => self.index(vn, "normal", self.normals.len(), n)?,
                None => {
                    smooth = false;
                    NONE
                }
            };
            if self.corners.len() - start == MAX_POLYGON_VERTICES {
                return Err(self.error(
                    n,
                    format!("face has more than {MAX_POLYGON_VERTICES} vertices"),
                ));
            }
            self.corners.push(Corner { position, normal });
        }
        let len = self.corners.len() - start;
        if len < 3 {
            return Err(self.error(n, format!("face needs at least 3 vertices, found {len}")));
        }
        self.faces.push(Face {
            line: n,
            start,
            len,
            smooth,
            material: self.current,
        });
        Ok(())
    }

    /// Resolves a 1-based or negative (relative) index to a 0-based one; `count` items
    /// of its kind are known so far.
    fn index(&self, text: &[u8], what: &str, count: usize, n: u32) -> Result<usize, SceneError> {
        let value: i64 = std::str::from_utf8(text)
            .ok()
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| self.error(n, format!("invalid {what} index `{}`", quote(text))))?;
        if value == 0 {
            return Err(self.error(n, format!("{what} index 0 is invalid (indices start at 1)")));
        }
        if value > 0 {
            return usize::try_from(value - 1)
                .map_err(|_| self.error(n, format!("{what} index {value} is out of range")));
        }
        // -1 is the last one read so far.
        let back = value.unsigned_abs();
        match usize::try_from(back)
            .ok()
            .and_then(|b| count.checked_sub(b))
        {
            Some(i) => Ok(i),
            None => Err(self.error(
                n,
                format!("{what} index {value} is out of range ({count} so far)"),
            )),
        }
    }

    /// `mtllib a.mtl [b.mtl ...]`: each name relative to the OBJ file's directory. A
    /// name with spaces is accepted when the whole rest of the line names a file. A
    /// library already read is not read again: its materials are known, and a file
    /// naming one library many times must not cost that many readings (nor keep that
    /// many copies of its materials).
    fn mtllib(&mut self, line: &[u8], n: u32) -> Result<(), SceneError> {
        let whole = rest_of_line(line);
        if whole.is_empty() {
            return Err(self.error(n, "expected a file name after `mtllib`"));
        }
        // A name with spaces read whole, if it can be; else each word is a name.
        let mut read = Vec::new();
        if whole.contains(char::is_whitespace) {
            if self.libraries_read.contains(&whole) {
                return Ok(());
            }
            if let Ok(lib) = (self.libraries)(&whole) {
                self.libraries_read.insert(whole);
                read.push(Ok(lib));
            }
        }
        if read.is_empty() {
            for w in words(line).skip(1) {
                let name = String::from_utf8_lossy(w).into_owned();
                if self.libraries_read.insert(name.clone()) {
                    read.push((self.libraries)(&name).map_err(|e| (name, e)));
                }
            }
        }
        for lib in read {
            let (mtl_name, data) = lib.map_err(|(name, e)| {
                let reason = super::error::io_reason(&e);
                self.error(
                    n,
                    format!(
                        "cannot read material library `{}`: {reason}",
                        quote(name.as_bytes())
                    ),
                )
                .with_source(e)
            })?;
            for (name, material) in parse_mtl(&data, &mtl_name, self.precision)? {
                let index = u32::try_from(self.materials.len())
                    .map_err(|_| self.error(n, "too many materials"))?;
                self.materials.push(material);
                self.material_names.insert(name, index);
            }
        }
        Ok(())
    }

    /// Checks forward indices, builds the primitives and frames the camera.
    fn finish(mut self, options: &ObjOptions) -> Result<SceneDesc, SceneError> {
        if self.faces.is_empty() {
            return Err(SceneError::whole_file(self.file, "file has no faces"));
        }
        let mut default_material = None;
        let mut shapes = Vec::with_capacity(self.faces.len());
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for face in &self.faces {
            let corners = &self.corners[face.start..face.start + face.len];
            let mut vertices = Vec::with_capacity(face.len);
            for c in corners {
                let p = *self.positions.get(c.position).ok_or_else(|| {
                    self.error(
                        face.line,
                        format!(
                            "vertex index {} is out of range (the file has {})",
                            c.position + 1,
                            self.positions.len()
                        ),
                    )
                })?;
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
                vertices.push(p);
            }
            let shape = if face.smooth {
                let mut normals = Vec::with_capacity(face.len);
                for c in corners {
                    normals.push(*self.normals.get(c.normal).ok_or_else(|| {
                        self.error(
                            face.line,
                            format!(
                                "normal index {} is out of range (the file has {})",
                                c.normal + 1,
                                self.normals.len()
                            ),
                        )
                    })?);
                }
                Shape::Patch { vertices, normals }
            } else {
                Shape::Polygon { vertices }
            };
            let material = match face.material {
                Some(m) => m,
                None => *default_material.get_or_insert_with(|| {
                    self.materials.push(DEFAULT_MATERIAL);
                    (self.materials.len() - 1) as u32
                }),
            };
            shapes.push(ShapeDesc {
                shape,
                material,
                line: face.line,
            });
        }
        let camera = frame(lo, hi, options).map_err(|m| SceneError::whole_file(self.file, m))?;
        for (what, p) in [("from", camera.from), ("at", camera.at), ("up", camera.up)] {
            if !p.iter().all(|&c| self.precision.fits(c)) {
                return Err(SceneError::whole_file(
                    self.file,
                    format!("camera `{what}` does not fit in {}", self.precision.name()),
                ));
            }
        }
        let light = match &options.light {
            Some(l) => {
                let finite = l
                    .position
                    .iter()
                    .chain(l.color.iter().flatten())
                    .all(|c| c.is_finite());
                if !finite {
                    return Err(SceneError::whole_file(self.file, "light must be finite"));
                }
                l.clone()
            }
            None => LightDesc {
                position: camera.from,
                color: None,
            },
        };
        Ok(SceneDesc {
            camera,
            background: [0.0; 3],
            lights: vec![light],
            materials: self.materials,
            shapes,
        })
    }
}

/// Parses every word of a line as a finite number, up to `N` of them; returns the
/// values and how many words there were (which may exceed `N`).
fn numbers<'d, const N: usize>(
    words: impl Iterator<Item = &'d [u8]>,
    file: &str,
    n: u32,
    precision: Precision,
) -> Result<([f64; N], usize), SceneError> {
    let mut out = [0.0; N];
    let mut count = 0;
    for w in words {
        let v = parse_real(w).map_err(|e| SceneError::at(file, n, e.message(w)))?;
        if !precision.fits(v) {
            return Err(SceneError::at(file, n, precision.overflow_message(w)));
        }
        if let Some(slot) = out.get_mut(count) {
            *slot = v;
        }
        count += 1;
    }
    Ok((out, count))
}

/// A camera for the box `lo`..`hi` per the module docs, or the message of an invalid
/// option.
fn frame(lo: P3, hi: P3, o: &ObjOptions) -> Result<CameraDesc, String> {
    let finite = |p: &Option<P3>| p.is_none_or(|p| p.iter().all(|c| c.is_finite()));
    for (name, p) in [("from", &o.from), ("at", &o.at), ("up", &o.up)] {
        if !finite(p) {
            return Err(format!("camera `{name}` must be finite"));
        }
    }
    let angle = o.angle.unwrap_or(DEFAULT_ANGLE);
    if !(angle > 0.0 && angle < 180.0) {
        return Err(format!(
            "angle must be between 0 and 180 degrees, found {angle}"
        ));
    }
    let (w, h) = o.resolution.unwrap_or(DEFAULT_RESOLUTION);
    if w == 0 || h == 0 {
        return Err("resolution must be positive".to_owned());
    }
    if w > MAX_RESOLUTION || h > MAX_RESOLUTION {
        return Err(format!("resolution must be at most {MAX_RESOLUTION}"));
    }
    let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let radius = match 0.5 * distance(lo, hi) {
        r if r > 0.0 && r.is_finite() => r,
        _ => 1.0,
    };
    let at = o.at.unwrap_or(centre);
    let up = o.up.unwrap_or([0.0, 1.0, 0.0]);
    let from = o.from.unwrap_or_else(|| {
        // `angle` spans the height; a narrower width narrows the horizontal half-angle.
        let half = (0.5 * angle).to_radians();
        let half = half.min((half.tan() * f64::from(w) / f64::from(h)).atan());
        // A sphere of radius r fits a cone of half-angle a from distance r / sin a; add
        // the offset of `at` from the centre so an off-centre `at` still fits it.
        let d = radius / half.sin() + distance(at, centre);
        let s = d / 3f64.sqrt();
        [at[0] + s, at[1] + s, at[2] + s]
    });
    let dir = [0, 1, 2].map(|k| at[k] - from[k]);
    if dir == [0.0; 3] {
        return Err("camera `from` equals `at`".to_owned());
    }
    if is_parallel(up, dir) {
        return Err("camera `up` is parallel to the view direction".to_owned());
    }
    Ok(CameraDesc {
        from,
        at,
        up,
        angle_deg: angle,
        hither: 1e-3 * distance(from, at),
        resolution: (w, h),
    })
}

/// $|a - b|$.
fn distance(a: P3, b: P3) -> f64 {
    let d = [0, 1, 2].map(|k| a[k] - b[k]);
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// MTL statements of one material, as read.
#[derive(Default)]
struct MtlFields {
    kd: Option<P3>,
    ks: Option<P3>,
    ns: Option<f64>,
    ni: Option<f64>,
    d: Option<f64>,
    tr: Option<f64>,
    illum: Option<u8>,
}

impl MtlFields {
    /// The NFF material per the table in the module docs.
    fn to_material(&self) -> MaterialDesc {
        let reflective = matches!(self.illum, Some(3..=9));
        let ks = match (reflective, self.ks) {
            (true, Some(k)) => ((k[0] + k[1] + k[2]) / 3.0).clamp(0.0, 1.0),
            _ => 0.0,
        };
        let t = match (self.d, self.tr) {
            (Some(d), _) => 1.0 - d,
            (None, Some(tr)) => tr,
            (None, None) => 0.0,
        }
        .clamp(0.0, 1.0);
        MaterialDesc {
            color: self.kd.unwrap_or(DEFAULT_MATERIAL.color),
            kd: (1.0 - ks - t).clamp(0.0, 1.0),
            ks,
            shine: self.ns.unwrap_or(DEFAULT_MATERIAL.shine),
            t,
            ior: self.ni.unwrap_or(1.0),
        }
    }
}

/// Parses an MTL library into named materials, in file order.
fn parse_mtl(
    data: &[u8],
    file: &str,
    precision: Precision,
) -> Result<Vec<(String, MaterialDesc)>, SceneError> {
    let mut out = Vec::new();
    let mut current: Option<(String, MtlFields)> = None;
    for (n, line) in lines(data) {
        let mut w = words(line);
        let Some(keyword) = w.next() else { continue };
        let key = String::from_utf8_lossy(keyword);
        let error = |message: String| SceneError::at(file, n, message);
        if keyword == b"newmtl" {
            let name = rest_of_line(line);
            if name.is_empty() {
                return Err(error("expected a material name after `newmtl`".to_owned()));
            }
            if let Some((name, m)) = current.replace((name, MtlFields::default())) {
                out.push((name, m.to_material()));
            }
            continue;
        }
        if !matches!(
            keyword,
            b"Kd" | b"Ks" | b"Ns" | b"Ni" | b"d" | b"Tr" | b"illum"
        ) {
            continue;
        }
        let Some((_, m)) = current.as_mut() else {
            return Err(error(format!("`{key}` before any `newmtl`")));
        };
        let mut w = w.peekable();
        match keyword {
            b"Kd" | b"Ks" => {
                if let Some(form) = w.peek().filter(|t| !looks_numeric(t)) {
                    return Err(error(format!(
                        "only rgb colours are supported after `{key}`, found `{}`",
                        quote(form)
                    )));
                }
                let (v, count) = numbers::<3>(w, file, n, precision)?;
                let color = match count {
                    1 => [v[0]; 3],
                    3 => v,
                    _ => {
                        return Err(error(format!(
                            "expected 1 or 3 numbers after `{key}`, found {count}"
                        )))
                    }
                };
                if keyword == b"Kd" {
                    m.kd = Some(color);
                } else {
                    m.ks = Some(color);
                }
            }
            b"illum" => {
                let text = w.next().unwrap_or_default();
                let model = std::str::from_utf8(text)
                    .ok()
                    .and_then(|s| s.parse::<u8>().ok())
                    .filter(|&i| i <= 10 && w.next().is_none())
                    .ok_or_else(|| {
                        error(format!(
                            "expected an illumination model from 0 to 10 after `illum`, found `{}`",
                            quote(rest_of_line(line).as_bytes())
                        ))
                    })?;
                m.illum = Some(model);
            }
            _ => {
                if keyword == b"d" {
                    w.next_if(|t| *t == b"-halo");
                }
                let (v, count) = numbers::<1>(w, file, n, precision)?;
                if count != 1 {
                    return Err(error(format!(
                        "expected 1 number after `{key}`, found {count}"
                    )));
                }
                let slot = match keyword {
                    b"Ns" => &mut m.ns,
                    b"Ni" => &mut m.ni,
                    b"d" => &mut m.d,
                    _ => &mut m.tr,
                };
                *slot = Some(v[0]);
            }
        }
    }
    if let Some((name, m)) = current {
        out.push((name, m.to_material()));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_strip_comments_and_carriage_returns() {
        let got: Vec<_> = lines(b"a # c\r\nb\n# x\nc").collect();
        assert_eq!(got, vec![(1, &b"a "[..]), (2, b"b"), (3, b""), (4, b"c")]);
    }

    #[test]
    fn rest_of_line_keeps_inner_spaces() {
        assert_eq!(rest_of_line(b"  usemtl  my mat \t"), "my mat");
        assert_eq!(rest_of_line(b"usemtl"), "");
    }

    #[test]
    fn mtl_mapping() {
        let mtl = b"newmtl glass\nKd 1 1 1\nKs 1 1 1\nillum 7\nd 0.1\nNi 1.5\nNs 200\n\
                    newmtl glossy\nKd 0.5\nKs 0.5 0.5 0.5\nillum 2\nTr 0.25\n";
        let m = parse_mtl(mtl, "m.mtl", Precision::F64).unwrap();
        assert_eq!(m[0].0, "glass");
        let glass = &m[0].1;
        assert_eq!((glass.ks, glass.ior, glass.shine), (1.0, 1.5, 200.0));
        assert!((glass.t - 0.9).abs() < 1e-12 && glass.kd == 0.0);
        let glossy = &m[1].1;
        assert_eq!(glossy.color, [0.5; 3]);
        assert_eq!((glossy.ks, glossy.t, glossy.kd), (0.0, 0.25, 0.75));
    }

    #[test]
    fn mtl_errors() {
        let err = |text: &str| {
            parse_mtl(text.as_bytes(), "m.mtl", Precision::F64)
                .unwrap_err()
                .to_string()
        };
        assert_eq!(err("Kd 1 1 1\n"), "m.mtl:1: `Kd` before any `newmtl`");
        assert_eq!(
            err("newmtl a\nKd 1 1\n"),
            "m.mtl:2: expected 1 or 3 numbers after `Kd`, found 2"
        );
        assert_eq!(
            err("newmtl a\nKd spectral x.rfl\n"),
            "m.mtl:2: only rgb colours are supported after `Kd`, found `spectral`"
        );
        assert_eq!(
            err("newmtl a\nNs nan\n"),
            "m.mtl:2: non-finite number `nan`"
        );
        assert_eq!(
            err("newmtl a\n\nillum 12\n"),
            "m.mtl:3: expected an illumination model from 0 to 10 after `illum`, found `12`"
        );
        assert_eq!(
            err("newmtl\n"),
            "m.mtl:1: expected a material name after `newmtl`"
        );
    }

    #[test]
    fn framing_fits_the_bounding_sphere() {
        let cam = frame([-1.0; 3], [1.0; 3], &ObjOptions::default()).unwrap();
        assert_eq!(cam.at, [0.0; 3]);
        let d = distance(cam.from, cam.at);
        let r = 3f64.sqrt();
        assert!((d - r / 22.5f64.to_radians().sin()).abs() < 1e-9);
        assert_eq!(cam.resolution, (512, 512));
        let wide = ObjOptions {
            resolution: Some((256, 512)),
            ..ObjOptions::default()
        };
        let narrow = frame([-1.0; 3], [1.0; 3], &wide).unwrap();
        assert!(distance(narrow.from, narrow.at) > d);
    }

    #[test]
    fn framing_rejects_bad_options() {
        let bad = |o: ObjOptions| frame([0.0; 3], [1.0; 3], &o).unwrap_err();
        let up = ObjOptions {
            up: Some([1.0, 1.0, 1.0]),
            ..ObjOptions::default()
        };
        assert_eq!(bad(up), "camera `up` is parallel to the view direction");
        let angle = ObjOptions {
            angle: Some(180.0),
            ..ObjOptions::default()
        };
        assert_eq!(
            bad(angle),
            "angle must be between 0 and 180 degrees, found 180"
        );
        let same = ObjOptions {
            from: Some([1.0; 3]),
            at: Some([1.0; 3]),
            ..ObjOptions::default()
        };
        assert_eq!(bad(same), "camera `from` equals `at`");
        let res = ObjOptions {
            resolution: Some((0, 5)),
            ..ObjOptions::default()
        };
        assert_eq!(bad(res), "resolution must be positive");
    }
}
