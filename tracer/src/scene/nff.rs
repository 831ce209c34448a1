//! Reader for Eric Haines' Neutral File Format (NFF), version 3.x as used by the Standard
//! Procedural Databases.
//!
//! The file is read as a stream of whitespace-separated tokens, so a statement may span
//! lines or share one (SPD's generators write all eight numbers of `c` on one line, the
//! specification writes them on two). `#` starts a comment that runs to the end of the
//! line. Statements:
//!
//! | statement | meaning |
//! |---|---|
//! | `v` | camera block: `from x y z`, `at x y z`, `up x y z`, `angle deg`, `hither d`, `resolution w h`, each exactly once, in any order |
//! | `b r g b` | background colour (black if absent) |
//! | `l x y z [r g b]` | point light, optionally coloured |
//! | `f r g b Kd Ks Shine T ior` | material for all following primitives |
//! | `s x y z r` | sphere; a negative radius means the inside is visible |
//! | `c bx by bz br ax ay az ar` | uncapped cone or cylinder from base to apex; negative radii mean the inside is visible |
//! | `p n` then `n` × `x y z` | planar polygon, convex or concave |
//! | `pp n` then `n` × `x y z nx ny nz` | polygon with vertex normals |
//!
//! Primitives before the first `f` get [`DEFAULT_MATERIAL`],
//! inserted into the material list where it is first needed (so at index 0).
//!
//! What is rejected, with the line of the statement at fault: unknown keywords, malformed
//! or non-finite numbers (`nan`, `inf`, `1e999`), numbers that do not fit the target
//! [`Precision`] (`1e39` for `f32`, with [`parse_nff_for`]), statements with too few or
//! too many numbers, a missing or repeated `v` block or camera field, a camera whose
//! `from` equals `at` or whose `up` is parallel to the view direction, an angle outside
//! (0, 180), a resolution that is not a whole number from 1 to 65536, cone radii of
//! opposite signs, and polygons with fewer than three or more than
//! [`MAX_POLYGON_VERTICES`] vertices or fewer vertices than declared.
//!
//! Degenerate primitives are legal and kept: a sphere of radius 0, a cone with both
//! radii 0 or with coinciding ends, polygons with collinear or repeated vertices. Real
//! files contain them; the geometry builder drops them before the BVH is built and
//! counts them ([`GeometryStats::skipped`](crate::geometry::GeometryStats::skipped), the
//! `primitives.degenerate` of `--stats`), so no ray ever hits them.
//!
//! Speed: the tokenizer walks the bytes once without allocating, numbers go through
//! `str::parse::<f64>` on the token, and only polygons allocate (their vertex lists,
//! reserved for no more vertices than the rest of the file can hold).
//!
//! Reference: E. Haines, "NFF: Neutral File Format", version 3.9, in the Standard
//! Procedural Databases 3.14 distribution.

use std::path::Path;

use super::error::quote;
use super::{
    CameraDesc, LightDesc, MaterialDesc, Precision, SceneDesc, SceneError, Shape, ShapeDesc,
    DEFAULT_MATERIAL, MAX_POLYGON_VERTICES, P3,
};

/// The largest accepted image side, in pixels.
pub const MAX_RESOLUTION: u32 = 65536;

/// Parses NFF text. Data starting with the gzip magic bytes is decompressed first.
/// `file_name` only labels errors.
///
/// # Errors
/// A [`SceneError`] naming the line and the problem; see the [module docs](self) for
/// what is rejected.
///
/// # Examples
/// ```
/// use tracer::scene::parse_nff;
/// let err = parse_nff("b 0 0 0\nq 1 2 3\n", "bad.nff").unwrap_err();
/// assert_eq!(err.to_string(), "bad.nff:2: unknown keyword `q`");
/// ```
pub fn parse_nff(data: impl AsRef<[u8]>, file_name: &str) -> Result<SceneDesc, SceneError> {
    parse_nff_for(data, file_name, Precision::F64)
}

/// [`parse_nff`] for a scene to be rendered in `precision`: every number must stay
/// finite in it (see [`Precision`]).
///
/// # Errors
/// As [`parse_nff`], and `FILE:LINE: number ... does not fit in f32 ...` for a number
/// out of range.
pub fn parse_nff_for(
    data: impl AsRef<[u8]>,
    file_name: &str,
    precision: Precision,
) -> Result<SceneDesc, SceneError> {
    let data = super::maybe_gunzip(data.as_ref(), file_name)?;
    Parser::new(&data, file_name, precision).parse()
}

/// Reads and parses an NFF file, gzip-compressed or not (recognised by its magic bytes).
/// Errors name the file as `path.display()` shows it.
///
/// # Errors
/// A [`SceneError`] if the file cannot be read, is not valid gzip, or is not valid NFF.
pub fn load_nff(path: &Path) -> Result<SceneDesc, SceneError> {
    load_nff_for(path, Precision::F64)
}

/// [`load_nff`] for a scene to be rendered in `precision` (see [`parse_nff_for`]).
///
/// # Errors
/// As [`load_nff`], and for a number out of `precision`'s range.
pub fn load_nff_for(path: &Path, precision: Precision) -> Result<SceneDesc, SceneError> {
    let name = path.display().to_string();
    let data = super::read_file(path, &name)?;
    Parser::new(&data, &name, precision).parse()
}

// ---------------------------------------------------------------------------------------
// Tokens

/// A run of non-blank bytes and the line it is on.
#[derive(Clone, Copy, Debug)]
struct Token<'a> {
    text: &'a [u8],
    line: u32,
}

/// Splits bytes into tokens, skipping blanks and `#` comments and counting lines
/// (`\n`, `\r\n` and a lone `\r` each end one).
struct Lexer<'a> {
    data: &'a [u8],
    pos: usize,
    line: u32,
}

/// Bytes that end a token.
const fn is_delimiter(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c | b'#')
}

impl<'a> Lexer<'a> {
    fn new(data: &'a [u8]) -> Self {
        Self {
            data,
            pos: 0,
            line: 1,
        }
    }

    /// Moves to the start of the next token (or the end).
    fn skip_blank(&mut self) {
        while let Some(&b) = self.data.get(self.pos) {
            match b {
                b'\n' => self.line = self.line.saturating_add(1),
                b'\r' => {
                    if self.data.get(self.pos + 1) != Some(&b'\n') {
                        self.line = self.line.saturating_add(1);
                    }
                }
                b' ' | b'\t' | 0x0b | 0x0c => {}
                b'#' => {
                    // Skip to the line end, which the next iteration counts.
                    let rest = &self.data[self.pos..];
                    let len = rest
                        .iter()
                        .position(|&c| c == b'\n' || c == b'\r')
                        .unwrap_or(rest.len());
                    self.pos += len;
                    continue;
                }
                _ => return,
            }
            self.pos += 1;
        }
    }

    /// The next token, consumed.
    fn next(&mut self) -> Option<Token<'a>> {
        self.skip_blank();
        let start = self.pos;
        let len = self.data[start..]
            .iter()
            .position(|&b| is_delimiter(b))
            .unwrap_or(self.data.len() - start);
        if len == 0 {
            return None;
        }
        self.pos += len;
        Some(Token {
            text: &self.data[start..start + len],
            line: self.line,
        })
    }

    /// The next token, not consumed.
    fn peek(&mut self) -> Option<Token<'a>> {
        let (pos, line) = (self.pos, self.line);
        let token = self.next();
        (self.pos, self.line) = (pos, line);
        token
    }

    /// The next token, consumed only if it is meant as a number (one scan, where
    /// `peek` then `next` would take two).
    fn next_numeric(&mut self) -> Result<Token<'a>, Option<Token<'a>>> {
        let (pos, line) = (self.pos, self.line);
        match self.next() {
            Some(t) if looks_numeric(t.text) => Ok(t),
            other => {
                (self.pos, self.line) = (pos, line);
                Err(other)
            }
        }
    }
}

/// Whether a token is meant as a number (and so is reported as a bad number rather than
/// an unknown keyword): it starts with a digit, a sign or a point, or spells `nan`,
/// `inf` or `infinity` (any case, optionally signed).
pub(crate) fn looks_numeric(token: &[u8]) -> bool {
    match token.first() {
        Some(b'0'..=b'9' | b'+' | b'-' | b'.') => true,
        _ => [&b"nan"[..], b"inf", b"infinity"]
            .iter()
            .any(|w| token.eq_ignore_ascii_case(w)),
    }
}

/// Why a token is not a usable number.
#[derive(Debug, PartialEq, Eq)]
pub(crate) enum NumberError {
    /// Not a decimal number at all.
    Invalid,
    /// NaN or infinite (including overflow such as `1e999`).
    NotFinite,
}

impl NumberError {
    /// The message for `token`.
    pub(crate) fn message(&self, token: &[u8]) -> String {
        match self {
            Self::Invalid => format!("invalid number `{}`", quote(token)),
            Self::NotFinite => format!("non-finite number `{}`", quote(token)),
        }
    }
}

/// Parses a decimal number (Rust's `f64` syntax: `1`, `-2.5`, `.5`, `1e-3`), rejecting
/// NaN and infinities.
pub(crate) fn parse_real(token: &[u8]) -> Result<f64, NumberError> {
    let value: f64 = std::str::from_utf8(token)
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or(NumberError::Invalid)?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(NumberError::NotFinite)
    }
}

// ---------------------------------------------------------------------------------------
// Parser

/// What the previous statement takes, to explain a stray number after it.
#[derive(Clone, Copy, Debug)]
enum Takes {
    /// A fixed count of numbers.
    Numbers(usize),
    /// `l`: three or six numbers.
    Light,
    /// `p`/`pp`: the declared number of vertices.
    Vertices(u32),
}

/// The statement before the current one.
#[derive(Clone, Copy, Debug)]
struct Previous {
    keyword: &'static str,
    line: u32,
    takes: Takes,
}

/// The camera block's fields as they are read, each with its line.
#[derive(Default)]
struct ViewFields {
    from: Option<(P3, u32)>,
    at: Option<(P3, u32)>,
    up: Option<(P3, u32)>,
    angle: Option<(f64, u32)>,
    hither: Option<(f64, u32)>,
    resolution: Option<((u32, u32), u32)>,
}

/// The camera block's keywords.
const VIEW_KEYWORDS: [&str; 6] = ["from", "at", "up", "angle", "hither", "resolution"];

struct Parser<'a> {
    lex: Lexer<'a>,
    file: &'a str,
    precision: Precision,
    camera: Option<(CameraDesc, u32)>,
    background: Option<(P3, u32)>,
    lights: Vec<LightDesc>,
    materials: Vec<MaterialDesc>,
    shapes: Vec<ShapeDesc>,
    /// Index of the material set by the last `f` (or the default material).
    current_material: Option<u32>,
    previous: Option<Previous>,
}

impl<'a> Parser<'a> {
    fn new(data: &'a [u8], file: &'a str, precision: Precision) -> Self {
        Self {
            lex: Lexer::new(data),
            file,
            precision,
            camera: None,
            background: None,
            lights: Vec::new(),
            materials: Vec::new(),
            // Most statements in large files are primitives of a line or more.
            shapes: Vec::with_capacity((data.len() / 40).min(1 << 20)),
            current_material: None,
            previous: None,
        }
    }

    fn error(&self, line: u32, message: impl Into<String>) -> SceneError {
        SceneError::at(self.file, line, message)
    }

    fn parse(mut self) -> Result<SceneDesc, SceneError> {
        let mut any_statement = false;
        while let Some(token) = self.lex.next() {
            any_statement = true;
            let line = token.line;
            let (keyword, line, takes): (&'static str, u32, Takes) = match token.text {
                b"v" => self.view(line)?,
                b"b" => {
                    if let Some((_, first)) = self.background {
                        return Err(self.error(
                            line,
                            format!("duplicate `b` (the first is on line {first})"),
                        ));
                    }
                    self.background = Some((self.numbers::<3>("b", line)?, line));
                    ("b", line, Takes::Numbers(3))
                }
                b"l" => {
                    self.light(line)?;
                    ("l", line, Takes::Light)
                }
                b"f" => {
                    self.material(line)?;
                    ("f", line, Takes::Numbers(8))
                }
                b"s" => {
                    self.sphere(line)?;
                    ("s", line, Takes::Numbers(4))
                }
                b"c" => {
                    self.cone(line)?;
                    ("c", line, Takes::Numbers(8))
                }
                b"p" => ("p", line, Takes::Vertices(self.polygon(line, false)?)),
                b"pp" => ("pp", line, Takes::Vertices(self.polygon(line, true)?)),
                text => return Err(self.stray(token, text)),
            };
            self.previous = Some(Previous {
                keyword,
                line,
                takes,
            });
        }
        if !any_statement {
            return Err(self.error(1, "file has no statements"));
        }
        let Some((camera, _)) = self.camera else {
            return Err(self.error(1, "missing `v` block"));
        };
        Ok(SceneDesc {
            camera,
            background: self.background.map_or([0.0; 3], |(b, _)| b),
            lights: self.lights,
            materials: self.materials,
            shapes: self.shapes,
        })
    }

    /// The error for a token that cannot start a statement.
    fn stray(&self, token: Token<'_>, text: &[u8]) -> SceneError {
        let line = token.line;
        if let Some(kw) = VIEW_KEYWORDS.iter().find(|k| k.as_bytes() == text) {
            return self.error(line, format!("`{kw}` outside the `v` block"));
        }
        if !looks_numeric(text) {
            return self.error(line, format!("unknown keyword `{}`", quote(text)));
        }
        let Some(prev) = self.previous else {
            return self.error(
                line,
                format!("expected a keyword, found number `{}`", quote(text)),
            );
        };
        let takes = match prev.takes {
            Takes::Numbers(1) => "takes 1 number".to_owned(),
            Takes::Numbers(n) => format!("takes {n} numbers"),
            Takes::Light => "takes 3 or 6 numbers".to_owned(),
            Takes::Vertices(n) => format!("declares {n} vertices"),
        };
        self.error(
            line,
            format!(
                "unexpected number `{}`: the `{}` on line {} {takes}",
                quote(text),
                prev.keyword,
                prev.line
            ),
        )
    }

    /// Reads the value of a numeric token, which must fit the target precision.
    fn number(&self, token: Token<'_>) -> Result<f64, SceneError> {
        let value =
            parse_real(token.text).map_err(|e| self.error(token.line, e.message(token.text)))?;
        if !self.precision.fits(value) {
            return Err(self.error(token.line, self.precision.overflow_message(token.text)));
        }
        Ok(value)
    }

    /// The next token if it is meant as a number, parsed; `None` at the end of the data
    /// or before a keyword (which is left unconsumed).
    fn next_number(&mut self) -> Result<Option<f64>, SceneError> {
        match self.lex.next_numeric() {
            Ok(token) => self.number(token).map(Some),
            Err(_) => Ok(None),
        }
    }

    /// Reads the `N` numbers that follow `keyword` (on `line`).
    fn numbers<const N: usize>(
        &mut self,
        keyword: &str,
        line: u32,
    ) -> Result<[f64; N], SceneError> {
        let mut out = [0.0; N];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = self.next_number()?.ok_or_else(|| {
                let plural = if N == 1 { "" } else { "s" };
                self.error(
                    line,
                    format!("expected {N} number{plural} after `{keyword}`, found {i}"),
                )
            })?;
        }
        Ok(out)
    }

    /// `v` and its six fields; returns the last field's keyword, line and arity.
    fn view(&mut self, v_line: u32) -> Result<(&'static str, u32, Takes), SceneError> {
        if let Some((_, first)) = self.camera {
            return Err(self.error(
                v_line,
                format!("duplicate `v` block (the first is on line {first})"),
            ));
        }
        let mut f = ViewFields::default();
        let arity = |k: &str| match k {
            "from" | "at" | "up" => 3,
            "resolution" => 2,
            _ => 1,
        };
        let mut last = ("v", v_line, Takes::Numbers(0));
        while let Some(token) = self.lex.peek() {
            let Some(&keyword) = VIEW_KEYWORDS.iter().find(|k| k.as_bytes() == token.text) else {
                break;
            };
            self.lex.next();
            let line = token.line;
            let first = match keyword {
                "from" => f
                    .from
                    .replace((self.numbers::<3>(keyword, line)?, line))
                    .map(|p| p.1),
                "at" => {
                    f.at.replace((self.numbers::<3>(keyword, line)?, line))
                        .map(|p| p.1)
                }
                "up" => {
                    f.up.replace((self.numbers::<3>(keyword, line)?, line))
                        .map(|p| p.1)
                }
                "angle" => {
                    let [a] = self.numbers::<1>(keyword, line)?;
                    if !(a > 0.0 && a < 180.0) {
                        return Err(self.error(
                            line,
                            format!("angle must be between 0 and 180 degrees, found {a}"),
                        ));
                    }
                    f.angle.replace((a, line)).map(|p| p.1)
                }
                "hither" => {
                    let [h] = self.numbers::<1>(keyword, line)?;
                    f.hither.replace((h, line)).map(|p| p.1)
                }
                _ => {
                    let [w, h] = self.numbers::<2>(keyword, line)?;
                    let res = (self.pixels(w, line)?, self.pixels(h, line)?);
                    f.resolution.replace((res, line)).map(|p| p.1)
                }
            };
            last = (keyword, line, Takes::Numbers(arity(keyword)));
            if let Some(first) = first {
                return Err(self.error(
                    line,
                    format!(
                        "duplicate `{keyword}` in the `v` block (the first is on line {first})"
                    ),
                ));
            }
        }
        let missing = |name: &str| self.error(v_line, format!("`v` block is missing `{name}`"));
        let (from, _) = f.from.ok_or_else(|| missing("from"))?;
        let (at, at_line) = f.at.ok_or_else(|| missing("at"))?;
        let (up, up_line) = f.up.ok_or_else(|| missing("up"))?;
        let (angle_deg, _) = f.angle.ok_or_else(|| missing("angle"))?;
        let (hither, _) = f.hither.ok_or_else(|| missing("hither"))?;
        let (resolution, _) = f.resolution.ok_or_else(|| missing("resolution"))?;
        let dir = sub(at, from);
        if dir == [0.0; 3] {
            return Err(self.error(at_line, "`at` equals `from`"));
        }
        if is_parallel(up, dir) {
            return Err(self.error(up_line, "`up` is parallel to the view direction"));
        }
        self.camera = Some((
            CameraDesc {
                from,
                at,
                up,
                angle_deg,
                hither,
                resolution,
            },
            v_line,
        ));
        Ok(last)
    }

    /// One side of `resolution`.
    fn pixels(&self, value: f64, line: u32) -> Result<u32, SceneError> {
        if value < 1.0 {
            return Err(self.error(line, "resolution must be positive"));
        }
        if value.fract() != 0.0 {
            return Err(self.error(
                line,
                format!("resolution must be a whole number of pixels, found {value}"),
            ));
        }
        if value > f64::from(MAX_RESOLUTION) {
            return Err(self.error(
                line,
                format!("resolution must be at most {MAX_RESOLUTION}, found {value}"),
            ));
        }
        Ok(value as u32)
    }

    /// `l x y z [r g b]`.
    fn light(&mut self, line: u32) -> Result<(), SceneError> {
        let mut values = [0.0; 6];
        let mut count = 0;
        while count < 6 {
            match self.next_number()? {
                Some(v) => values[count] = v,
                None => break,
            }
            count += 1;
        }
        let [x, y, z, r, g, b] = values;
        let color = match count {
            3 => None,
            6 => Some([r, g, b]),
            _ => {
                return Err(self.error(
                    line,
                    format!("expected 3 or 6 numbers after `l`, found {count}"),
                ))
            }
        };
        self.lights.push(LightDesc {
            position: [x, y, z],
            color,
        });
        Ok(())
    }

    /// `f r g b Kd Ks Shine T ior`.
    fn material(&mut self, line: u32) -> Result<(), SceneError> {
        let [r, g, b, kd, ks, shine, t, ior] = self.numbers::<8>("f", line)?;
        let index = self.material_index(line)?;
        self.materials.push(MaterialDesc {
            color: [r, g, b],
            kd,
            ks,
            shine,
            t,
            ior,
        });
        self.current_material = Some(index);
        Ok(())
    }

    /// The index the next material gets.
    fn material_index(&self, line: u32) -> Result<u32, SceneError> {
        u32::try_from(self.materials.len()).map_err(|_| self.error(line, "too many materials"))
    }

    /// Adds a primitive with the current material.
    fn push(&mut self, shape: Shape, line: u32) -> Result<(), SceneError> {
        let material = match self.current_material {
            Some(m) => m,
            None => {
                let m = self.material_index(line)?;
                self.materials.push(DEFAULT_MATERIAL);
                self.current_material = Some(m);
                m
            }
        };
        self.shapes.push(ShapeDesc {
            shape,
            material,
            line,
        });
        Ok(())
    }

    /// `s x y z r`.
    fn sphere(&mut self, line: u32) -> Result<(), SceneError> {
        // A zero radius is degenerate but legal: kept, and dropped by the builder.
        let [x, y, z, r] = self.numbers::<4>("s", line)?;
        self.push(
            Shape::Sphere {
                center: [x, y, z],
                radius: r.abs(),
                inside_visible: r < 0.0,
            },
            line,
        )
    }

    /// `c base.x base.y base.z base_radius apex.x apex.y apex.z apex_radius`.
    fn cone(&mut self, line: u32) -> Result<(), SceneError> {
        let [bx, by, bz, br, ax, ay, az, ar] = self.numbers::<8>("c", line)?;
        // Opposite signs would ask for both sides visible at once: no meaning, refused.
        // Two zero radii or coinciding ends are degenerate but legal (kept, and dropped
        // by the builder).
        if (br < 0.0 && ar > 0.0) || (br > 0.0 && ar < 0.0) {
            return Err(self.error(line, "cone radii must have the same sign"));
        }
        let (base, apex) = ([bx, by, bz], [ax, ay, az]);
        self.push(
            Shape::Cone {
                base,
                base_radius: br.abs(),
                apex,
                apex_radius: ar.abs(),
                inside_visible: br < 0.0 || ar < 0.0,
            },
            line,
        )
    }

    /// `p n` (or `pp n` when `patch`) and its vertices; returns `n`.
    fn polygon(&mut self, line: u32, patch: bool) -> Result<u32, SceneError> {
        let (keyword, what) = if patch {
            ("pp", "patch")
        } else {
            ("p", "polygon")
        };
        let count = self.next_number()?.ok_or_else(|| {
            self.error(line, format!("expected a vertex count after `{keyword}`"))
        })?;
        if count.fract() != 0.0 {
            return Err(self.error(
                line,
                format!("vertex count must be a whole number, found {count}"),
            ));
        }
        if count < 3.0 {
            return Err(self.error(
                line,
                format!("{what} needs at least 3 vertices, found {count}"),
            ));
        }
        if count > MAX_POLYGON_VERTICES as f64 {
            return Err(self.error(
                line,
                format!(
                    "{what} vertex count {count} is too large (the limit is {MAX_POLYGON_VERTICES})"
                ),
            ));
        }
        let n = count as u32;
        let per_vertex = if patch { 6 } else { 3 };
        // Reserve no more than the rest of the data could hold (a number takes at least
        // one byte and one delimiter), so a bogus count cannot make us allocate more
        // than the file's size; a short file then fails below with the count it gave.
        let room = self.lex.data.len().saturating_sub(self.lex.pos) / (2 * per_vertex);
        let cap = (n as usize).min(room);
        let mut vertices = Vec::with_capacity(cap);
        let mut normals = Vec::with_capacity(if patch { cap } else { 0 });
        for k in 0..n {
            let mut v = [0.0; 6];
            for slot in &mut v[..per_vertex] {
                match self.lex.next_numeric() {
                    Ok(t) => *slot = self.number(t)?,
                    Err(None) => {
                        return Err(self.error(
                            line,
                            format!("{what} declares {n} vertices but the file ends after {k}"),
                        ))
                    }
                    Err(Some(t)) => {
                        return Err(self.error(
                            line,
                            format!(
                                "{what} declares {n} vertices but only {k} are given before `{}` on line {}",
                                quote(t.text),
                                t.line
                            ),
                        ))
                    }
                }
            }
            vertices.push([v[0], v[1], v[2]]);
            if patch {
                normals.push([v[3], v[4], v[5]]);
            }
        }
        let shape = if patch {
            Shape::Patch { vertices, normals }
        } else {
            Shape::Polygon { vertices }
        };
        self.push(shape, line)?;
        Ok(n)
    }
}

/// $a - b$.
fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Whether `a` and `b` are parallel (or either is zero): $|a \times b| \le 10^{-12} |a| |b|$.
pub(crate) fn is_parallel(a: P3, b: P3) -> bool {
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let len = |v: P3| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    len(c) <= 1e-12 * len(a) * len(b) || len(a) == 0.0 || len(b) == 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tokens(text: &str) -> Vec<(String, u32)> {
        let mut lex = Lexer::new(text.as_bytes());
        std::iter::from_fn(|| lex.next())
            .map(|t| (String::from_utf8_lossy(t.text).into_owned(), t.line))
            .collect()
    }

    #[test]
    fn lexer_counts_lines_and_skips_comments() {
        let got = tokens("a b#c d\n\n  e\r\nf\rg # h\n#x\n i");
        let want = [("a", 1), ("b", 1), ("e", 3), ("f", 4), ("g", 5), ("i", 7)];
        let want: Vec<_> = want.iter().map(|&(s, l)| (s.to_owned(), l)).collect();
        assert_eq!(got, want);
    }

    #[test]
    fn lexer_peek_does_not_consume() {
        let mut lex = Lexer::new(b"x\ny");
        assert_eq!(lex.peek().unwrap().text, b"x");
        assert_eq!(lex.next().unwrap().text, b"x");
        let y = lex.peek().unwrap();
        assert_eq!((y.text, y.line), (&b"y"[..], 2));
        assert_eq!(lex.next().unwrap().line, 2);
        assert!(lex.next().is_none());
        assert!(lex.peek().is_none());
    }

    #[test]
    fn numbers() {
        assert_eq!(parse_real(b"1"), Ok(1.0));
        assert_eq!(parse_real(b"-2.5e-1"), Ok(-0.25));
        assert_eq!(parse_real(b".5"), Ok(0.5));
        assert_eq!(parse_real(b"1.2.3"), Err(NumberError::Invalid));
        assert_eq!(parse_real(b"-"), Err(NumberError::Invalid));
        assert_eq!(parse_real(b"nan"), Err(NumberError::NotFinite));
        assert_eq!(parse_real(b"-Infinity"), Err(NumberError::NotFinite));
        assert_eq!(parse_real(b"1e999"), Err(NumberError::NotFinite));
        assert!(looks_numeric(b"NaN") && looks_numeric(b"-inf") && looks_numeric(b".5"));
        assert!(!looks_numeric(b"from") && !looks_numeric(b"info"));
    }

    #[test]
    fn parallel() {
        assert!(is_parallel([0.0, 0.0, 1.0], [0.0, 0.0, -3.0]));
        assert!(is_parallel([0.0; 3], [1.0, 0.0, 0.0]));
        assert!(!is_parallel([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]));
    }
}
