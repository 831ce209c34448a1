//! Each primitive against analytic expectations, in `f32` and `f64`.

use tracer::geometry::{AccelOptions, Geometry, GeometryBuilder, TriangleTest};
use tracer::scene::desc::{Shape, ShapeDesc, P3};
use tracer::{Hit, Ray};
use vecexpr::{vec3, Expr, Real, Vec3};

fn shape(shape: Shape, material: u32) -> ShapeDesc {
    ShapeDesc {
        shape,
        material,
        line: 0,
    }
}

fn sphere(center: P3, radius: f64) -> ShapeDesc {
    shape(
        Shape::Sphere {
            center,
            radius,
            inside_visible: false,
        },
        0,
    )
}

fn polygon(vertices: Vec<P3>) -> ShapeDesc {
    shape(Shape::Polygon { vertices }, 0)
}

fn v<T: Real>(x: f64, y: f64, z: f64) -> Vec3<T> {
    vec3(
        <T as Real>::from_f64(x),
        <T as Real>::from_f64(y),
        <T as Real>::from_f64(z),
    )
}

fn ray<T: Real>(o: [f64; 3], d: [f64; 3]) -> Ray<T> {
    Ray::new(v(o[0], o[1], o[2]), v(d[0], d[1], d[2]))
}

fn close<T: Real>(a: T, b: f64, tol: f64) -> bool {
    (a.to_f64() - b).abs() <= tol * b.abs().max(1.0)
}

fn close_v<T: Real>(a: &Vec3<T>, b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|i| close(a[i], b[i], tol))
}

/// Checks the invariants every hit must satisfy.
fn sane<T: Real>(h: &Hit<T>, r: &Ray<T>) {
    assert!(
        h.t.is_finite() && h.t > r.t_min && h.t < r.t_max,
        "t = {}",
        h.t
    );
    for n in [&h.geometric_normal, &h.shading_normal] {
        assert!((n.length().to_f64() - 1.0).abs() < 1e-5, "normal {n:?}");
    }
    assert!(h.point.iter().all(|x| x.is_finite()));
    assert!(h.shading_normal.dot(&h.geometric_normal) >= T::ZERO);
}

/// A gear outline like SPD `gears`: `teeth` teeth, four vertices each, counter-clockwise
/// in the plane z = `z`.
fn gear(teeth: usize, inner: f64, outer: f64, z: f64) -> Vec<P3> {
    let mut v = Vec::new();
    let step = std::f64::consts::TAU / teeth as f64;
    for i in 0..teeth {
        let a = i as f64 * step;
        for (f, r) in [(0.0, inner), (0.25, outer), (0.5, outer), (0.75, inner)] {
            let phi = a + f * step;
            v.push([r * phi.cos(), r * phi.sin(), z]);
        }
    }
    v
}

macro_rules! precision_tests {
    ($m:ident, $t:ty, $tol:expr) => {
        mod $m {
            use super::*;
            type T = $t;
            const TOL: f64 = $tol;

            fn build(shapes: &[ShapeDesc]) -> Geometry<T> {
                Geometry::build(shapes, &AccelOptions::default())
            }

            fn both(shapes: &[ShapeDesc]) -> [Geometry<T>; 3] {
                [
                    build(shapes),
                    Geometry::build(
                        shapes,
                        &AccelOptions {
                            use_bvh: false,
                            ..AccelOptions::default()
                        },
                    ),
                    Geometry::build(
                        shapes,
                        &AccelOptions {
                            triangle: TriangleTest::MollerTrumbore,
                            ..AccelOptions::default()
                        },
                    ),
                ]
            }

            #[test]
            fn sphere_distance_and_normal() {
                for g in both(&[sphere([1.0, 2.0, 3.0], 2.0)]) {
                    let r = ray::<T>([1.0, 2.0, 13.0], [0.0, 0.0, -1.0]);
                    let h = g.intersect(&r).expect("hit");
                    sane(&h, &r);
                    assert!(close(h.t, 8.0, TOL));
                    assert!(close_v(&h.point, [1.0, 2.0, 5.0], TOL));
                    assert!(close_v(&h.geometric_normal, [0.0, 0.0, 1.0], TOL));
                    assert_eq!((h.prim_id, h.material), (0, 0));
                    // Oblique: the normal is (p - c) / r.
                    let r = ray::<T>([10.0, 2.0 + 1.2, 3.0], [-1.0, 0.0, 0.0]);
                    let h = g.intersect(&r).expect("oblique hit");
                    sane(&h, &r);
                    assert!(close(h.t, 10.0 - 2.6, TOL));
                    assert!(close_v(&h.geometric_normal, [0.8, 0.6, 0.0], TOL * 10.0));
                }
            }

            #[test]
            fn sphere_from_inside_and_inside_visible() {
                let mut inside = sphere([0.0; 3], 1.0);
                inside.shape = Shape::Sphere {
                    center: [0.0; 3],
                    radius: 1.0,
                    inside_visible: true,
                };
                for g in both(&[sphere([0.0, 0.0, 0.0], 2.0)]) {
                    let r = ray::<T>([0.0, 0.0, 0.5], [0.0, 0.0, 1.0]);
                    let h = g.intersect(&r).expect("inside hit");
                    assert!(close(h.t, 1.5, TOL));
                    // Outward normal even from inside: the renderer flips it.
                    assert!(close_v(&h.geometric_normal, [0.0, 0.0, 1.0], TOL));
                }
                for g in both(&[inside]) {
                    let r = ray::<T>([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
                    let h = g.intersect(&r).expect("hit");
                    assert!(close(h.t, 1.0, TOL));
                    assert!(close_v(&h.geometric_normal, [-1.0, 0.0, 0.0], TOL));
                    assert!(close_v(&h.shading_normal, [-1.0, 0.0, 0.0], TOL));
                }
            }

            #[test]
            fn sphere_tangent_and_grazing_rays() {
                for g in both(&[sphere([0.0, 0.0, 0.0], 1.0)]) {
                    // Exactly tangent: either outcome, but never NaN.
                    let r = ray::<T>([-5.0, 1.0, 0.0], [1.0, 0.0, 0.0]);
                    if let Some(h) = g.intersect(&r) {
                        sane(&h, &r);
                        assert!(close(h.t, 5.0, 1e-2));
                    }
                    let miss = ray::<T>([-5.0, 1.0 + 1e-3, 0.0], [1.0, 0.0, 0.0]);
                    assert!(g.intersect(&miss).is_none());
                    assert!(!g.occluded(&miss));
                    let hit = ray::<T>([-5.0, 1.0 - 1e-3, 0.0], [1.0, 0.0, 0.0]);
                    let h = g.intersect(&hit).expect("grazing hit");
                    sane(&h, &hit);
                    assert!(g.occluded(&hit));
                }
            }

            #[test]
            fn interval_is_open() {
                let g = build(&[sphere([0.0, 0.0, 0.0], 1.0)]);
                let mut r = ray::<T>([0.0, 0.0, 5.0], [0.0, 0.0, -1.0]);
                r.t_max = 4.0;
                assert!(g.intersect(&r).is_none());
                assert!(!g.occluded(&r));
                r.t_max = 4.5;
                assert!(g.occluded(&r));
                // t_min past the front: the back at t = 6.
                r.t_max = T::INFINITY;
                r.t_min = 4.0;
                assert!(close(g.intersect(&r).unwrap().t, 6.0, TOL));
            }

            #[test]
            fn cylinder_hits_and_normals() {
                let cyl = shape(
                    Shape::Cone {
                        base: [0.0, 0.0, 0.0],
                        base_radius: 1.0,
                        apex: [0.0, 4.0, 0.0],
                        apex_radius: 1.0,
                        inside_visible: false,
                    },
                    3,
                );
                for g in both(std::slice::from_ref(&cyl)) {
                    let r = ray::<T>([0.0, 1.0, 10.0], [0.0, 0.0, -1.0]);
                    let h = g.intersect(&r).expect("hit");
                    sane(&h, &r);
                    assert!(close(h.t, 9.0, TOL));
                    assert!(close_v(&h.geometric_normal, [0.0, 0.0, 1.0], TOL));
                    assert_eq!(h.material, 3);
                    // Oblique in x-z: entry at (0.6, 2, 0.8).
                    let r = ray::<T>([0.6, 2.0, 10.0], [0.0, 0.0, -1.0]);
                    let h = g.intersect(&r).expect("hit");
                    assert!(close(h.t, 9.2, TOL));
                    assert!(close_v(&h.geometric_normal, [0.6, 0.0, 0.8], TOL * 10.0));
                    // Beyond the ends: no caps, no hit; looking down the axis: no hit.
                    assert!(g
                        .intersect(&ray::<T>([0.0, 4.5, 10.0], [0.0, 0.0, -1.0]))
                        .is_none());
                    assert!(g
                        .intersect(&ray::<T>([0.0, -1.0, 0.0], [0.0, 1.0, 0.0]))
                        .is_none());
                    // Through the open end, slanting onto the inside of the wall.
                    let r = ray::<T>([0.0, 6.0, 0.0], [0.25, -1.0, 0.0]);
                    let h = g.intersect(&r).expect("inner wall");
                    assert!(close_v(&h.point, [1.0, 2.0, 0.0], TOL * 10.0));
                    assert!(close_v(&h.geometric_normal, [1.0, 0.0, 0.0], TOL * 10.0));
                }
                let mut inv = cyl;
                inv.shape = Shape::Cone {
                    base: [0.0, 0.0, 0.0],
                    base_radius: 1.0,
                    apex: [0.0, 4.0, 0.0],
                    apex_radius: 1.0,
                    inside_visible: true,
                };
                let h = build(&[inv])
                    .intersect(&ray::<T>([0.0, 1.0, 10.0], [0.0, 0.0, -1.0]))
                    .unwrap();
                assert!(close_v(&h.geometric_normal, [0.0, 0.0, -1.0], TOL));
            }

            #[test]
            fn cone_hits_and_normals() {
                // Radius 2 at y = 0 to radius 1 at y = 2: slope -1/2.
                let cone = shape(
                    Shape::Cone {
                        base: [0.0, 0.0, 0.0],
                        base_radius: 2.0,
                        apex: [0.0, 2.0, 0.0],
                        apex_radius: 1.0,
                        inside_visible: false,
                    },
                    0,
                );
                for g in both(std::slice::from_ref(&cone)) {
                    let r = ray::<T>([10.0, 1.0, 0.0], [-1.0, 0.0, 0.0]);
                    let h = g.intersect(&r).expect("hit");
                    sane(&h, &r);
                    // Radius 1.5 at y = 1.
                    assert!(close(h.t, 8.5, TOL));
                    // Normal ∝ (1, 1/2, 0).
                    let s = 1.0 / 1.25f64.sqrt();
                    assert!(close_v(&h.geometric_normal, [s, 0.5 * s, 0.0], TOL * 10.0));
                    // Just above the top at radius 1: miss; straight down inside: miss.
                    assert!(g
                        .intersect(&ray::<T>([10.0, 2.1, 0.0], [-1.0, 0.0, 0.0]))
                        .is_none());
                    assert!(g
                        .intersect(&ray::<T>([0.0, 5.0, 0.0], [0.0, -1.0, 0.0]))
                        .is_none());
                }
                // A pointed cone (apex radius 0): the tip region never yields NaN.
                let tip = shape(
                    Shape::Cone {
                        base: [0.0, 0.0, 0.0],
                        base_radius: 1.0,
                        apex: [0.0, 1.0, 0.0],
                        apex_radius: 0.0,
                        inside_visible: false,
                    },
                    0,
                );
                let g = build(&[tip]);
                for k in 0..50 {
                    let y = 0.95 + k as f64 * 0.002;
                    let r = ray::<T>([5.0, y, 0.0], [-1.0, 0.0, 0.0]);
                    if let Some(h) = g.intersect(&r) {
                        sane(&h, &r);
                    }
                }
            }

            #[test]
            fn triangle_barycentrics_via_vertex_normals() {
                // pp triangle in z = 0 with distinct vertex normals.
                let n = [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]];
                let patch = shape(
                    Shape::Patch {
                        vertices: vec![[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]],
                        normals: n.to_vec(),
                    },
                    0,
                );
                for g in both(&[patch]) {
                    // Point (1, 2, 0): barycentrics (1/4, 1/4, 1/2).
                    let r = ray::<T>([1.0, 2.0, 3.0], [0.0, 0.0, -1.0]);
                    let h = g.intersect(&r).expect("hit");
                    sane(&h, &r);
                    assert!(close(h.t, 3.0, TOL));
                    assert!(close_v(&h.point, [1.0, 2.0, 0.0], TOL));
                    assert!(close_v(&h.geometric_normal, [0.0, 0.0, 1.0], TOL));
                    let unit = |a: [f64; 3]| {
                        let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
                        a.map(|x| x / l)
                    };
                    let (n0, n1, n2) = (unit(n[0]), unit(n[1]), unit(n[2]));
                    let s = unit(core::array::from_fn(|i| {
                        0.25 * n0[i] + 0.25 * n1[i] + 0.5 * n2[i]
                    }));
                    assert!(
                        close_v(&h.shading_normal, s, TOL * 10.0),
                        "{:?}",
                        h.shading_normal
                    );
                    // From below: same normals, they are not flipped toward the ray.
                    let h = g
                        .intersect(&ray::<T>([1.0, 2.0, -3.0], [0.0, 0.0, 1.0]))
                        .expect("back");
                    assert!(close_v(&h.geometric_normal, [0.0, 0.0, 1.0], TOL));
                }
            }

            #[test]
            fn patch_normals_degenerate_or_flipped() {
                let verts = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
                let zero = shape(
                    Shape::Patch {
                        vertices: verts.clone(),
                        normals: vec![[0.0; 3]; 3],
                    },
                    0,
                );
                let nan = shape(
                    Shape::Patch {
                        vertices: verts.clone(),
                        normals: vec![[f64::NAN; 3]; 3],
                    },
                    0,
                );
                let cancel = shape(
                    Shape::Patch {
                        vertices: verts.clone(),
                        normals: vec![[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
                    },
                    0,
                );
                let down = shape(
                    Shape::Patch {
                        vertices: verts,
                        normals: vec![[0.0, 0.0, -1.0]; 3],
                    },
                    0,
                );
                let r = ray::<T>([0.25, 0.25, 1.0], [0.0, 0.0, -1.0]);
                for s in [zero, nan, down] {
                    let h = build(&[s]).intersect(&r).expect("hit");
                    sane(&h, &r);
                    assert!(close_v(&h.shading_normal, [0.0, 0.0, 1.0], TOL));
                }
                // Interpolation (0.5, 0, 0) + ... lands in the plane: still unit and in
                // the geometric hemisphere.
                let h =
                    build(&[cancel]).intersect(&ray::<T>([0.5, 0.0 + 0.25, 1.0], [0.0, 0.0, -1.0]));
                sane(&h.expect("hit"), &r);
            }

            #[test]
            fn concave_gear_polygon() {
                let outline = gear(36, 0.8, 1.0, 0.0);
                assert_eq!(outline.len(), 144);
                let shapes = [sphere([0.0, 0.0, -100.0], 0.5), polygon(outline)];
                let step = std::f64::consts::TAU / 36.0;
                for g in both(&shapes) {
                    assert_eq!(g.stats().polygons, 1);
                    assert_eq!(g.stats().triangles, 142);
                    for i in 0..36 {
                        let a = i as f64 * step;
                        let at = |phi: f64, r: f64| {
                            ray::<T>([r * phi.cos(), r * phi.sin(), 1.0], [0.0, 0.0, -1.0])
                        };
                        // Through a tooth: hit, reporting the polygon's index.
                        let h = g.intersect(&at(a + 0.375 * step, 0.9)).expect("tooth");
                        assert_eq!(h.prim_id, 1);
                        assert!(close(h.t, 1.0, TOL));
                        assert!(close_v(&h.geometric_normal, [0.0, 0.0, 1.0], TOL));
                        // Through the notch between teeth: miss.
                        assert!(
                            g.intersect(&at(a + 0.875 * step, 0.9)).is_none(),
                            "notch {i}"
                        );
                        assert!(!g.occluded(&at(a + 0.875 * step, 0.9)));
                        // Through the body: hit.
                        assert!(g.intersect(&at(a + 0.6 * step, 0.5)).is_some());
                        assert!(g.intersect(&at(a, 0.05)).is_some());
                        // Outside: miss.
                        assert!(g.intersect(&at(a, 1.05)).is_none());
                    }
                }
            }

            #[test]
            fn polygon_winding_sets_normal() {
                let cw = polygon(vec![
                    [0.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [1.0, 0.0, 0.0],
                ]);
                let h = build(&[cw])
                    .intersect(&ray::<T>([0.5, 0.5, 1.0], [0.0, 0.0, -1.0]))
                    .unwrap();
                assert!(close_v(&h.geometric_normal, [0.0, 0.0, -1.0], TOL));
                assert!(close_v(&h.shading_normal, [0.0, 0.0, -1.0], TOL));
            }

            #[test]
            fn degenerate_input_is_skipped() {
                let shapes = [
                    sphere([0.0, 0.0, 0.0], 0.0),
                    sphere([f64::NAN, 0.0, 0.0], 1.0),
                    sphere([0.0, 0.0, 0.0], f64::INFINITY),
                    polygon(vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]),
                    polygon(vec![[0.0; 3], [1.0, 0.0, 0.0]]),
                    polygon(vec![[1.0; 3]; 5]),
                    shape(
                        Shape::Cone {
                            base: [0.0; 3],
                            base_radius: 1.0,
                            apex: [0.0; 3],
                            apex_radius: 1.0,
                            inside_visible: false,
                        },
                        0,
                    ),
                    shape(
                        Shape::Patch {
                            vertices: vec![[0.0; 3]; 3],
                            normals: vec![[0.0, 0.0, 1.0]; 3],
                        },
                        0,
                    ),
                    sphere([5.0, 0.0, 0.0], 1.0),
                ];
                for g in both(&shapes) {
                    assert_eq!(g.stats().skipped, 8);
                    assert_eq!(g.stats().spheres, 1);
                    assert_eq!(g.stats().triangles + g.stats().cones, 0);
                    let h = g
                        .intersect(&ray::<T>([5.0, 0.0, 5.0], [0.0, 0.0, -1.0]))
                        .unwrap();
                    assert_eq!(h.prim_id, 8);
                    for d in [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]] {
                        assert!(g.intersect(&ray::<T>([0.0, 0.0, 0.0], d)).is_none());
                    }
                }
            }

            #[test]
            fn invalid_rays_hit_nothing() {
                let g = build(&[
                    sphere([0.0, 0.0, 0.0], 1.0),
                    polygon(vec![
                        [-5.0, -5.0, -2.0],
                        [5.0, -5.0, -2.0],
                        [0.0, 5.0, -2.0],
                    ]),
                ]);
                let nan = T::NAN;
                let inf = T::INFINITY;
                let o = v::<T>(0.0, 0.0, 5.0);
                let d = v::<T>(0.0, 0.0, -1.0);
                let bad = [
                    Ray::new(vec3(nan, 0.0, 5.0), d),
                    Ray::new(o, vec3(0.0, nan, -1.0)),
                    Ray::new(vec3(inf, 0.0, 5.0), d),
                    Ray::new(o, vec3(0.0, 0.0, -inf)),
                    Ray::new(o, vec3(0.0, 0.0, 0.0)),
                    Ray {
                        t_min: nan,
                        ..Ray::new(o, d)
                    },
                    Ray {
                        t_max: nan,
                        ..Ray::new(o, d)
                    },
                    Ray {
                        t_min: 3.0,
                        t_max: 2.0,
                        ..Ray::new(o, d)
                    },
                ];
                for r in &bad {
                    assert!(g.intersect(r).is_none(), "{r:?}");
                    assert!(!g.occluded(r), "{r:?}");
                }
                assert!(g.intersect(&Ray::new(o, d)).is_some());
            }

            #[test]
            fn ties_go_to_the_first_primitive() {
                // Three identical spheres and two coincident quads.
                let quad = || {
                    polygon(vec![
                        [-1.0, -1.0, -3.0],
                        [1.0, -1.0, -3.0],
                        [1.0, 1.0, -3.0],
                        [-1.0, 1.0, -3.0],
                    ])
                };
                let shapes = [
                    quad(),
                    sphere([0.0, 0.0, 0.0], 1.0),
                    sphere([0.0, 0.0, 0.0], 1.0),
                    quad(),
                    sphere([0.0, 0.0, 0.0], 1.0),
                ];
                for g in both(&shapes) {
                    let h = g
                        .intersect(&ray::<T>([0.1, 0.2, 5.0], [0.0, 0.0, -1.0]))
                        .unwrap();
                    assert_eq!(h.prim_id, 1);
                    let h = g
                        .intersect(&ray::<T>([0.9, 0.9, 5.0], [0.0, 0.0, -1.0]))
                        .unwrap();
                    assert_eq!(h.prim_id, 0);
                }
            }

            #[test]
            fn builder_api() {
                let positions = [
                    v::<T>(0.0, 0.0, 0.0),
                    v(1.0, 0.0, 0.0),
                    v(1.0, 1.0, 0.0),
                    v(0.0, 1.0, 0.0),
                ];
                let g = GeometryBuilder::<T>::new()
                    .add_sphere(v(0.0, 0.0, 10.0), 1.0, 7)
                    .add_mesh(&positions, &[[0, 1, 2], [0, 2, 3], [0, 9, 1]], None, 2)
                    .add_plane(v(0.0, 0.0, -5.0), v(0.0, 0.0, 3.0), 4)
                    .add_cone(v(5.0, 0.0, 0.0), 1.0, v(5.0, 0.0, 2.0), 0.5, 1)
                    .add_polygon(
                        &[v(-3.0, 0.0, 1.0), v(-2.0, 0.0, 1.0), v(-2.0, 1.0, 1.0)],
                        5,
                    )
                    .build(&AccelOptions::default());
                let s = g.stats();
                assert_eq!(
                    (s.spheres, s.triangles, s.planes, s.cones, s.skipped),
                    (1, 3, 1, 1, 1)
                );
                let h = g
                    .intersect(&ray::<T>([0.0, 0.0, 20.0], [0.0, 0.0, -1.0]))
                    .unwrap();
                assert_eq!((h.prim_id, h.material), (0, 7));
                let h = g
                    .intersect(&ray::<T>([0.75, 0.25, 5.0], [0.0, 0.0, -1.0]))
                    .unwrap();
                assert_eq!((h.prim_id, h.material), (1, 2));
                let h = g
                    .intersect(&ray::<T>([0.25, 0.75, 5.0], [0.0, 0.0, -1.0]))
                    .unwrap();
                assert_eq!(h.prim_id, 2);
                // Outside everything but the plane: the plane.
                let h = g
                    .intersect(&ray::<T>([50.0, 50.0, 5.0], [0.0, 0.0, -1.0]))
                    .unwrap();
                assert_eq!((h.prim_id, h.material), (4, 4));
                assert!(close(h.t, 10.0, TOL));
                assert!(close_v(&h.geometric_normal, [0.0, 0.0, 1.0], TOL));
                // Parallel to the plane above it: nothing.
                assert!(g
                    .intersect(&ray::<T>([50.0, 50.0, 5.0], [1.0, 0.0, 0.0]))
                    .is_none());
                let h = g
                    .intersect(&ray::<T>([5.0, 10.0, 1.0], [0.0, -1.0, 0.0]))
                    .unwrap();
                assert_eq!(h.prim_id, 5);
                let h = g
                    .intersect(&ray::<T>([-2.25, 0.5, 5.0], [0.0, 0.0, -1.0]))
                    .unwrap();
                assert_eq!(h.prim_id, 6);
                // Bounds cover the bounded primitives only.
                let b = g.bounds();
                assert!(b.contains(&v(0.0, 0.0, 10.9)) && b.contains(&v(5.9, 0.0, 0.0)));
                assert!(!b.contains(&v(0.0, 0.0, -5.0)));
            }

            #[test]
            fn stats_are_consistent() {
                let shapes: Vec<ShapeDesc> = (0..500)
                    .map(|i| sphere([i as f64, (i % 7) as f64, (i % 13) as f64], 0.4))
                    .collect();
                let g = build(&shapes);
                let s = g.stats();
                let bvh = g.bvh().unwrap();
                assert_eq!(s.spheres, 500);
                assert_eq!(s.bvh_nodes, bvh.nodes().len());
                assert_eq!(s.bvh_bytes, 32 * s.bvh_nodes + 4 * 500);
                assert_eq!(s.bvh_depth, bvh.depth());
                assert!(s.bvh_depth >= 7 && s.bvh_depth < 40);
                assert!(s.prim_bytes >= 500 * core::mem::size_of::<tracer::geometry::Sphere<T>>());
                assert!(s.build_ms >= 0.0);
                assert!(s.bytes_per_primitive() > 16.0 && s.bytes_per_primitive() < 200.0);
                let none = Geometry::<T>::build(&[], &AccelOptions::default());
                assert!(none
                    .intersect(&ray::<T>([0.0; 3], [0.0, 0.0, 1.0]))
                    .is_none());
                assert!(none.bounds().is_empty());
            }
        }
    };
}

precision_tests!(f32_tests, f32, 1e-5);
precision_tests!(f64_tests, f64, 1e-12);
