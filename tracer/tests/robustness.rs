//! Numerical robustness: watertight meshes, distant spheres, self-intersection of spawned
//! rays, refraction, degenerate input and f32 against f64. Modelled on Embree's `verify`
//! suite, pbrt-v4's shape tests and Ray Tracing Gems (2019) chapters 6 and 7; the cases,
//! methods and measured numbers are in `tracer/ROBUSTNESS.md`.
//!
//! Every test prints what it measured (`cargo test -p tracer --test integration
//! robustness:: -- --nocapture`). `ROBUSTNESS_SIZE=512` renders the f32/f64 comparison at full size.

use tracer::geometry::{offset_ray, AccelOptions, Geometry, GeometryBuilder, TriangleTest};
use tracer::scene::desc::{MaterialDesc, P3};
use tracer::shade::{trace_fx, TraceLimits};
use tracer::{render, Image, Ray, RayCounts, Scene, SceneBuilder, Settings};
use vecexpr::{vec3, Expr, Vec3};

// ----- helpers ----------------------------------------------------------------------------

/// Fixed-seed xorshift64*.
struct Rng(u64);

impl Rng {
    fn f(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
    /// Log-uniform in `[a, b]`.
    fn log(&mut self, a: f64, b: f64) -> f64 {
        (a.ln() + (b.ln() - a.ln()) * self.f()).exp()
    }
    fn in_ball(&mut self) -> P3 {
        loop {
            let p = [
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            ];
            if dot(p, p) <= 1.0 && dot(p, p) > 1e-6 {
                return p;
            }
        }
    }
    fn unit(&mut self) -> P3 {
        let p = self.in_ball();
        scale(p, 1.0 / dot(p, p).sqrt())
    }
}

fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn add(a: P3, b: P3) -> P3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: P3, s: f64) -> P3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: P3) -> f64 {
    dot(a, a).sqrt()
}
fn unit(a: P3) -> P3 {
    scale(a, 1.0 / norm(a))
}
/// Two unit vectors perpendicular to the unit `a` and to each other.
fn basis(a: P3) -> (P3, P3) {
    let t = if a[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = unit(cross(a, t));
    (u, cross(a, u))
}

/// The radiance of `ray` as the general renderer traces it.
fn trace<T: tracer::Float>(
    scene: &Scene<T>,
    ray: &Ray<T>,
    depth: u32,
    weight: T,
    limits: &TraceLimits<T>,
    counts: &mut RayCounts,
) -> Vec3<T> {
    trace_fx::<T, { tracer::effects::ALL }>(scene, ray, depth, weight, limits, counts)
}

fn v<T: tracer::Float>(p: P3) -> Vec3<T> {
    vec3(T::from_f64(p[0]), T::from_f64(p[1]), T::from_f64(p[2]))
}
fn w<T: tracer::Float>(p: &Vec3<T>) -> P3 {
    [p[0].to_f64(), p[1].to_f64(), p[2].to_f64()]
}

/// A closed icosphere: the icosahedron subdivided `levels` times, vertices pushed to the
/// sphere, shared between neighbouring triangles, outward winding.
fn icosphere(center: P3, radius: f64, levels: u32) -> (Vec<P3>, Vec<[u32; 3]>) {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut pos: Vec<P3> = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| unit(p))
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::with_capacity(tris.len() * 4);
        let mut m = |a: u32, b: u32, pos: &mut Vec<P3>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                pos.push(unit(scale(add(pos[a as usize], pos[b as usize]), 0.5)));
                (pos.len() - 1) as u32
            })
        };
        for [a, b, c] in tris {
            let (ab, bc, ca) = (m(a, b, &mut pos), m(b, c, &mut pos), m(c, a, &mut pos));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    let pos = pos.iter().map(|&p| add(center, scale(p, radius))).collect();
    (pos, tris)
}

fn mesh_geometry<T: tracer::Float>(
    pos: &[Vec3<T>],
    tris: &[[u32; 3]],
    test: TriangleTest,
) -> Geometry<T> {
    let opts = AccelOptions {
        triangle: test,
        ..AccelOptions::default()
    };
    GeometryBuilder::<T>::new()
        .add_mesh(pos, tris, None, 0)
        .build(&opts)
}

fn material(kd: f64, ks: f64, t: f64, ior: f64, color: P3) -> MaterialDesc {
    MaterialDesc {
        color,
        kd,
        ks,
        shine: 10.0,
        t,
        ior,
    }
}

// ----- watertight triangles ---------------------------------------------------------------

/// Escapes from inside a closed icosphere of radius 2 (5,120 triangles) in `f32`, far from
/// the origin and at it: 10^6 random rays from random inner points, plus rays from the
/// centre and from random inner points aimed exactly at every vertex and edge midpoint.
/// Watertight (Woop et al. 2013) with the conservative BVH: zero escapes. Möller–Trumbore
/// on the same rays: the counts ROBUSTNESS.md reports.
#[test]
fn closed_mesh_has_no_escapes_far_from_and_at_the_origin() {
    type T = f32;
    for center in [[148376.0, 1234.0, -223423.0], [0.0, 0.0, 0.0]] {
        let radius = 2.0;
        let (pos, tris) = icosphere(center, radius, 4);
        let p: Vec<Vec3<T>> = pos.iter().map(|&q| v(q)).collect();
        let wt = mesh_geometry(&p, &tris, TriangleTest::Watertight);
        let mt = mesh_geometry(&p, &tris, TriangleTest::MollerTrumbore);
        // Rounding the vertices to f32 (ulp 1/64 at 2^17) must keep every triangle.
        assert_eq!(wt.stats().triangles, tris.len());
        assert_eq!(wt.stats().skipped, 0);
        let mut rng = Rng(0x243f_6a88_85a3_08d3);
        let c: Vec3<T> = v(center);
        let mut rays: Vec<Ray<T>> = Vec::with_capacity(1_040_000);
        for _ in 0..1_000_000 {
            let o = v::<T>(add(center, scale(rng.in_ball(), 0.5 * radius)));
            rays.push(Ray::new(o, v(rng.unit())));
        }
        let random = rays.len();
        // Aimed rays: direction = target - origin in f32 (exact by Sterbenz' lemma far
        // from the origin, exact for the centre at the origin).
        let mut targets: Vec<Vec3<T>> = p.clone();
        for t in &tris {
            for k in 0..3 {
                let (a, b) = (p[t[k] as usize], p[t[(k + 1) % 3] as usize]);
                targets.push((&a + &b).scale(0.5).eval());
            }
        }
        for t in &targets {
            let o = v::<T>(add(center, scale(rng.in_ball(), 0.3 * radius)));
            for o in [c, o] {
                let d = (t - &o).eval();
                if d.length_squared() > 0.0 {
                    rays.push(Ray::new(o, d));
                }
            }
        }
        let (mut esc_wt, mut esc_mt) = (0usize, 0usize);
        let (mut esc_wt_aimed, mut esc_mt_aimed) = (0usize, 0usize);
        for (i, r) in rays.iter().enumerate() {
            let a = wt.intersect(r).is_none();
            let b = mt.intersect(r).is_none();
            if i >= random {
                assert_eq!(wt.occluded(r), !a, "occluded disagrees with intersect");
            }
            esc_wt += a as usize;
            esc_mt += b as usize;
            if i >= random {
                esc_wt_aimed += a as usize;
                esc_mt_aimed += b as usize;
            }
        }
        let n = rays.len();
        println!(
            "watertight: centre {center:?}: {n} rays ({random} random, {} aimed at vertices \
             and edges): watertight {esc_wt} escapes ({esc_wt_aimed} aimed), \
             Moller-Trumbore {esc_mt} escapes ({esc_mt_aimed} aimed) = {:.4}%",
            n - random,
            100.0 * esc_mt as f64 / n as f64
        );
        assert_eq!(esc_wt, 0, "watertight test leaked at {center:?}");
        // ROBUSTNESS.md's table: 1,035,844 rays per centre; Möller–Trumbore loses none
        // far from the origin and 4,073 at it, all among the aimed rays. The rays and
        // both kernels are deterministic (seeded, plain IEEE f32), so the counts are
        // exact.
        assert_eq!(n, 1_035_844);
        let want_mt = if center[0] == 0.0 { 4_073 } else { 0 };
        assert_eq!(esc_mt, want_mt, "Möller–Trumbore escapes at {center:?}");
        assert_eq!(esc_mt_aimed, esc_mt, "escapes outside the aimed rays");
    }
}

// ----- spheres ----------------------------------------------------------------------------

/// Exact (f64) closest approach of the f32 ray to the centre, and the near root.
fn sphere_reference(o: P3, d: P3, c: P3, r: f64) -> (f64, Option<f64>) {
    let f = sub(o, c);
    let dd = dot(d, d);
    let b = dot(f, d);
    let l = sub(f, scale(d, b / dd));
    let rho = norm(l);
    let disc = r * r - dot(l, l);
    if disc < 0.0 {
        return (rho, None);
    }
    let q = -b - (dd * disc).sqrt().copysign(b);
    let (t0, t1) = ((dot(f, f) - r * r) / q, q / dd);
    let (near, far) = (t0.min(t1), t0.max(t1));
    (rho, [near, far].into_iter().find(|&t| t > 0.0))
}

/// A unit sphere at the origin seen from 10^2 to 10^5 in f32: every ray whose line passes
/// well inside hits, well outside misses; hit points lie within 10^-4 of the surface.
#[test]
fn unit_sphere_seen_from_far_away() {
    type T = f32;
    let view = unit([1.0, 0.37, -0.61]);
    let (u, wv) = basis(view);
    let g = GeometryBuilder::<T>::new()
        .add_sphere(vec3(0.0, 0.0, 0.0), 1.0, 0)
        .build(&AccelOptions::default());
    for dist in [1e2, 1e3, 1e4, 1e5] {
        let eye = scale(view, dist);
        let o = v::<T>(eye);
        let n = 201;
        let (mut band, mut surf, mut along, mut normal_err) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        let (mut holes, mut extra) = (0usize, 0usize);
        for i in 0..n {
            for j in 0..n {
                let x = -1.25 + 2.5 * i as f64 / (n - 1) as f64;
                let y = -1.25 + 2.5 * j as f64 / (n - 1) as f64;
                let target = add(scale(u, x), scale(wv, y));
                let d = v::<T>(unit(sub(target, eye)));
                let (rho, t_ref) = sphere_reference(w(&o), w(&d), [0.0; 3], 1.0);
                let hit = g.intersect(&Ray::new(o, d));
                if hit.is_some() != t_ref.is_some() {
                    band = band.max((rho - 1.0).abs());
                    if rho < 0.98 {
                        holes += 1;
                    } else if rho > 1.02 {
                        extra += 1;
                    }
                }
                if let (Some(h), Some(t)) = (hit, t_ref) {
                    let p = w(&h.point);
                    surf = surf.max((norm(p) - 1.0).abs());
                    let exact = add(w(&o), scale(w(&d), t));
                    along = along.max(norm(sub(p, exact)));
                    normal_err = normal_err.max(norm(sub(w(&h.geometric_normal), unit(exact))));
                }
            }
        }
        println!(
            "sphere at distance {dist:e}: hit/miss differs from exact only within |rho - 1| <= \
             {band:.2e}; max distance of hit point from surface {surf:.2e}, from the exact \
             hit of the same ray {along:.2e}; max normal error {normal_err:.2e}"
        );
        assert_eq!((holes, extra), (0, 0), "distance {dist}");
        assert!(surf <= 1e-4, "distance {dist}: {surf}");
    }
}

/// The disc rendered in f32 from 10^2 to 10^5 has no hole (a background pixel inside) and
/// no speckle (a pixel far from the f64 render) away from its rim.
#[test]
fn rendered_distant_disc_has_no_holes_or_speckles() {
    let view = unit([1.0, 0.37, -0.61]);
    let (u, _) = basis(view);
    for dist in [1e2, 1e3, 1e4, 1e5] {
        let mut b = SceneBuilder::default();
        let m = b.add_material(material(0.8, 0.0, 0.0, 1.0, [1.0, 1.0, 1.0]));
        b.add_sphere([0.0; 3], 1.0, m);
        let eye = scale(view, dist);
        b.add_light(add(eye, scale(u, 0.5 * dist)), Some([1.0, 1.0, 1.0]));
        b.background([0.1, 0.2, 0.3]);
        b.look_at(eye, [0.0; 3], u, 2.0 * (1.3 / dist).atan().to_degrees());
        let s32: Scene<f32> = b.build();
        let s64: Scene<f64> = b.build();
        let size = 64;
        let settings = Settings {
            width: Some(size),
            height: Some(size),
            ..Settings::default()
        };
        let (a, c) = (render(&s32, &settings), render(&s64, &settings));
        let cam = s64.camera_for(size, size);
        let (mut holes, mut speckles, mut interior, mut max_diff) = (0, 0, 0, 0.0f32);
        for y in 0..size {
            for x in 0..size {
                let d = cam.direction(x as f64 + 0.5, y as f64 + 0.5);
                let (rho, _) = sphere_reference(eye, w(&d), [0.0; 3], 1.0);
                if rho > 0.98 {
                    continue;
                }
                interior += 1;
                let (p, q) = (a.get(x, y), c.get(x, y));
                if p == [0.1, 0.2, 0.3] {
                    holes += 1;
                }
                let diff = (0..3).map(|k| (p[k] - q[k]).abs()).fold(0.0, f32::max);
                max_diff = max_diff.max(diff);
                if diff > 8.0 / 255.0 {
                    speckles += 1;
                }
            }
        }
        println!(
            "disc at distance {dist:e}: {interior} interior pixels, {holes} holes, {speckles} \
             speckles (> 8/255 from f64), max difference from f64 {:.2}/255",
            max_diff * 255.0
        );
        assert!(interior > 1000);
        assert_eq!((holes, speckles), (0, 0), "distance {dist}");
    }
}

/// Rays exactly tangent (in f64) to spheres, rounded to the precision at hand: hit or
/// miss, `intersect` and `occluded` agree, and a hit is on the surface near the tangent
/// point.
fn tangent_rays<T: tracer::Float>(tol: f64) {
    let mut rng = Rng(11);
    let mut hits = 0;
    let n = 20_000;
    for k in 0..n {
        let r = rng.log(1e-2, 1e2);
        let c = scale(rng.unit(), rng.range(0.0, 100.0));
        let g = GeometryBuilder::<T>::new()
            .add_sphere(v(c), T::from_f64(r), 0)
            .build(&AccelOptions::default());
        let dir = rng.unit();
        let (a, _) = basis(dir);
        // The line c + r a + s dir touches the sphere at c + r a.
        let touch = add(c, scale(a, r));
        let back = r * rng.range(2.0, 10.0);
        let o = v::<T>(sub(touch, scale(dir, back)));
        let d = v::<T>(dir);
        let ray = Ray::new(o, d);
        let hit = g.intersect(&ray);
        assert_eq!(hit.is_some(), g.occluded(&ray), "ray {k}");
        if let Some(h) = hit {
            hits += 1;
            let p = w(&h.point);
            let scale_ = r + norm(c);
            assert!(
                (norm(sub(p, c)) - r).abs() <= tol * scale_,
                "ray {k}: off the surface"
            );
            // Within sqrt of the rounding of the touch point along the ray.
            let off = norm(sub(p, touch));
            assert!(
                off <= (tol * scale_ * r).sqrt() * 8.0 + tol * scale_,
                "ray {k}: {off}"
            );
        }
    }
    println!(
        "tangent rays ({}): {hits} of {n} hit, all consistent",
        std::any::type_name::<T>()
    );
}

#[test]
fn tangent_rays_behave_consistently() {
    tangent_rays::<f32>(1e-5);
    tangent_rays::<f64>(1e-13);
}

/// Rays starting inside a sphere hit its inside: always a hit, leaving through the
/// surface (outward normal along the ray), on the surface.
#[test]
fn rays_from_inside_hit_the_inside() {
    type T = f32;
    let mut rng = Rng(5);
    for (c, r) in [
        ([0.0; 3], 1.0),
        ([100.0, -200.0, 50.0], 1.0),
        ([3.0, 1.0, -2.0], 1e-3),
    ] {
        let g = GeometryBuilder::<T>::new()
            .add_sphere(v(c), r as T, 0)
            .build(&AccelOptions::default());
        for _ in 0..20_000 {
            let o = v::<T>(add(c, scale(rng.in_ball(), 0.999 * r)));
            let d = v::<T>(rng.unit());
            let h = g
                .intersect(&Ray::new(o, d))
                .expect("a ray from inside hits");
            assert!(h.t > 0.0 && h.geometric_normal.dot(&d) > 0.0);
            // 10^-4 of the radius, or a few ulps of the centre's coordinates when
            // those are coarser.
            let err = (norm(sub(w(&h.point), c)) - r).abs();
            assert!(
                err <= 1e-4 * r + 4.0 * f64::from(f32::EPSILON) * norm(c),
                "{err}"
            );
        }
    }
}

// ----- self-intersection ------------------------------------------------------------------

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Sphere,
    Triangle,
    Cylinder,
}

#[derive(Default, Debug)]
struct SelfHits {
    points: usize,
    /// The primary ray missed (a triangle of sub-ulp size, a grazing ray).
    skipped: usize,
    /// A ray from outside a sphere or cylinder, tangent to within rounding, whose
    /// computed hit reports the ray leaving: which side it hit is not decidable in this
    /// precision, so the spawned rays are not checked.
    tangent: usize,
    reflection: usize,
    shadow: usize,
    refraction_rehit: usize,
    /// A refraction ray that left a closed sphere without meeting its far side.
    refraction_escape: usize,
    /// How far each reflection ray's origin was moved, over the object's size.
    offsets: Vec<f64>,
}

impl SelfHits {
    fn failures(&self) -> usize {
        self.reflection + self.shadow + self.refraction_rehit + self.refraction_escape
    }
}

/// The offset this tracer used before: a few hundred ulps of the largest coordinate (at
/// least 1) along the normal. Kept here to compare against.
fn scaled_epsilon<T: tracer::Float>(p: &Vec3<T>, n: &Vec3<T>, _dir: &Vec3<T>) -> Vec3<T> {
    let scale = p.abs().max_element().max(T::ONE);
    (p + n.scale(scale * T::EPSILON * T::from_f64(512.0))).eval()
}

/// A ray-origin offset: hit point, a geometric normal, the new ray's direction.
type Offset<T> = fn(&Vec3<T>, &Vec3<T>, &Vec3<T>) -> Vec3<T>;

/// Random points on random spheres, triangles and cylinders of scale $10^{-3}$ to $10^5$
/// at up to $10^5$ from the origin (`max_ratio`: at most this many times the scale, to
/// stay within what the precision can represent); from each, reflection, refraction
/// (ior 1.5) and shadow rays spawned as the shader spawns them.
fn spawn_rays<T: tracer::Float>(
    kind: Kind,
    configs: usize,
    per: usize,
    max_ratio: f64,
    offset: Offset<T>,
    seed: u64,
) -> SelfHits {
    let mut rng = Rng(seed);
    let mut out = SelfHits::default();
    for _ in 0..configs {
        let s = rng.log(1e-3, 1e5);
        let mag = if rng.f() < 0.2 {
            rng.range(0.0, 1.0)
        } else {
            rng.log(1.0, 1e5)
        };
        let c = scale(rng.unit(), mag.min(max_ratio * s));
        let axis = rng.unit();
        let (e1, e2) = basis(axis);
        let mut tri = [[0.0; 3]; 3];
        let b = GeometryBuilder::<T>::new();
        let g = match kind {
            Kind::Sphere => b.add_sphere(v(c), T::from_f64(s), 0),
            Kind::Triangle => {
                loop {
                    tri = [0, 1, 2].map(|_| add(c, scale(rng.in_ball(), s)));
                    let n = cross(sub(tri[1], tri[0]), sub(tri[2], tri[0]));
                    if norm(n) > 0.2 * s * s {
                        break;
                    }
                }
                b.add_triangle(v(tri[0]), v(tri[1]), v(tri[2]), 0)
            }
            Kind::Cylinder => b.add_cone(
                v(sub(c, scale(axis, s))),
                T::from_f64(s),
                v(add(c, scale(axis, s))),
                T::from_f64(s),
                0,
            ),
        }
        .build(&AccelOptions::default());
        for _ in 0..per {
            out.points += 1;
            let (q, n) = match kind {
                Kind::Sphere => {
                    let u = rng.unit();
                    (add(c, scale(u, s)), u)
                }
                Kind::Triangle => {
                    let (b1, b2) = loop {
                        let (b1, b2) = (rng.range(0.05, 0.9), rng.range(0.05, 0.9));
                        if b1 + b2 <= 0.95 {
                            break (b1, b2);
                        }
                    };
                    let q = add(
                        scale(tri[0], 1.0 - b1 - b2),
                        add(scale(tri[1], b1), scale(tri[2], b2)),
                    );
                    let n = unit(cross(sub(tri[1], tri[0]), sub(tri[2], tri[0])));
                    (q, if rng.f() < 0.5 { n } else { scale(n, -1.0) })
                }
                Kind::Cylinder => {
                    let phi = rng.range(0.0, std::f64::consts::TAU);
                    let e = add(scale(e1, phi.cos()), scale(e2, phi.sin()));
                    let h = rng.range(-0.8, 0.8) * s;
                    (add(c, add(scale(axis, h), scale(e, s))), e)
                }
            };
            // Incoming from the side n faces.
            let mut din = rng.unit();
            if dot(din, n) > 0.0 {
                din = scale(din, -1.0);
            }
            let ray = Ray::new(v::<T>(sub(q, scale(din, 3.0 * s))), v::<T>(din));
            let Some(hit) = g.intersect(&ray) else {
                out.skipped += 1;
                continue;
            };
            let d = ray.dir;
            if kind != Kind::Triangle && hit.geometric_normal.dot(&d) >= T::ZERO {
                out.tangent += 1;
                continue;
            }
            let p = hit.point;
            let ng = if hit.geometric_normal.dot(&d) < T::ZERO {
                hit.geometric_normal
            } else {
                (-&hit.geometric_normal).eval()
            };
            // As the shader spawns them: the normal facing the incoming ray for the old
            // offset, the side of the new direction for `offset_ray`.
            let r_dir = d.reflect(&ng).normalize();
            let reflected = Ray::new(offset(&p, &ng, &r_dir), r_dir);
            out.offsets.push(norm(sub(w(&reflected.origin), w(&p))) / s);
            if let Some(h2) = g.intersect(&reflected) {
                out.reflection += 1;
                if std::env::var_os("ROBUSTNESS_DEBUG").is_some() {
                    println!("{kind:?} axis {axis:?} refl {:?} s {s:e} c {c:?} q {q:?} n {n:?} din {din:?} hit {hit:?} rehit {h2:?}", reflected.dir);
                }
            }
            // Shadow ray toward a light in the hemisphere of the normal.
            let mut l = rng.unit();
            if dot(l, w(&ng)) < 0.0 {
                l = scale(l, -1.0);
            }
            let light = v::<T>(add(w(&p), scale(l, 10.0 * s)));
            let to_light = (&light - &p).eval();
            let dist = to_light.length();
            let ldir = to_light.scale(dist.recip()).eval();
            if ng.dot(&ldir) > T::ZERO {
                let shadow = Ray {
                    t_max: dist,
                    ..Ray::new(offset(&p, &ng, &ldir), ldir)
                };
                out.shadow += g.occluded(&shadow) as usize;
            }
            // Refraction into the object.
            if let Some(t_dir) = d.refract(&ng, T::from_f64(1.0 / 1.5)) {
                let t_dir = t_dir.normalize();
                let below = offset(&p, &(-&ng).eval(), &t_dir);
                let inner = g.intersect(&Ray::new(below, t_dir));
                // The far side of a sphere or cylinder is at least 2 s cos(41.8°) away.
                let near = |h: &tracer::Hit<T>| h.t < T::from_f64(0.5 * s);
                match (kind, inner) {
                    (Kind::Triangle, Some(_)) => out.refraction_rehit += 1,
                    (Kind::Sphere, None) => out.refraction_escape += 1,
                    (_, Some(h)) if near(&h) => out.refraction_rehit += 1,
                    _ => {}
                }
            }
        }
    }
    out
}

/// 10^5 points in f32 (within what f32 represents: positions up to 10^3 times the scale)
/// and 3·10^4 in f64 (all positions): no spawned ray re-hits its own surface. Also
/// printed, not asserted: f32 at every position, and the old scaled-epsilon offset.
#[test]
fn spawned_rays_never_rehit_their_surface() {
    let kinds = [Kind::Sphere, Kind::Triangle, Kind::Cylinder];
    let run = |name: &str, f: &dyn Fn(Kind, u64) -> SelfHits, assert_clean: bool| {
        for (i, &k) in kinds.iter().enumerate() {
            let mut r = f(k, 1000 + i as u64);
            r.offsets.sort_by(f64::total_cmp);
            let (median, max) = (
                r.offsets[r.offsets.len() / 2],
                r.offsets[r.offsets.len() - 1],
            );
            println!(
                "self-intersection {name} {k:?}: {} points ({} primary misses, {} tangent): {} \
                 reflection, {} shadow, {} refraction re-hits, {} refraction escapes; offset / \
                 size median {median:.1e}, max {max:.1e}",
                r.points,
                r.skipped,
                r.tangent,
                r.reflection,
                r.shadow,
                r.refraction_rehit,
                r.refraction_escape
            );
            if assert_clean {
                assert_eq!(r.failures(), 0, "{name} {k:?}: {r:?}");
                assert!(r.skipped * 20 < r.points, "{name} {k:?}: {r:?}");
            }
        }
    };
    run(
        "f32 ratio<=1e3 offset_ray",
        &|k, seed| spawn_rays::<f32>(k, 334, 100, 1e3, offset_ray, seed),
        true,
    );
    run(
        "f64 all offset_ray",
        &|k, seed| spawn_rays::<f64>(k, 100, 100, f64::INFINITY, offset_ray, seed),
        true,
    );
    run(
        "f32 all offset_ray",
        &|k, seed| spawn_rays::<f32>(k, 100, 100, f64::INFINITY, offset_ray, seed),
        false,
    );
    run(
        "f32 ratio<=1e3 scaled-epsilon",
        &|k, seed| spawn_rays::<f32>(k, 100, 100, 1e3, scaled_epsilon, seed),
        false,
    );
}

/// A lit convex object alone in the scene (sphere, icosphere mesh, the outside of a
/// cylinder) at several scales and positions: no pixel whose surface faces the light is
/// left in shadow by the shader.
#[test]
fn lone_convex_objects_have_no_self_shadowed_pixel() {
    type T = f32;
    for (s, c) in [
        (1e-3, [0.0; 3]),
        (1.0, [1e3, -5e2, 2e2]),
        (1e3, [6e4, -8e4, 1e4]),
        (50.0, [0.25, 0.5, -0.125]),
    ] {
        for kind in 0..3 {
            let mut b = SceneBuilder::default();
            let m = b.add_material(material(0.8, 0.0, 0.0, 1.0, [1.0, 1.0, 1.0]));
            match kind {
                0 => {
                    b.add_sphere(c, s, m);
                }
                1 => {
                    let (pos, tris) = icosphere(c, s, 2);
                    b.add_mesh(&pos, &tris, None, m);
                }
                _ => {
                    b.add_cone(add(c, [0.0, -s, 0.0]), s, add(c, [0.0, s, 0.0]), s, m);
                }
            }
            let light = add(c, scale(unit([0.3, 1.0, 0.5]), 10.0 * s));
            b.add_light(light, Some([1.0, 1.0, 1.0]));
            let eye = add(c, scale(unit([0.2, 0.4, 1.0]), 4.0 * s));
            b.look_at(eye, c, [0.0, 1.0, 0.0], 40.0);
            let scene: Scene<T> = b.build();
            let cam = scene.camera_for(48, 48);
            let limits = TraceLimits {
                max_depth: 1,
                threshold: 0.0,
                spd: false,
                arith: tracer::arith::Arith::EXACT,
            };
            let (mut lit, mut shadowed) = (0, 0);
            for y in 0..48 {
                for x in 0..48 {
                    let ray = Ray::new(cam.position, cam.direction(x as T + 0.5, y as T + 0.5));
                    let Some(h) = scene.intersect(&ray) else {
                        continue;
                    };
                    // Outside surfaces only (the inside of a tube may shadow itself).
                    if h.geometric_normal.dot(&ray.dir) >= 0.0 {
                        continue;
                    }
                    let l = (v::<T>(light) - &h.point).normalize();
                    if h.geometric_normal.dot(&l) <= 1e-3 {
                        continue;
                    }
                    lit += 1;
                    let col = trace(&scene, &ray, 1, 1.0, &limits, &mut RayCounts::default());
                    // Ambient alone is 0.2: a shadowed lit pixel.
                    if col[0] <= 0.2 + 1e-6 {
                        shadowed += 1;
                    }
                }
            }
            assert!(lit > 50, "scale {s}, kind {kind}: {lit}");
            assert_eq!(
                shadowed, 0,
                "scale {s} at {c:?}, kind {kind}: of {lit} lit pixels"
            );
        }
    }
}

// ----- refraction -------------------------------------------------------------------------

fn limits<T: tracer::Float>(max_depth: u32) -> TraceLimits<T> {
    TraceLimits {
        max_depth,
        threshold: T::ZERO,
        spd: false,
        arith: tracer::arith::Arith::EXACT,
    }
}

/// Nested glass of index 1 (a sphere inside a sphere, and a triangle slab) is invisible:
/// every pixel is the background, in both precisions, grazing rays included.
fn index_one_is_invisible<T: tracer::Float>() {
    let mut b = SceneBuilder::default();
    let glass = b.add_material(material(0.0, 0.0, 1.0, 1.0, [1.0, 1.0, 1.0]));
    b.add_sphere([0.0; 3], 1.0, glass);
    b.add_sphere([0.2, 0.1, 0.0], 0.5, glass);
    b.add_polygon(
        vec![
            [-2.0, -2.0, -1.5],
            [2.0, -2.0, -1.5],
            [2.0, 2.0, -1.5],
            [-2.0, 2.0, -1.5],
        ],
        glass,
    );
    b.add_polygon(
        vec![
            [-2.0, -2.0, -1.7],
            [-2.0, 2.0, -1.7],
            [2.0, 2.0, -1.7],
            [2.0, -2.0, -1.7],
        ],
        glass,
    );
    b.background([0.1, 0.2, 0.3]);
    b.look_at([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 30.0);
    let scene: Scene<T> = b.build();
    let img = render(
        &scene,
        &Settings {
            width: Some(48),
            height: Some(48),
            depth: 12,
            ..Settings::default()
        },
    );
    for p in &img.pixels {
        for (c, bg) in p.iter().zip([0.1f32, 0.2, 0.3]) {
            assert!((c - bg).abs() <= 1e-6, "{p:?}");
        }
    }
}

#[test]
fn glass_of_index_one_passes_straight_through() {
    index_one_is_invisible::<f32>();
    index_one_is_invisible::<f64>();
}

/// A glass sphere of index 1.5 with `Ks = 0`, `Kt = 1`: a ray entering at any incidence,
/// grazing included, refracts in and out again (no total internal reflection on the way
/// out, since the inner angle is below the critical one); a ray inside beyond the critical
/// angle is totally reflected and its weight goes to the reflection ray.
fn enter_leave_and_tir<T: tracer::Float>() {
    let mut b = SceneBuilder::default();
    let glass = b.add_material(material(0.0, 0.0, 1.0, 1.5, [1.0, 1.0, 1.0]));
    b.add_sphere([0.0; 3], 1.0, glass);
    b.background([1.0, 1.0, 1.0]);
    let scene: Scene<T> = b.build();
    for rho in [0.0, 0.3, 0.9, 0.999, 0.999_999] {
        let ray = Ray::new(v::<T>([rho, 0.0, 5.0]), v::<T>([0.0, 0.0, -1.0]));
        let mut counts = RayCounts::default();
        let c = trace(&scene, &ray, 1, T::ONE, &limits(3), &mut counts);
        assert_eq!((counts.refraction, counts.reflection), (2, 0), "rho {rho}");
        assert!(
            c.iter().all(|x| (x.to_f64() - 1.0).abs() < 1e-6),
            "rho {rho}: {c:?}"
        );
    }
    // From inside, hitting the wall at 72° from the normal (critical angle 41.8°).
    let ray = Ray::new(v::<T>([0.95, 0.0, 0.0]), v::<T>([0.0, 1.0, 0.0]));
    let mut counts = RayCounts::default();
    let c = trace(&scene, &ray, 1, T::ONE, &limits(2), &mut counts);
    assert_eq!((counts.refraction, counts.reflection), (0, 1));
    assert!(c.iter().all(|x| x.is_finite() && x.to_f64() <= 1.0));
    // At normal incidence from inside it leaves.
    let ray = Ray::new(v::<T>([0.0, 0.0, 0.0]), v::<T>([0.0, 1.0, 0.0]));
    let mut counts = RayCounts::default();
    let c = trace(&scene, &ray, 1, T::ONE, &limits(2), &mut counts);
    assert_eq!((counts.refraction, counts.reflection), (1, 0));
    assert!(c.iter().all(|x| (x.to_f64() - 1.0).abs() < 1e-6));
}

#[test]
fn refraction_enters_leaves_and_reflects_totally() {
    enter_leave_and_tir::<f32>();
    enter_leave_and_tir::<f64>();
}

/// Random scenes of nested and overlapping spheres and slabs with physically valid
/// materials ($K_d + K_s + T \le 1$, colours in [0, 1]), a white background and no lights:
/// no pixel exceeds 1 (energy is never created), none is NaN, at depth 12.
#[test]
fn energy_is_never_created() {
    let mut rng = Rng(99);
    let mut max = 0.0f32;
    for _ in 0..12 {
        let mut b = SceneBuilder::default();
        for _ in 0..6 {
            let (kd, ks, t) = (rng.f(), rng.f(), rng.f());
            let sum = (kd + ks + t).max(1.0) * rng.range(1.0, 1.2);
            let color = [rng.f(), rng.f(), rng.f()];
            let m = b.add_material(material(
                kd / sum,
                ks / sum,
                t / sum,
                rng.range(1.0, 2.5),
                color,
            ));
            let c = [
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ];
            b.add_sphere(c, rng.range(0.2, 1.0), m);
            b.add_sphere(c, rng.range(0.05, 0.2), m);
        }
        let m = b.add_material(material(0.2, 0.5, 0.3, 1.3, [1.0, 1.0, 1.0]));
        b.add_polygon(
            vec![
                [-3.0, -2.0, -3.0],
                [-3.0, -2.0, 3.0],
                [3.0, -2.0, 3.0],
                [3.0, -2.0, -3.0],
            ],
            m,
        );
        b.add_polygon(
            vec![
                [-3.0, -1.8, -3.0],
                [3.0, -1.8, -3.0],
                [3.0, -1.8, 3.0],
                [-3.0, -1.8, 3.0],
            ],
            m,
        );
        b.background([1.0, 1.0, 1.0]);
        b.look_at([0.0, 1.0, 6.0], [0.0; 3], [0.0, 1.0, 0.0], 45.0);
        let settings = Settings {
            width: Some(24),
            height: Some(24),
            depth: 12,
            ..Settings::default()
        };
        for img in [
            render(&b.build::<f32>(), &settings),
            render(&b.build::<f64>(), &settings),
        ] {
            for p in &img.pixels {
                for &c in p {
                    assert!((0.0..=1.0 + 1e-5).contains(&c), "{p:?}");
                    max = max.max(c);
                }
            }
        }
    }
    println!("energy: brightest pixel channel {max} (background 1)");
}

/// NFF allows $K_s + T > 1$; such materials are scaled to sum to 1 when the scene is built,
/// so nested glass of that kind, totally reflecting inside, still creates no light.
#[test]
fn overbright_materials_are_scaled_to_conserve_energy() {
    let desc = material(0.0, 0.8, 0.8, 1.5, [1.0, 1.0, 1.0]);
    let m = tracer::Material::<f64>::from_desc(&desc);
    assert!(
        (m.ks + m.kt - 1.0).abs() < 1e-12 && (m.ks - m.kt).abs() < 1e-12,
        "{m:?}"
    );
    let mut b = SceneBuilder::default();
    let glass = b.add_material(desc);
    b.add_sphere([0.0, 0.0, 0.0], 1.0, glass);
    b.add_sphere([0.2, 0.1, 0.0], 0.5, glass);
    b.background([1.0, 1.0, 1.0]);
    b.look_at([0.0, 0.0, 4.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0);
    let settings = Settings {
        width: Some(32),
        height: Some(32),
        depth: 16,
        ..Settings::default()
    };
    for img in [
        render(&b.build::<f32>(), &settings),
        render(&b.build::<f64>(), &settings),
    ] {
        for p in &img.pixels {
            for &c in p {
                assert!((0.0..=1.0 + 1e-5).contains(&c), "{p:?}");
            }
        }
    }
}

// ----- degenerate input -------------------------------------------------------------------

const DEGENERATE_NFF: &str = "\
b 0.1 0.2 0.3
v
from 0 0 6
at 0 0 0
up 0 1 0
angle 40
hither 1
resolution 32 32
l 3 4 5
f 0.9 0.5 0.3 0.6 0.3 20 0.3 1.4
s 0 0 0 1
p 3
0.5 0.5 0.5
0.5 0.5 0.5
0.5 0.5 0.5
p 3
0 0 0
1 1 1
2 2 2
p 4
-1 -1 1
0 0 1
1 1 1
2 2 1
pp 3
-2 -1 0 0 0 0
2 -1 0 0 0 0
0 2 0 0 0 0
pp 4
-2 -2 -1 0 0 1
2 -2 -1 0 0 0
2 2 -1 0 0 -1
-2 2 -1 0 0 0
c 1 1 1 0 1 2 1 0.5
c 0 0 -2 0 0 0 -1 0.25
";

/// Zero-area triangles, collinear polygons, zero and cancelling normals in `pp`, a cone
/// tip: the scene loads, the degenerate pieces are dropped, and both precisions render
/// without a NaN pixel.
#[test]
fn degenerate_scene_renders_without_nan() {
    let desc = tracer::scene::parse_nff(DEGENERATE_NFF, "degenerate.nff").expect("parses");
    for img in [
        render(
            &Scene::<f32>::from_desc(&desc, &AccelOptions::default()),
            &Settings::default(),
        ),
        render(
            &Scene::<f64>::from_desc(&desc, &AccelOptions::default()),
            &Settings::default(),
        ),
    ] {
        assert!(img
            .pixels
            .iter()
            .flatten()
            .all(|c| c.is_finite() && *c >= 0.0));
    }
    let s = Scene::<f32>::from_desc(&desc, &AccelOptions::default());
    assert!(s.geometry.stats().skipped >= 3, "{:?}", s.geometry.stats());
    // Zero radius through the API: skipped, no hit.
    let g = GeometryBuilder::<f32>::new()
        .add_sphere(vec3(0.0, 0.0, 0.0), 0.0, 0)
        .add_cone(vec3(0.0, 0.0, 0.0), 0.0, vec3(0.0, 0.0, 1.0), 0.0, 0)
        .build(&AccelOptions::default());
    assert_eq!(g.stats().skipped, 2);
    assert!(g
        .intersect(&Ray::new(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, -1.0)))
        .is_none());
}

/// A scene with every primitive type, including an infinite plane.
fn all_kinds<T: tracer::Float>() -> Scene<T> {
    let mut b = SceneBuilder::default();
    b.add_material(material(0.5, 0.3, 0.2, 1.5, [1.0, 0.8, 0.6]));
    b.add_light([3.0, 4.0, 5.0], None);
    b.background([0.1, 0.2, 0.3]);
    b.look_at([0.0, 0.0, 6.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0);
    let mut s: Scene<T> = b.build();
    s.geometry = Geometry::builder()
        .add_sphere(vec3(T::ZERO, T::ZERO, T::ZERO), T::ONE, 0)
        .add_triangle(
            v([-2.0, -1.0, 0.0]),
            v([2.0, -1.0, 0.0]),
            v([0.0, 2.0, 0.0]),
            0,
        )
        .add_cone(
            v([2.0, 0.0, 0.0]),
            T::from_f64(0.5),
            v([2.0, 2.0, 0.0]),
            T::from_f64(0.1),
            0,
        )
        .add_plane(v([0.0, -1.5, 0.0]), v([0.0, 1.0, 0.0]), 0)
        .build(&AccelOptions::default());
    s
}

/// Rays with NaN or infinite components, zero directions and broken intervals hit
/// nothing, are never occluded, and shade to the background; rays parallel to a plane or
/// lying in a triangle's plane give no NaN.
fn invalid_rays<T: tracer::Float>() {
    let scene = all_kinds::<T>();
    let bad = [T::NAN, T::INFINITY, T::NEG_INFINITY];
    let mut rng = Rng(3);
    for k in 0..3000 {
        let mut o = v::<T>(scale(rng.in_ball(), 5.0));
        let mut d = v::<T>(rng.unit());
        let (mut t_min, mut t_max) = (T::ZERO, T::INFINITY);
        let x = bad[k % 3];
        match (k / 3) % 5 {
            0 => o[k % 3] = x,
            1 => d[(k / 5) % 3] = x,
            2 => d = vec3(T::ZERO, T::ZERO, T::ZERO),
            3 => t_min = T::NAN,
            _ => t_max = T::NAN,
        }
        let ray = Ray {
            origin: o,
            dir: d,
            t_min,
            t_max,
        };
        assert!(scene.intersect(&ray).is_none(), "{ray:?}");
        assert!(!scene.occluded(&ray));
        let c = trace(
            &scene,
            &ray,
            1,
            T::ONE,
            &limits(5),
            &mut RayCounts::default(),
        );
        assert_eq!(c, scene.background);
    }
    // Parallel to the plane y = -1.5 (on it and above it), and in the triangle's plane.
    for o in [
        [-5.0, -1.5, 0.3],
        [-5.0, -1.2, 0.3],
        [-5.0, 0.0, 0.0],
        [-1.0, -0.5, 0.0],
    ] {
        let ray = Ray::new(v::<T>(o), v::<T>([1.0, 0.0, 0.0]));
        let mut counts = RayCounts::default();
        let c = trace(&scene, &ray, 1, T::ONE, &limits(5), &mut counts);
        assert!(c.iter().all(|x| x.is_finite()), "{o:?}: {c:?}");
        if let Some(h) = scene.intersect(&ray) {
            assert!(h.t.is_finite() && h.point.iter().all(|x| x.is_finite()));
        }
    }
}

#[test]
fn invalid_and_parallel_rays_are_harmless() {
    invalid_rays::<f32>();
    invalid_rays::<f64>();
}

/// ROBUSTNESS.md's claim about the cost of invalid rays, asserted: rejected before
/// traversal, they cost less than valid rays (the example `invalid_rays` measures the
/// table; Embree's criterion is at most 2.5 times). Eye rays of teapot-s1 and the same
/// rays made invalid in five ways, timed in 9 interleaved rounds; medians. The measured
/// ratio is 0.02 to 0.08, so a ratio of 1 leaves a wide margin for a loaded machine.
#[test]
fn invalid_rays_cost_less_than_valid_ones() {
    use std::hint::black_box;
    use std::time::Instant;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot-s1.nff");
    let scene = Scene::<f32>::from_desc(
        &tracer::scene::load(&path).unwrap(),
        &AccelOptions::default(),
    );
    let cam = scene.camera_for(256, 256);
    let mut rng = Rng(17);
    let valid: Vec<Ray<f32>> = (0..20_000)
        .map(|_| {
            let (x, y) = (rng.range(0.0, 256.0), rng.range(0.0, 256.0));
            Ray::new(cam.position, cam.direction(x as f32, y as f32))
        })
        .collect();
    let invalid: Vec<Ray<f32>> = valid
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let mut r = *r;
            match i % 5 {
                0 => r.origin[i % 3] = f32::NAN,
                1 => r.origin[i % 3] = f32::INFINITY,
                2 => r.dir[i % 3] = f32::NEG_INFINITY,
                3 => r.dir = vec3(0.0, 0.0, 0.0),
                _ => r.t_max = f32::NAN,
            }
            r
        })
        .collect();
    assert!(invalid.iter().all(|r| scene.intersect(r).is_none()));
    let time = |rays: &[Ray<f32>], any: bool| {
        let t = Instant::now();
        let mut k = 0usize;
        for r in rays {
            k += usize::from(if any {
                scene.geometry.occluded(black_box(r))
            } else {
                scene.intersect(black_box(r)).is_some()
            });
        }
        black_box(k);
        t.elapsed().as_secs_f64()
    };
    let mut m: [Vec<f64>; 4] = Default::default();
    for round in 0..9 {
        for k in 0..4 {
            let k = if round % 2 == 0 { k } else { 3 - k };
            m[k].push(time(if k % 2 == 0 { &valid } else { &invalid }, k >= 2));
        }
    }
    let [a, b, c, d] = m.map(|mut v| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    });
    println!(
        "invalid/valid: intersect {:.3}, occluded {:.3}",
        b / a,
        d / c
    );
    assert!(b < a, "intersect: invalid {b} s, valid {a} s");
    assert!(d < c, "occluded: invalid {d} s, valid {c} s");
}

// ----- f32 against f64 --------------------------------------------------------------------

/// Per pixel, the primitive hit by the eye ray through its centre (`u32::MAX`: none).
fn prim_ids(scene: &Scene<f64>, size: u32) -> Vec<u32> {
    let cam = scene.camera_for(size, size);
    let mut ids = Vec::with_capacity((size * size) as usize);
    for y in 0..size {
        for x in 0..size {
            let r = Ray::new(cam.position, cam.direction(x as f64 + 0.5, y as f64 + 0.5));
            ids.push(scene.intersect(&r).map_or(u32::MAX, |h| h.prim_id));
        }
    }
    ids
}

/// Channels differing by more than 1/255 (after clamping to [0, 1]) at pixel `i`.
fn differs(a: &Image, b: &Image, i: usize) -> bool {
    (0..3).any(|k| {
        (a.pixels[i][k].clamp(0.0, 1.0) - b.pixels[i][k].clamp(0.0, 1.0)).abs() > 1.0 / 255.0
    })
}

/// Every SPD scene at size 1 (the copies in `tracer/scenes`) rendered in f32 and f64: the
/// fraction of pixels differing by more than 1/255 in a channel, outside silhouettes
/// (pixels whose 3x3 neighbourhood sees more than one primitive in f64) and in all.
#[test]
fn f32_and_f64_agree_on_the_spd_scenes() {
    let size: u32 = std::env::var("ROBUSTNESS_SIZE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(64);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with("-s1.nff"))
        .collect();
    names.sort();
    assert!(names.len() >= 7);
    let settings = Settings {
        width: Some(size),
        height: Some(size),
        ..Settings::default()
    };
    let mut worst = 0.0f64;
    for path in names {
        let desc = tracer::scene::load(&path).unwrap();
        let s32 = Scene::<f32>::from_desc(&desc, &AccelOptions::default());
        let s64 = Scene::<f64>::from_desc(&desc, &AccelOptions::default());
        let (a, b) = (render(&s32, &settings), render(&s64, &settings));
        let ids = prim_ids(&s64, size);
        let n = size as i64;
        let (mut interior, mut diff_interior, mut diff_all) = (0usize, 0usize, 0usize);
        for y in 0..n {
            for x in 0..n {
                let i = (y * n + x) as usize;
                let mut edge = false;
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let (xx, yy) = ((x + dx).clamp(0, n - 1), (y + dy).clamp(0, n - 1));
                        edge |= ids[(yy * n + xx) as usize] != ids[i];
                    }
                }
                let d = differs(&a, &b, i);
                diff_all += d as usize;
                if !edge {
                    interior += 1;
                    diff_interior += d as usize;
                }
            }
        }
        let total = (n * n) as usize;
        let frac = diff_interior as f64 / interior.max(1) as f64;
        worst = worst.max(frac);
        // ROBUSTNESS.md's figures, at 64 x 64 (CI) and 512 x 512 alike: at most 0.03% of
        // the non-silhouette pixels, except teapot-s1 (interpenetrating coarse patches)
        // at most 0.8%.
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let bound = if name == "teapot-s1.nff" {
            0.008
        } else {
            0.0003
        };
        assert!(
            frac <= bound,
            "{name}: {frac} of the non-silhouette pixels differ"
        );
        println!(
            "f32 vs f64 {} at {size}x{size}: {diff_interior} of {interior} non-silhouette \
             pixels differ by > 1/255 ({:.3}%); {diff_all} of {total} in all ({:.3}%)",
            path.file_name().unwrap().to_string_lossy(),
            100.0 * frac,
            100.0 * diff_all as f64 / total as f64
        );
    }
    assert!(worst <= 0.008, "worst non-silhouette fraction {worst}");
}

/// Shadow rays from the eye-ray hits of every SPD size-1 scene (front faces, lights the
/// surface faces) are never blocked by their own primitive; printed: how many are blocked
/// by another one.
#[test]
fn spd_shadow_rays_never_hit_their_own_primitive() {
    type T = f32;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with("-s1.nff"))
        .collect();
    names.sort();
    for path in names {
        let desc = tracer::scene::load(&path).unwrap();
        let scene = Scene::<T>::from_desc(&desc, &AccelOptions::default());
        let cam = scene.camera_for(128, 128);
        let (mut lit, mut own, mut other) = (0usize, 0usize, 0usize);
        for y in 0..128 {
            for x in 0..128 {
                let r = Ray::new(cam.position, cam.direction(x as T + 0.5, y as T + 0.5));
                let Some(h) = scene.intersect(&r) else {
                    continue;
                };
                let ng = h.geometric_normal;
                if ng.dot(&r.dir) >= 0.0 {
                    continue;
                }
                for l in &scene.lights {
                    let to_light = (&l.position - &h.point).eval();
                    let dist = to_light.length();
                    let ldir = to_light.scale(dist.recip()).eval();
                    if ng.dot(&ldir) <= 0.0 {
                        continue;
                    }
                    lit += 1;
                    let shadow = Ray {
                        t_max: dist,
                        ..Ray::new(offset_ray(&h.point, &ng, &ldir), ldir)
                    };
                    if let Some(b) = scene.intersect(&shadow) {
                        if b.prim_id == h.prim_id {
                            own += 1;
                        } else {
                            other += 1;
                        }
                    }
                }
            }
        }
        println!(
            "shadow rays {} at 128x128: {lit} toward lights, {other} blocked by another \
             primitive, {own} by their own",
            path.file_name().unwrap().to_string_lossy()
        );
        assert_eq!(own, 0, "{}", path.display());
    }
}

/// The golden images of `tests/render.rs` against an f64 render at the same size: pixels
/// with a channel more than 2/255 off. `ROBUSTNESS_GOLDEN_DIR` compares another directory
/// of PNGs instead (for instance an earlier revision's goldens), without asserting.
#[test]
fn golden_images_are_close_to_f64() {
    let own = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let other = std::env::var_os("ROBUSTNESS_GOLDEN_DIR").map(std::path::PathBuf::from);
    let dir = other.clone().unwrap_or(own);
    let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for name in [
        "balls-s1",
        "gears-s1",
        "mount-s1",
        "rings-s1",
        "teapot-s1",
        "tetra-s1",
        "tree-s1",
        "showcase",
    ] {
        let Ok(golden) = Image::read_png(&dir.join(format!("{name}.png"))) else {
            continue;
        };
        let desc = tracer::scene::load(&scenes.join(format!("{name}.nff"))).unwrap();
        let s64 = Scene::<f64>::from_desc(&desc, &AccelOptions::default());
        let settings = Settings {
            width: Some(golden.width),
            height: Some(golden.height),
            ..Settings::default()
        };
        let (a, b) = (golden.to_rgb8(), render(&s64, &settings).to_rgb8());
        let far = a
            .chunks(3)
            .zip(b.chunks(3))
            .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 2))
            .count();
        let total = a.len() / 3;
        println!(
            "golden {name} ({}): {far} of {total} pixels more than 2/255 from f64",
            dir.display()
        );
        if other.is_none() {
            assert!(far * 50 <= total, "{name}: {far} of {total}");
        }
    }
}
