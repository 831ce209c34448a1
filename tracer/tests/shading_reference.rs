//! Rendered pixels against an independent `f64` reference of the Whitted model.
//!
//! The reference below does not call the tracer's camera, intersection or shading code:
//! it is written here from the model the crate documents (the `world` module docs for
//! NFF's material mapping, `Camera` for the eye rays, `Image::to_rgb8` for 8-bit
//! output), in plain `f64` on arrays:
//!
//! - eye ray through pixel centre $(i + 1/2, j + 1/2)$: $x = 2\hat x / w - 1$,
//!   $y = 1 - 2\hat y / h$, direction $\mathrm{normalize}(D + x L + y U)$ with
//!   $|U| = \tan(\alpha/2)$, $|L| = \frac{w}{h}\tan(\alpha/2)$, $L \parallel D \times up$;
//! - colour at a hit with surface colour $C$ (normals faced toward the ray):
//!   $K_a C + K_d C I (N \cdot L) + K_s I (R \cdot V)^n$ for the light when its shadow
//!   ray is clear and $N \cdot L > 0$, with $K_a = \max(0, 1 - K_d - K_s - T)$ and
//!   $R = 2N(N \cdot L) - L$; then, below the depth limit, $T C I_t$ along the Snell
//!   direction ($\eta = 1/n$ entering, $n$ leaving) and $K_s I_r$ along the mirror
//!   direction, total internal reflection moving $T$ onto the mirror ray (Whitted's
//!   weights, no Fresnel term);
//! - escaping rays see the background.
//!
//! Each scene is rendered by the library (`f64` and `f32`) and compared pixel by pixel.
//! A pixel is compared only if its ray tree is structurally stable: the reference traces
//! the same pixel with the eye ray moved by a small amount in x and y, and if any ray of
//! the tree hits another primitive or any shadow ray changes its answer (a silhouette,
//! a checker edge, a shadow edge, seen directly or through glass or a mirror), the pixel
//! is left out. That decision uses the reference only, so a wrong tracer cannot make a
//! pixel skip its check; each test also asserts how many pixels it compared and that the
//! feature it is about (an off-peak highlight of each exponent, a reflected checker, a
//! refracted checker) is among them.

// Per-channel sums over several arrays read best indexed.
#![allow(clippy::needless_range_loop)]

use tracer::scene::desc::MaterialDesc;
use tracer::{render, Image, Scene, SceneBuilder, Settings};

type P3 = [f64; 3];

fn add(a: P3, b: P3) -> P3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn mul(a: P3, s: f64) -> P3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: P3) -> P3 {
    mul(a, 1.0 / dot(a, a).sqrt())
}

// ----- the scene, shared by the library and the reference -------------------------------

/// A primitive of a test scene: a sphere or a convex planar polygon (counter-clockwise
/// seen from its front).
#[derive(Clone, Debug)]
enum Prim {
    Sphere { c: P3, r: f64 },
    Poly { v: Vec<P3>, n: P3 },
}

#[derive(Clone, Debug)]
struct TestScene {
    materials: Vec<MaterialDesc>,
    prims: Vec<(Prim, usize)>,
    light: P3,
    light_color: P3,
    background: P3,
    /// from, at, up, vertical angle in degrees.
    camera: (P3, P3, P3, f64),
}

impl TestScene {
    fn new(light: P3, light_color: P3, background: P3, camera: (P3, P3, P3, f64)) -> Self {
        Self {
            materials: Vec::new(),
            prims: Vec::new(),
            light,
            light_color,
            background,
            camera,
        }
    }

    fn material(&mut self, m: MaterialDesc) -> usize {
        // The reference takes K_r = K_s and K_t = T as given: the tracer only rescales
        // materials with Ks + T > 1, which these tests do not use.
        assert!(m.ks + m.t <= 1.0);
        self.materials.push(m);
        self.materials.len() - 1
    }

    fn sphere(&mut self, c: P3, r: f64, m: usize) {
        self.prims.push((Prim::Sphere { c, r }, m));
    }

    fn poly(&mut self, v: Vec<P3>, m: usize) {
        let n = unit(cross(sub(v[1], v[0]), sub(v[2], v[0])));
        self.prims.push((Prim::Poly { v, n }, m));
    }

    /// A checkerboard of `k` x `k` unit squares on the plane y = `y`, centred at the
    /// origin, facing up, in materials `a` and `b`.
    fn checker(&mut self, y: f64, k: i32, a: usize, b: usize) {
        let h = k / 2;
        for i in -h..k - h {
            for j in -h..k - h {
                let (x0, z0) = (i as f64, j as f64);
                let m = if (i + j).rem_euclid(2) == 0 { a } else { b };
                self.poly(
                    vec![
                        [x0, y, z0],
                        [x0, y, z0 + 1.0],
                        [x0 + 1.0, y, z0 + 1.0],
                        [x0 + 1.0, y, z0],
                    ],
                    m,
                );
            }
        }
    }

    /// An axis-aligned box from `lo` to `hi`, faces wound counter-clockwise from
    /// outside.
    fn cuboid(&mut self, lo: P3, hi: P3, m: usize) {
        let p = |x: usize, y: usize, z: usize| {
            [[lo[0], hi[0]][x], [lo[1], hi[1]][y], [lo[2], hi[2]][z]]
        };
        let faces = [
            [p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0)], // top, +y
            [p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1)], // bottom, -y
            [p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1)], // +x
            [p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0)], // -x
            [p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1)], // +z
            [p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0)], // -z
        ];
        let centre = mul(add(lo, hi), 0.5);
        for f in faces {
            let n = unit(cross(sub(f[1], f[0]), sub(f[2], f[0])));
            assert!(dot(n, sub(f[0], centre)) > 0.0, "face wound inward");
            self.poly(f.to_vec(), m);
        }
    }

    /// The same scene through the library's builder.
    fn build<T: tracer::Float>(&self) -> Scene<T> {
        let mut b = SceneBuilder::default();
        for m in &self.materials {
            b.add_material(m.clone());
        }
        for (p, m) in &self.prims {
            match p {
                Prim::Sphere { c, r } => {
                    b.add_sphere(*c, *r, *m as u32);
                }
                Prim::Poly { v, .. } => {
                    b.add_polygon(v.clone(), *m as u32);
                }
            }
        }
        b.add_light(self.light, Some(self.light_color));
        b.background(self.background);
        let (from, at, up, angle) = self.camera;
        b.look_at(from, at, up, angle);
        b.build()
    }
}

// ----- the reference ---------------------------------------------------------------------

/// Hits closer than this are the surface a ray leaves (the tracer moves such origins off
/// the surface by about 1e-13 in f64; every surface in these scenes is at least 0.1
/// from any other along any ray).
const T_EPS: f64 = 1e-9;

/// The nearest intersection of `o + t d` (unit `d`) with `prim` for `t` in
/// (`T_EPS`, `t_max`).
fn hit_prim(prim: &Prim, o: P3, d: P3, t_max: f64) -> Option<f64> {
    match prim {
        Prim::Sphere { c, r } => {
            // |o + t d - c|^2 = r^2: t^2 + 2 b t + q = 0.
            let f = sub(o, *c);
            let b = dot(f, d);
            let q = dot(f, f) - r * r;
            let disc = b * b - q;
            if disc < 0.0 {
                return None;
            }
            let s = disc.sqrt();
            [-b - s, -b + s]
                .into_iter()
                .find(|&t| t > T_EPS && t < t_max)
        }
        Prim::Poly { v, n } => {
            let denom = dot(*n, d);
            if denom == 0.0 {
                return None;
            }
            let t = dot(*n, sub(v[0], o)) / denom;
            if t.is_nan() || t <= T_EPS || t >= t_max {
                return None;
            }
            let p = add(o, mul(d, t));
            // Inside a convex polygon: on the inner side of every edge.
            let inside = (0..v.len()).all(|k| {
                let (a, b) = (v[k], v[(k + 1) % v.len()]);
                dot(cross(sub(b, a), sub(p, a)), *n) >= 0.0
            });
            inside.then_some(t)
        }
    }
}

/// What the reference saw along one ray tree: which primitive each ray hit and what
/// each shadow ray answered, in order. Two trees with the same path are the same smooth
/// function of the eye ray.
#[derive(Default, PartialEq, Debug)]
struct Path(Vec<i64>);

/// What a pixel exercised, for the coverage assertions.
#[derive(Default, Clone, Copy)]
struct Seen {
    /// A lit highlight with $(R \cdot V)^n$ in [0.05, 0.9]: well off the peak.
    off_peak_highlight: bool,
    /// A mirror ray that hit a checker square.
    reflected_checker: bool,
    /// A refracted ray (after leaving the glass) that hit a checker square.
    refracted_checker: bool,
}

struct Reference<'a> {
    s: &'a TestScene,
    max_depth: u32,
    /// Primitives below this index are checker squares.
    checker_end: usize,
}

impl Reference<'_> {
    /// The eye ray through image-plane point (`px`, `py`) of a `w` x `h` image.
    fn eye(&self, w: u32, h: u32, px: f64, py: f64) -> (P3, P3) {
        let (from, at, up, angle) = self.s.camera;
        let d = unit(sub(at, from));
        let half = (angle.to_radians() / 2.0).tan();
        let l = mul(unit(cross(d, up)), half * w as f64 / h as f64);
        let u = mul(unit(cross(unit(cross(d, up)), d)), half);
        let x = 2.0 * px / w as f64 - 1.0;
        let y = 1.0 - 2.0 * py / h as f64;
        (from, unit(add(add(d, mul(l, x)), mul(u, y))))
    }

    fn closest(&self, o: P3, d: P3, t_max: f64) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        for (i, (p, _)) in self.s.prims.iter().enumerate() {
            if let Some(t) = hit_prim(p, o, d, best.map_or(t_max, |b| b.0)) {
                best = Some((t, i));
            }
        }
        best
    }

    fn trace(&self, o: P3, d: P3, depth: u32, path: &mut Path, seen: &mut Seen) -> P3 {
        let Some((t, id)) = self.closest(o, d, f64::INFINITY) else {
            path.0.push(-1);
            return self.s.background;
        };
        path.0.push(id as i64);
        let (prim, mi) = &self.s.prims[id];
        let m = &self.s.materials[*mi];
        let p = add(o, mul(d, t));
        let outward = match prim {
            Prim::Sphere { c, r } => mul(sub(p, *c), 1.0 / r),
            Prim::Poly { n, .. } => *n,
        };
        let entering = dot(outward, d) < 0.0;
        let n = if entering {
            outward
        } else {
            mul(outward, -1.0)
        };
        let c = m.color;
        let ka = (1.0 - m.kd - m.ks - m.t).max(0.0);
        let mut col = mul(c, ka);

        // The point light, if the surface faces it and nothing is in between.
        let to_light = sub(self.s.light, p);
        let dist = dot(to_light, to_light).sqrt();
        let l = mul(to_light, 1.0 / dist);
        let ndotl = dot(n, l);
        if ndotl > 0.0 {
            let blocked = self.closest(p, l, dist).is_some();
            path.0.push(if blocked { -2 } else { -3 });
            if !blocked {
                let i = self.s.light_color;
                for k in 0..3 {
                    col[k] += m.kd * c[k] * i[k] * ndotl;
                }
                let r = sub(mul(n, 2.0 * ndotl), l);
                let rv = -dot(r, d);
                if m.ks > 0.0 && rv > 0.0 {
                    let spec = rv.powf(m.shine);
                    seen.off_peak_highlight |= (0.05..=0.9).contains(&spec);
                    for k in 0..3 {
                        col[k] += m.ks * i[k] * spec;
                    }
                }
            }
        }
        if depth >= self.max_depth {
            return col;
        }

        let mut kr = m.ks;
        if m.t > 0.0 {
            // Snell: sin θt = η sin θi.
            let eta = if entering { 1.0 / m.ior } else { m.ior };
            let cos_i = -dot(n, d);
            let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
            if k < 0.0 {
                path.0.push(-4);
                kr += m.t;
            } else {
                let td = unit(add(mul(d, eta), mul(n, eta * cos_i - k.sqrt())));
                let before = path.0.len();
                let ct = self.trace(p, td, depth + 1, path, seen);
                let landed = path.0[before];
                if landed >= 0 && (landed as usize) < self.checker_end && !entering {
                    seen.refracted_checker = true;
                }
                for k in 0..3 {
                    col[k] += m.t * c[k] * ct[k];
                }
            }
        }
        if kr > 0.0 {
            let rd = unit(sub(d, mul(n, 2.0 * dot(n, d))));
            let before = path.0.len();
            let cr = self.trace(p, rd, depth + 1, path, seen);
            let landed = path.0[before];
            if landed >= 0 && (landed as usize) < self.checker_end && m.t == 0.0 {
                seen.reflected_checker = true;
            }
            for k in 0..3 {
                col[k] += kr * cr[k];
            }
        }
        col
    }

    /// The pixel's reference colour, or `None` if its ray tree changes within `delta`
    /// pixels of the centre.
    fn pixel(&self, w: u32, h: u32, x: u32, y: u32, delta: f64) -> Option<(P3, Seen)> {
        let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
        let run = |px: f64, py: f64| {
            let (o, d) = self.eye(w, h, px, py);
            let (mut path, mut seen) = (Path::default(), Seen::default());
            let c = self.trace(o, d, 1, &mut path, &mut seen);
            (c, path, seen)
        };
        let (c, path, seen) = run(px, py);
        for (dx, dy) in [(delta, 0.0), (-delta, 0.0), (0.0, delta), (0.0, -delta)] {
            if run(px + dx, py + dy).1 != path {
                return None;
            }
        }
        Some((c, seen))
    }
}

// ----- comparison ------------------------------------------------------------------------

/// Distance in representable `f32` values between two non-negative finite floats.
fn ulps(a: f32, b: f32) -> u32 {
    assert!(a >= 0.0 && b >= 0.0, "{a} {b}");
    a.to_bits().abs_diff(b.to_bits())
}

/// `Image::to_rgb8`'s documented conversion of an image channel (an `f32`): clamp to
/// [0, 1], scale by 255 and round, in `f32` arithmetic as the image holds it (so a value
/// such as 0.7, whose product with 255 rounds to 178.5 in `f32`, gives 179 on both
/// sides).
fn to_u8(v: f32) -> i32 {
    i32::from((v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
}

struct Check {
    /// Largest accepted |tracer - reference| in a channel, beyond `max_ulps`.
    abs_tol: f64,
    /// Accepted distance in f32 values (for the `f64` render).
    max_ulps: u32,
    /// Eye-ray displacement (pixels) within which the ray tree must not change.
    delta: f64,
}

/// How many pixels were compared and what they exercised.
#[derive(Default, Debug)]
struct Tally {
    compared: usize,
    skipped: usize,
    off_peak: usize,
    reflected_checker: usize,
    refracted_checker: usize,
    /// Channels whose 8-bit values differ by one (rounding at a .5 boundary).
    off_by_one_u8: usize,
}

fn compare(what: &str, r: &Reference, img: &Image, check: &Check) -> Tally {
    let (w, h) = (img.width, img.height);
    let mut tally = Tally::default();
    let mut failures = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let Some((want, seen)) = r.pixel(w, h, x, y, check.delta) else {
                tally.skipped += 1;
                continue;
            };
            tally.compared += 1;
            tally.off_peak += usize::from(seen.off_peak_highlight);
            tally.reflected_checker += usize::from(seen.reflected_checker);
            tally.refracted_checker += usize::from(seen.refracted_checker);
            let got = img.get(x, y);
            for k in 0..3 {
                let (g, e) = (got[k], want[k]);
                let close = ulps(g, e as f32) <= check.max_ulps
                    || (f64::from(g) - e).abs() <= check.abs_tol;
                let (g8, e8) = (to_u8(g), to_u8(e as f32));
                tally.off_by_one_u8 += usize::from(g8 != e8);
                if !close || g8.abs_diff(e8) > 1 {
                    failures.push(format!(
                        "({x}, {y}) channel {k}: tracer {g:e}, reference {e:e}"
                    ));
                }
            }
        }
    }
    println!("{what}: {tally:?}");
    assert!(
        failures.is_empty(),
        "{what}: {} channels differ from the reference, first: {:?}",
        failures.len(),
        &failures[..failures.len().min(8)]
    );
    // A one-step 8-bit difference needs a value within about 1e-7 of a .5 boundary.
    assert!(
        tally.off_by_one_u8 * 100 <= tally.compared,
        "{what}: {tally:?}"
    );
    tally
}

/// The `f64` render: the tracer's result and the reference differ only by rounding
/// (about 1e-15 relative per operation, a few dozen operations, plus secondary-ray
/// origins moved by 256 f64 ulps), far below half an f32 ulp (3e-8 relative); so after
/// rounding to the f32 image each channel equals the reference rounded to f32, or is the
/// next f32 when the exact value lies within that error of a rounding boundary: 1 ulp.
/// Values near zero (a highlight or Lambert term at grazing angles) get 1e-12 absolute
/// instead, the same error bound without the relative scaling.
const F64: Check = Check {
    abs_tol: 1e-12,
    max_ulps: 1,
    delta: 1e-4,
};

/// The `f32` render: inputs are rounded to f32 (relative 6e-8) and each step adds a
/// rounding; measured differences stay below 2e-5 on these scenes (a Phong power of 60
/// multiplies the relative error of R·V by 60). 1e-4 is a tenth of an 8-bit step
/// (1/255 = 3.9e-3) and is still 1/25 of what a Phong exponent 5% off, a 1% error in
/// the index of refraction or a missing ambient term change on these scenes. f32 ray
/// directions are off by about 1e-7 rad, so the ray tree must be stable over 0.02 px.
const F32: Check = Check {
    abs_tol: 1e-4,
    max_ulps: 0,
    delta: 0.02,
};

fn settings(w: u32, h: u32, depth: u32) -> Settings {
    Settings {
        width: Some(w),
        height: Some(h),
        depth,
        ..Settings::default()
    }
}

/// Renders `scene` in both precisions and compares each with the reference; returns the
/// `f64` tally.
fn check_scene(
    what: &str,
    scene: &TestScene,
    checker_end: usize,
    size: (u32, u32),
    depth: u32,
) -> Tally {
    let r = Reference {
        s: scene,
        max_depth: depth,
        checker_end,
    };
    let s = settings(size.0, size.1, depth);
    let t64 = compare(
        &format!("{what} f64"),
        &r,
        &render(&scene.build::<f64>(), &s),
        &F64,
    );
    let t32 = compare(
        &format!("{what} f32"),
        &r,
        &render(&scene.build::<f32>(), &s),
        &F32,
    );
    let n = (size.0 * size.1) as usize;
    // Most pixels are away from every edge.
    assert!(t64.compared * 10 >= n * 8, "{what}: {t64:?}");
    assert!(t32.compared * 10 >= n * 7, "{what}: {t32:?}");
    t64
}

fn matte(color: P3, kd: f64) -> MaterialDesc {
    MaterialDesc {
        color,
        kd,
        ks: 0.0,
        shine: 1.0,
        t: 0.0,
        ior: 1.0,
    }
}

// ----- the scenes ------------------------------------------------------------------------

/// Three spheres with Phong exponents 3, 12 and 60 over a matte floor, one coloured point
/// light.
fn three_spheres() -> TestScene {
    let mut s = TestScene::new(
        [4.0, 7.0, 6.0],
        [1.0, 0.9, 0.7],
        [0.05, 0.1, 0.2],
        ([0.0, 2.5, 8.0], [0.0, 0.8, 0.0], [0.0, 1.0, 0.0], 32.0),
    );
    let floor = s.material(matte([0.8, 0.75, 0.6], 0.7));
    s.poly(
        vec![
            [-6.0, 0.0, -6.0],
            [-6.0, 0.0, 6.0],
            [6.0, 0.0, 6.0],
            [6.0, 0.0, -6.0],
        ],
        floor,
    );
    let shiny = |color: P3, shine: f64| MaterialDesc {
        color,
        kd: 0.5,
        ks: 0.4,
        shine,
        t: 0.0,
        ior: 1.0,
    };
    for (x, color, shine) in [
        (-2.2, [0.9, 0.2, 0.2], 3.0),
        (0.0, [0.2, 0.8, 0.3], 12.0),
        (2.2, [0.3, 0.4, 0.9], 60.0),
    ] {
        let m = s.material(shiny(color, shine));
        s.sphere([x, 1.0, 0.0], 0.9, m);
    }
    s
}

/// The three spheres under local shading only (depth 1): ambient, Lambert with shadows,
/// highlights off their peak.
#[test]
fn ambient_lambert_and_phong_match_the_reference() {
    let s = three_spheres();
    let t = check_scene("phong", &s, 0, (96, 64), 1);
    // Every sphere shows an off-peak highlight; count them per exponent by rendering the
    // spheres alone.
    assert!(t.off_peak >= 60, "{t:?}");
    for k in 0..3 {
        let mut one = s.clone();
        one.prims = vec![s.prims[0].clone(), s.prims[1 + k].clone()];
        let r = Reference {
            s: &one,
            max_depth: 1,
            checker_end: 0,
        };
        let off_peak = (0..64)
            .flat_map(|y| (0..96).map(move |x| (x, y)))
            .filter_map(|(x, y)| r.pixel(96, 64, x, y, F64.delta))
            .filter(|(_, seen)| seen.off_peak_highlight)
            .count();
        assert!(off_peak >= 10, "exponent {}: {off_peak}", [3, 12, 60][k]);
    }
}

/// The three spheres under a ceiling just above the light. A shadow ray ends at the
/// light, so the ceiling, which every shadow ray of the scene would reach if it went on,
/// shadows nothing: the spheres keep their lit sides and highlights.
#[test]
fn a_surface_beyond_the_light_casts_no_shadow() {
    let mut s = three_spheres();
    let ceiling = s.material(matte([0.5, 0.5, 0.5], 0.5));
    // Wound clockwise seen from above: it faces down, toward the light.
    s.poly(
        vec![
            [-30.0, 8.0, -30.0],
            [30.0, 8.0, -30.0],
            [30.0, 8.0, 30.0],
            [-30.0, 8.0, 30.0],
        ],
        ceiling,
    );
    let t = check_scene("beyond the light", &s, 0, (96, 64), 1);
    assert!(t.off_peak >= 60, "{t:?}");
}

/// A mirror (Ks = 0.8, a faint highlight, some ambient) facing a checkerboard, with a
/// coloured sphere in front: the checker seen directly and in the mirror.
#[test]
fn mirror_reflects_the_checkerboard() {
    let mut s = TestScene::new(
        [2.0, 6.0, 5.0],
        [1.0, 1.0, 1.0],
        [0.3, 0.5, 0.7],
        ([1.5, 3.0, 6.0], [0.0, 0.5, -2.0], [0.0, 1.0, 0.0], 40.0),
    );
    let a = s.material(matte([0.95, 0.95, 0.9], 0.8));
    let b = s.material(matte([0.15, 0.2, 0.5], 0.8));
    s.checker(0.0, 10, a, b);
    let checker_end = s.prims.len();
    let mirror = s.material(MaterialDesc {
        color: [1.0, 1.0, 1.0],
        kd: 0.0,
        ks: 0.8,
        shine: 30.0,
        t: 0.0,
        ior: 1.0,
    });
    // A vertical mirror at z = -3 facing +z.
    s.poly(
        vec![
            [-4.0, 0.2, -3.0],
            [4.0, 0.2, -3.0],
            [4.0, 3.5, -3.0],
            [-4.0, 3.5, -3.0],
        ],
        mirror,
    );
    let red = s.material(matte([0.9, 0.1, 0.1], 0.6));
    s.sphere([0.5, 0.7, -0.5], 0.6, red);
    let t = check_scene("mirror", &s, checker_end, (80, 64), 5);
    assert!(t.reflected_checker >= 300, "{t:?}");
}

/// Glass (T = 0.85, Ks = 0.05, index 1.5, slightly tinted) over a checkerboard: a slab
/// (a closed box) and a sphere, each pixel's source found by Snell's law.
#[test]
fn glass_slab_and_sphere_refract_the_checkerboard() {
    let glass = MaterialDesc {
        color: [0.9, 1.0, 0.95],
        kd: 0.0,
        ks: 0.05,
        shine: 80.0,
        t: 0.85,
        ior: 1.5,
    };
    let base = || {
        let mut s = TestScene::new(
            [-3.0, 8.0, 4.0],
            [1.0, 1.0, 1.0],
            [0.2, 0.3, 0.4],
            ([0.0, 4.0, 5.0], [0.0, 0.3, 0.0], [0.0, 1.0, 0.0], 45.0),
        );
        let a = s.material(matte([0.95, 0.9, 0.8], 0.8));
        let b = s.material(matte([0.1, 0.3, 0.15], 0.8));
        s.checker(0.0, 12, a, b);
        s
    };
    let mut slab = base();
    let checker_end = slab.prims.len();
    let g = slab.material(glass.clone());
    slab.cuboid([-2.0, 0.6, -1.5], [2.0, 1.1, 1.5], g);
    let t = check_scene("glass slab", &slab, checker_end, (80, 64), 5);
    assert!(t.refracted_checker >= 500, "{t:?}");

    let mut ball = base();
    let g = ball.material(glass);
    ball.sphere([0.0, 1.3, 0.0], 1.2, g);
    let t = check_scene("glass sphere", &ball, checker_end, (80, 64), 5);
    assert!(t.refracted_checker >= 300, "{t:?}");
}
