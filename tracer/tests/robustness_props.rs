//! Property tests of every intersection routine in `f32` against an `f64` reference
//! computed from the same (exactly widened) inputs with independent textbook formulas,
//! including rays that barely graze. Where the reference is far enough from a decision
//! boundary (by a margin derived from f32's rounding), the f32 kernel must agree: hit or
//! miss, the distance within a rounding bound, the point on the surface; `occluded`
//! always agrees with `intersect`.

use proptest::prelude::*;
use tracer::geometry::{AccelOptions, Geometry, GeometryBuilder, TriangleTest};
use tracer::Ray;
use vecexpr::{vec3, Expr, Vec3};

type P = [f64; 3];
const EPS: f64 = f32::EPSILON as f64;

fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add(a: P, b: P) -> P {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: P, s: f64) -> P {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn cross(a: P, b: P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: P) -> f64 {
    dot(a, a).sqrt()
}
fn unit(a: P) -> P {
    scale(a, 1.0 / norm(a))
}
/// Rounds to f32 and back: the value the kernel sees, exactly.
fn r32(a: P) -> P {
    a.map(|x| f64::from(x as f32))
}
fn v32(a: P) -> Vec3<f32> {
    vec3(a[0] as f32, a[1] as f32, a[2] as f32)
}
fn w(a: &Vec3<f32>) -> P {
    [f64::from(a[0]), f64::from(a[1]), f64::from(a[2])]
}

fn point() -> impl Strategy<Value = P> {
    [-1e3f64..1e3, -1e3f64..1e3, -1e3f64..1e3]
}
fn direction() -> impl Strategy<Value = P> {
    [-1f64..1.0, -1f64..1.0, -1f64..1.0].prop_filter("non-zero", |d| dot(*d, *d) > 1e-4)
}
/// Log-uniform positive.
fn log(a: f64, b: f64) -> impl Strategy<Value = f64> {
    (a.ln()..b.ln()).prop_map(f64::exp)
}
/// A unit vector perpendicular to the unit `a`.
fn perp(a: P, hint: P) -> P {
    let c = cross(a, hint);
    if norm(c) > 1e-3 {
        unit(c)
    } else {
        unit(cross(a, [a[1], a[2], -a[0]]))
    }
}

fn check_consistent(g: &Geometry<f32>, r: &Ray<f32>) -> Option<tracer::Hit<f32>> {
    let h = g.intersect(r);
    assert_eq!(
        h.is_some(),
        g.occluded(r),
        "occluded disagrees with intersect: {r:?}"
    );
    if let Some(h) = &h {
        assert!(h.t.is_finite() && h.t > r.t_min && h.t < r.t_max);
        assert!((h.geometric_normal.length() - 1.0).abs() < 1e-5);
    }
    h
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 2000,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Spheres: origin outside (at 1.01 to 10^3 radii) or inside, any direction, or one
    /// aimed to pass the centre at $(1 \pm \delta) r$ with $\delta$ down to $10^{-7}$.
    #[test]
    fn sphere_against_f64(c in point(), r in log(1e-2, 1e2), u in direction(), k in log(1e-3, 1e3),
                          dd in direction(), graze in any::<bool>(), delta in log(1e-7, 1e-1),
                          outside in any::<bool>()) {
        let (c, r) = (r32(c), f64::from(r as f32));
        let o = r32(add(c, scale(unit(u), r * if graze { 1.0 + k } else { k })));
        let d = if graze {
            // Aim past the centre at distance (1 ± delta) r.
            let to_c = unit(sub(c, o));
            let side = perp(to_c, dd);
            let rho = r * if outside { 1.0 + delta } else { 1.0 - delta };
            r32(unit(add(sub(c, o), scale(side, rho))))
        } else {
            r32(unit(dd))
        };
        let g = GeometryBuilder::<f32>::new().add_sphere(v32(c), r as f32, 0).build(&AccelOptions::default());
        let ray = Ray::new(v32(o), v32(d));
        let hit = check_consistent(&g, &ray);
        // Reference.
        let f = sub(o, c);
        let (a, b) = (dot(d, d), dot(f, d));
        let l = sub(f, scale(d, b / a));
        let rho = norm(l);
        let sc = norm(f) + r;
        let band = 64.0 * EPS * sc;
        let disc = r * r - rho * rho;
        let roots = (disc >= 0.0).then(|| {
            let s = (a * disc).sqrt();
            ((-b - s) / a, (-b + s) / a)
        });
        let t_ref = roots.and_then(|(t0, t1)| [t0, t1].into_iter().find(|&t| t > 0.0));
        if rho > r + band {
            prop_assert!(hit.is_none(), "line passes outside, hit {hit:?}");
        }
        let inside = norm(f) < r - band;
        if (rho < r - band && b < 0.0) || inside {
            let t = t_ref.expect("reference hits");
            let h = hit.expect("must hit");
            let cond = 1.0 + r / disc.max(r * band).sqrt();
            let tol = 64.0 * EPS * sc * cond;
            prop_assert!((f64::from(h.t) - t).abs() <= tol, "t {} vs {t}, tol {tol}", h.t);
        }
        if let Some(h) = hit {
            let err = (norm(sub(w(&h.point), c)) - r).abs();
            prop_assert!(err <= 8.0 * EPS * (norm(c) + r), "point {err} off the surface");
        }
    }

    /// Triangles, both tests: rays through a point of given barycentrics, from a random
    /// side, including rays at grazing angles (down to 10^-4 rad from the plane).
    #[test]
    fn triangle_against_f64(c in point(), a in direction(), b in direction(), e in direction(),
                            size in log(1e-2, 1e2), b1 in -0.2f64..1.2, b2 in -0.2f64..1.2,
                            dd in direction(), dist in log(1e-2, 1e3), graze in log(1e-4, 1.0),
                            graze_on in any::<bool>()) {
        let v = [r32(add(c, scale(a, size))), r32(add(c, scale(b, size))), r32(add(c, scale(e, size)))];
        let n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
        prop_assume!(norm(n) > 0.05 * size * size);
        let nh = unit(n);
        let target = add(scale(v[0], 1.0 - b1 - b2), add(scale(v[1], b1), scale(v[2], b2)));
        let mut d = unit(dd);
        if graze_on {
            // Tilt an in-plane direction by `graze` radians out of the plane.
            let inplane = perp(nh, d);
            d = unit(add(scale(inplane, graze.cos()), scale(nh, graze.sin() * dot(d, nh).signum())));
        }
        prop_assume!(dot(d, nh).abs() > 1e-5);
        let o = r32(sub(target, scale(d, dist * size)));
        let d = r32(d);
        let ray = Ray::new(v32(o), v32(d));
        // Reference: Möller–Trumbore in f64 on the f32 values.
        let e1 = sub(v[1], v[0]);
        let e2 = sub(v[2], v[0]);
        let p = cross(d, e2);
        let det = dot(e1, p);
        let s = sub(o, v[0]);
        let u = dot(s, p) / det;
        let q = cross(s, e1);
        let vv = dot(d, q) / det;
        let t = dot(e2, q) / det;
        let margin_b = (u.min(vv)).min(1.0 - u - vv);
        let cos = dot(unit(d), nh).abs();
        let sc = norm(sub(o, c)) + size + norm(c);
        // Barycentric error: position error over the triangle's size, amplified by 1/cos.
        let slack = 1e-4f64.max(512.0 * EPS * sc / (size * cos));
        let t_tol = 512.0 * EPS * sc / cos;
        for test in [TriangleTest::Watertight, TriangleTest::MollerTrumbore] {
            let g = GeometryBuilder::<f32>::new()
                .add_triangle(v32(v[0]), v32(v[1]), v32(v[2]), 0)
                .build(&AccelOptions { triangle: test, ..AccelOptions::default() });
            let hit = check_consistent(&g, &ray);
            if margin_b > slack && t > t_tol {
                let h = hit.expect("must hit");
                prop_assert!((f64::from(h.t) - t).abs() <= t_tol, "{test:?}: t {} vs {t}", h.t);
                prop_assert!(dot(w(&h.geometric_normal), nh).abs() > 1.0 - 1e-5);
            } else if margin_b < -slack || t < -t_tol {
                prop_assert!(hit.is_none(), "{test:?}: hit {hit:?}, margin {margin_b}, t {t}");
            }
        }
    }

    /// Cones and cylinders: the reference solves the textbook quadratic $B^2 - AC$ in f64.
    #[test]
    fn cone_against_f64(base in point(), axis in direction(), h in log(1e-1, 1e2),
                        r0 in log(1e-2, 1e1), r1f in 0.0f64..2.0, cyl in any::<bool>(),
                        u in direction(), k in log(1.5, 100.0), dd in direction(),
                        aim in any::<bool>(), s_aim in 0.0f64..1.0, phi in 0.0f64..std::f64::consts::TAU) {
        let ax = unit(axis);
        let base = r32(base);
        let apex = r32(add(base, scale(ax, h)));
        let r0 = f64::from(r0 as f32);
        let r1 = if cyl { r0 } else { f64::from((r0 * r1f) as f32) };
        let g = GeometryBuilder::<f32>::new()
            .add_cone(v32(base), r0 as f32, v32(apex), r1 as f32, 0)
            .build(&AccelOptions::default());
        prop_assume!(g.stats().cones == 1);
        let size = h + r0.max(r1);
        let o = r32(add(add(base, scale(ax, 0.5 * h)), scale(unit(u), size * k)));
        let d = if aim {
            // Toward a point on the lateral surface.
            let e1 = perp(ax, u);
            let e2 = cross(ax, e1);
            let rad = r0 + (r1 - r0) * s_aim;
            let target = add(add(base, scale(ax, s_aim * h)), add(scale(e1, rad * phi.cos()), scale(e2, rad * phi.sin())));
            r32(unit(sub(target, o)))
        } else {
            r32(unit(dd))
        };
        let ray = Ray::new(v32(o), v32(d));
        let hit = check_consistent(&g, &ray);
        // Reference, from the stored (f32) base, apex and radii.
        let hh = norm(sub(apex, base));
        let a_hat = scale(sub(apex, base), 1.0 / hh);
        let kk = (r1 - r0) / hh;
        let wv = sub(o, base);
        let ws = dot(wv, a_hat);
        let ds = dot(d, a_hat);
        let wp = sub(wv, scale(a_hat, ws));
        let dp = sub(d, scale(a_hat, ds));
        let rho = r0 + kk * ws;
        let qa = dot(dp, dp) - kk * kk * ds * ds;
        let qb = dot(wp, dp) - kk * rho * ds;
        let qc = dot(wp, wp) - rho * rho;
        let disc = qb * qb - qa * qc;
        let sc = norm(wv) + size + norm(base);
        let roots: Vec<f64> = if disc >= 0.0 && qa.abs() > 1e-12 {
            let s = disc.sqrt();
            vec![(-qb - s) / qa, (-qb + s) / qa]
        } else {
            vec![]
        };
        let valid: Vec<(f64, f64)> = roots
            .iter()
            .map(|&t| (t, (ws + t * ds) / hh))
            .filter(|&(t, s)| t > 0.0 && (0.0..=1.0).contains(&s))
            .collect();
        // Robust cases: a clean crossing away from the rims, grazing excluded.
        let clear = disc > 1e-3 * qb * qb + 1e-6 * size * size;
        let first = roots.iter().copied().filter(|&t| t > 0.0).fold(f64::INFINITY, f64::min);
        if clear {
            if let Some(&(t, s)) = valid.first() {
                let other_ok = roots.iter().all(|&t2| {
                    let s2 = (ws + t2 * ds) / hh;
                    t2 <= 0.0 || (s2 - 0.0).abs() > 1e-3 && (s2 - 1.0).abs() > 1e-3
                });
                if s > 1e-3 && s < 1.0 - 1e-3 && other_ok && t == first {
                    let hitv = hit.expect("must hit");
                    let tol = 1e-4 * sc / (qa.abs().sqrt().max(1e-3));
                    prop_assert!((f64::from(hitv.t) - t).abs() <= tol, "t {} vs {t}", hitv.t);
                }
            }
        }
        if disc < -1e-3 * (qb * qb).max(qa.abs() * qc.abs()) {
            prop_assert!(hit.is_none(), "line misses the infinite cone, hit {hit:?}");
        }
    }

    /// Infinite planes, including rays nearly parallel to them.
    #[test]
    fn plane_against_f64(p in point(), n in direction(), o in point(), dd in direction(),
                         graze in log(1e-5, 1.0), graze_on in any::<bool>()) {
        let nh = r32(unit(n));
        let p = r32(p);
        let mut d = unit(dd);
        if graze_on {
            let inplane = perp(unit(nh), d);
            d = unit(add(scale(inplane, graze.cos()), scale(unit(nh), -graze.sin())));
        }
        let d = r32(d);
        let o = r32(o);
        let g = GeometryBuilder::<f32>::new()
            .add_plane(v32(p), v32(nh), 0)
            .build(&AccelOptions::default());
        let ray = Ray::new(v32(o), v32(d));
        let hit = check_consistent(&g, &ray);
        let nn = unit(nh);
        let denom = dot(d, nn);
        let dist = dot(sub(p, o), nn);
        let sc = norm(p) + norm(o) + 1.0;
        let tol_dist = 64.0 * EPS * sc;
        if denom.abs() > 1e-6 {
            let t = dist / denom;
            if dist.abs() > tol_dist && t > 0.0 {
                let h = hit.expect("must hit");
                // Rounding of d·n is absolute, so t's error grows as 1/denom^2.
                let tol = 64.0 * EPS * (sc / denom.abs() + dist.abs() / (denom * denom));
                prop_assert!((f64::from(h.t) - t).abs() <= tol, "t {} vs {t}", h.t);
                // The point is projected onto the plane.
                let off = dot(sub(w(&h.point), p), nn).abs();
                let bound = 16.0 * EPS * (norm(w(&h.point)) + norm(p));
                prop_assert!(off <= bound, "point {off} off the plane");
            } else if dist.abs() > tol_dist {
                prop_assert!(hit.is_none());
            }
        }
    }
}
