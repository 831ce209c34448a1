//! The BVH against brute force on random scenes, `occluded` against `intersect`, and the
//! determinism of the parallel build. (Single `f32` rays walk the eight-wide tree where
//! the CPU has AVX2, the four-wide one elsewhere and with `eight_wide: false`: both are
//! checked, and so are the eight-wide walk's AVX-512VL and AVX2 compilations where the
//! CPU has AVX-512, with `avx512: false` for the second.)

use tracer::geometry::{kinds, AccelOptions, Geometry, TriangleTest, NO_HINT};
use tracer::scene::desc::{Shape, ShapeDesc, P3};
use tracer::Ray;
use vecexpr::{vec3, Real};

/// PCG32 (O'Neill 2014), fixed seed per test.
struct Pcg(u64);

impl Pcg {
    fn next_u32(&mut self) -> u32 {
        let old = self.0;
        self.0 = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let x = (((old >> 18) ^ old) >> 27) as u32;
        x.rotate_right((old >> 59) as u32)
    }
    /// Uniform in [0, 1).
    fn f(&mut self) -> f64 {
        f64::from(self.next_u32()) / 4_294_967_296.0
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f()
    }
    fn point(&mut self, lo: f64, hi: f64) -> P3 {
        [self.range(lo, hi), self.range(lo, hi), self.range(lo, hi)]
    }
    /// Uniform on the unit sphere.
    fn dir(&mut self) -> P3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let s = (1.0 - z * z).sqrt();
        [s * phi.cos(), s * phi.sin(), z]
    }
}

fn desc(shape: Shape, material: u32) -> ShapeDesc {
    ShapeDesc {
        shape,
        material,
        line: 0,
    }
}

/// A random mix: spheres, triangles, concave polygons, patches and cones, of varied size.
fn random_scene(rng: &mut Pcg, n: usize, kinds: &[u32]) -> Vec<ShapeDesc> {
    (0..n)
        .map(|i| {
            let c = rng.point(-10.0, 10.0);
            let size = 0.05 + 1.5 * rng.f() * rng.f();
            let near =
                |rng: &mut Pcg| -> P3 { core::array::from_fn(|k| c[k] + rng.range(-size, size)) };
            let m = i as u32 % 5;
            match kinds[i % kinds.len()] {
                0 => desc(
                    Shape::Sphere {
                        center: c,
                        radius: size,
                        inside_visible: rng.f() < 0.1,
                    },
                    m,
                ),
                1 => desc(
                    Shape::Polygon {
                        vertices: vec![near(rng), near(rng), near(rng)],
                    },
                    m,
                ),
                2 => {
                    // A planar concave "L" with a random frame.
                    let (u, w) = (rng.dir(), rng.dir());
                    let pts = [
                        (0.0, 0.0),
                        (2.0, 0.0),
                        (2.0, 1.0),
                        (1.0, 1.0),
                        (1.0, 2.0),
                        (0.0, 2.0),
                    ];
                    let vertices = pts
                        .iter()
                        .map(|(a, b)| core::array::from_fn(|k| c[k] + size * (a * u[k] + b * w[k])))
                        .collect();
                    desc(Shape::Polygon { vertices }, m)
                }
                3 => desc(
                    Shape::Patch {
                        vertices: vec![near(rng), near(rng), near(rng)],
                        normals: vec![rng.dir(), rng.dir(), rng.dir()],
                    },
                    m,
                ),
                _ => desc(
                    Shape::Cone {
                        base: c,
                        base_radius: size * rng.f(),
                        apex: near(rng),
                        apex_radius: size * rng.f(),
                        inside_visible: false,
                    },
                    m,
                ),
            }
        })
        .collect()
}

/// Rays: from outside toward random points, from inside the scene in random directions,
/// and some with a random finite `t_max`.
fn random_rays<T: Real>(rng: &mut Pcg, n: usize) -> Vec<Ray<T>> {
    let c = |x: f64| <T as Real>::from_f64(x);
    (0..n)
        .map(|i| {
            let (o, d) = if i % 2 == 0 {
                let o = rng.point(-15.0, 15.0);
                let target = rng.point(-10.0, 10.0);
                let d: P3 = core::array::from_fn(|k| target[k] - o[k]);
                (o, d)
            } else {
                (rng.point(-10.0, 10.0), rng.dir())
            };
            let mut r = Ray::new(
                vec3(c(o[0]), c(o[1]), c(o[2])),
                vec3(c(d[0]), c(d[1]), c(d[2])),
            );
            if i % 3 == 0 {
                r.t_max = c(rng.range(0.0, 20.0));
            }
            if i % 7 == 0 {
                r.t_min = c(rng.range(0.0, 1.0));
            }
            r
        })
        .collect()
}

/// Checks every BVH configuration against brute force (computed once per triangle
/// test) on every ray: the same `t` bit for bit, the same primitive and normals, and
/// `occluded` agreeing with `intersect`. Returns the number of hits.
fn compare<T: tracer::Float>(
    shapes: &[ShapeDesc],
    rays: &[Ray<T>],
    configs: &[AccelOptions],
) -> usize {
    let mut hits = 0;
    for test in [TriangleTest::Watertight, TriangleTest::MollerTrumbore] {
        let configs: Vec<_> = configs.iter().filter(|c| c.triangle == test).collect();
        if configs.is_empty() {
            continue;
        }
        let brute = Geometry::<T>::build(
            shapes,
            &AccelOptions {
                use_bvh: false,
                ..*configs[0]
            },
        );
        assert_eq!(brute.stats().bvh_nodes, 0);
        let expected: Vec<_> = rays.iter().map(|r| brute.intersect(r)).collect();
        for (r, e) in rays.iter().zip(&expected) {
            assert_eq!(brute.occluded(r), e.is_some(), "brute force occluded {r:?}");
        }
        hits = expected.iter().filter(|h| h.is_some()).count();
        for opts in configs {
            let bvh = Geometry::<T>::build(shapes, opts);
            assert!(bvh.stats().bvh_nodes > 1);
            for (i, (r, b)) in rays.iter().zip(&expected).enumerate() {
                let a = bvh.intersect(r);
                match (&a, b) {
                    (None, None) => {}
                    (Some(a), Some(b)) => {
                        assert_eq!(
                            a.t.to_bits(),
                            b.t.to_bits(),
                            "ray {i}: t {} vs {}",
                            a.t,
                            b.t
                        );
                        assert_eq!(a.prim_id, b.prim_id, "ray {i}");
                        assert_eq!(a.material, b.material, "ray {i}");
                        assert_eq!(a.point, b.point, "ray {i}");
                        assert_eq!(a.geometric_normal, b.geometric_normal, "ray {i}");
                        assert_eq!(a.shading_normal, b.shading_normal, "ray {i}");
                        assert!(a.t > r.t_min && a.t < r.t_max);
                        assert!(a.shading_normal.iter().all(|x| x.is_finite()));
                    }
                    _ => panic!("ray {i} {r:?} ({opts:?}): bvh {a:?} vs brute force {b:?}"),
                }
                assert_eq!(bvh.occluded(r), a.is_some(), "ray {i}: bvh occluded");
                // The queries compiled for the scene's kinds answer as the all-kinds ones.
                let all = bvh.intersect_kinds::<{ kinds::ALL }>(r);
                let key = |h: &Option<tracer::Hit<T>>| h.as_ref().map(|h| (h.t.to_bits(), h.prim_id));
                assert_eq!(key(&all), key(&a), "ray {i}: all kinds");
                assert_eq!(bvh.occluded_kinds::<{ kinds::ALL }>(r), a.is_some(), "ray {i}");
                let cast = bvh.cast(r).map(|c| bvh.hit(r, &c));
                assert_eq!(key(&cast), key(&a), "ray {i}: cast");
            }
        }
    }
    hits
}

fn opts(triangle: TriangleTest, max_leaf_size: usize) -> AccelOptions {
    AccelOptions {
        triangle,
        max_leaf_size,
        ..AccelOptions::default()
    }
}

macro_rules! bvh_tests {
    ($m:ident, $t:ty) => {
        mod $m {
            use super::*;
            type T = $t;

            #[test]
            fn random_spheres() {
                let mut rng = Pcg(1);
                let shapes = random_scene(&mut rng, 1500, &[0]);
                let rays = random_rays::<T>(&mut rng, 8_000);
                let four_wide = AccelOptions {
                    eight_wide: false,
                    ..opts(TriangleTest::Watertight, 8)
                };
                let avx2 = AccelOptions {
                    avx512: false,
                    ..opts(TriangleTest::Watertight, 8)
                };
                let hits = compare(
                    &shapes,
                    &rays,
                    &[opts(TriangleTest::Watertight, 8), four_wide, avx2],
                );
                assert!(hits > 2_000 && hits < 7_500, "{hits} hits");
            }

            #[test]
            fn random_triangles_both_tests() {
                let mut rng = Pcg(2);
                let shapes = random_scene(&mut rng, 1500, &[1]);
                let rays = random_rays::<T>(&mut rng, 8_000);
                let hits = compare(
                    &shapes,
                    &rays,
                    &[
                        opts(TriangleTest::Watertight, 4),
                        AccelOptions {
                            eight_wide: false,
                            ..opts(TriangleTest::Watertight, 4)
                        },
                        AccelOptions {
                            avx512: false,
                            ..opts(TriangleTest::Watertight, 4)
                        },
                        opts(TriangleTest::MollerTrumbore, 4),
                    ],
                );
                assert!(hits > 500, "{hits} hits");
            }

            #[test]
            fn shadow_cache_never_changes_occluded() {
                // The hint carried from ray to ray (as the shadow cache does), reset, or
                // garbage (references to nothing, other kinds, out-of-range indices).
                let mut rng = Pcg(9);
                let mut shapes = random_scene(&mut rng, 600, &[0, 1, 2, 3, 4]);
                shapes.push(desc(
                    Shape::Polygon {
                        vertices: vec![
                            [-40.0, -12.0, -40.0],
                            [40.0, -12.0, -40.0],
                            [40.0, -12.0, 40.0],
                        ],
                    },
                    0,
                ));
                let rays = random_rays::<T>(&mut rng, 4_000);
                for (wide, avx512) in [(true, true), (true, false), (false, true)] {
                    for use_bvh in [true, false] {
                        let o = AccelOptions {
                            wide,
                            avx512,
                            use_bvh,
                            ..opts(TriangleTest::Watertight, 4)
                        };
                        let g = Geometry::<T>::build(&shapes, &o);
                        let (mut carried, mut blocked) = (NO_HINT, 0);
                        for (i, r) in rays.iter().enumerate() {
                            let want = g.occluded(r);
                            blocked += usize::from(want);
                            let got = g.occluded_hint_kinds::<{ kinds::ALL }>(r, &mut carried);
                            assert_eq!(got, want, "ray {i}, carried hint");
                            let mut junk = match i % 4 {
                                0 => NO_HINT,
                                1 => rng.next_u32(),
                                2 => rng.next_u32() % 2048,
                                _ => (3 << 30) | (rng.next_u32() % 4),
                            };
                            let got = g.occluded_hint_kinds::<{ kinds::ALL }>(r, &mut junk);
                            assert_eq!(got, want, "ray {i}, hint {junk}");
                        }
                        assert!(blocked > 400, "{blocked} blocked");
                    }
                }
            }

            #[test]
            fn random_mixed_scene() {
                let mut rng = Pcg(3);
                let shapes = random_scene(&mut rng, 1500, &[0, 1, 2, 3, 4]);
                let rays = random_rays::<T>(&mut rng, 8_000);
                let configs = [1, 8, 32].map(|leaf| opts(TriangleTest::Watertight, leaf));
                let hits = compare(&shapes, &rays, &configs);
                assert!(hits > 1_500, "{hits} hits");
            }

            #[test]
            fn clustered_and_duplicated_primitives() {
                // Many identical spheres (ties, equal centroids) plus a far outlier.
                let mut shapes: Vec<ShapeDesc> = (0..200)
                    .map(|_| {
                        desc(
                            Shape::Sphere {
                                center: [0.0, 0.0, 0.0],
                                radius: 1.0,
                                inside_visible: false,
                            },
                            0,
                        )
                    })
                    .collect();
                shapes.push(desc(
                    Shape::Sphere {
                        center: [1e4, 0.0, 0.0],
                        radius: 1.0,
                        inside_visible: false,
                    },
                    1,
                ));
                let mut rng = Pcg(4);
                let rays = random_rays::<T>(&mut rng, 2_000);
                compare(&shapes, &rays, &[opts(TriangleTest::Watertight, 4)]);
                let g = Geometry::<T>::build(&shapes, &AccelOptions::default());
                let h = g
                    .intersect(&Ray::new(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, -1.0)))
                    .unwrap();
                assert_eq!(h.prim_id, 0);
                // The depth stays bounded with 200 coincident centroids.
                assert!(g.stats().bvh_depth <= 10, "depth {}", g.stats().bvh_depth);
            }

            #[test]
            fn stacked_triangles_tie_to_the_first_given() {
                // Copies of the same quads (ties in `t` within and across leaves and
                // groups of four), shuffled with distinct quads: every hit must be the
                // copy given first, on every tree and with shadow rays.
                let mut rng = Pcg(11);
                let mut shapes = Vec::new();
                for k in 0..40 {
                    let (x, y) = (f64::from(k % 8) * 1.5, f64::from(k / 8) * 1.5);
                    let copies = if k % 3 == 0 { 7 } else { 1 };
                    for c in 0..copies {
                        shapes.push(desc(
                            Shape::Polygon {
                                vertices: vec![
                                    [x, y, 0.0],
                                    [x + 1.0, y, 0.0],
                                    [x + 1.0, y + 1.0, 0.0],
                                    [x, y + 1.0, 0.0],
                                ],
                            },
                            c,
                        ));
                    }
                }
                let mut rays = random_rays::<T>(&mut rng, 3_000);
                for i in 0..400 {
                    let p = rng.point(-1.0, 12.0);
                    let f = <T as Real>::from_f64;
                    let z = if i % 2 == 0 { 1.0 } else { -1.0 };
                    rays.push(Ray::new(
                        vec3(f(p[0]), f(p[1]), f(4.0 * z)),
                        vec3(f(0.0), f(0.0), f(-z)),
                    ));
                }
                let configs = [1, 4, 8].map(|leaf| opts(TriangleTest::Watertight, leaf));
                let hits = compare(&shapes, &rays, &configs);
                assert!(hits > 150, "{hits} hits");
                let g = Geometry::<T>::build(&shapes, &AccelOptions::default());
                for r in &rays {
                    if let Some(h) = g.intersect(r) {
                        assert_eq!(h.material, 0, "{r:?}");
                    }
                }
            }

            #[test]
            fn axis_aligned_rays_on_box_faces() {
                // A grid of unit cubes made of quads; rays run exactly along the faces
                // (zero direction components, origins on box planes).
                let mut shapes = Vec::new();
                for i in 0..6 {
                    for j in 0..6 {
                        let (x, y) = (f64::from(i) * 2.0, f64::from(j) * 2.0);
                        shapes.push(desc(
                            Shape::Polygon {
                                vertices: vec![
                                    [x, y, 0.0],
                                    [x + 1.0, y, 0.0],
                                    [x + 1.0, y + 1.0, 0.0],
                                    [x, y + 1.0, 0.0],
                                ],
                            },
                            0,
                        ));
                    }
                }
                let bvh = Geometry::<T>::build(&shapes, &AccelOptions::default());
                let brute = Geometry::<T>::build(
                    &shapes,
                    &AccelOptions {
                        use_bvh: false,
                        ..AccelOptions::default()
                    },
                );
                for i in 0..=24 {
                    for j in 0..=24 {
                        let (x, y) = (
                            <T as Real>::from_f64(f64::from(i) * 0.5),
                            <T as Real>::from_f64(f64::from(j) * 0.5),
                        );
                        for d in [
                            vec3(0.0, 0.0, -1.0),
                            vec3(-0.0, 0.0, -1.0),
                            vec3(0.0, 1.0, -1.0),
                        ] {
                            let r = Ray::new(vec3(x, y, 1.0), d);
                            let (a, b) = (bvh.intersect(&r), brute.intersect(&r));
                            assert_eq!(
                                a.map(|h| (h.t, h.prim_id)),
                                b.map(|h| (h.t, h.prim_id)),
                                "{r:?}"
                            );
                        }
                    }
                }
            }
        }
    };
}

bvh_tests!(f32_tests, f32);
bvh_tests!(f64_tests, f64);

#[test]
fn parallel_build_is_deterministic() {
    let mut rng = Pcg(5);
    let shapes = random_scene(&mut rng, 30_000, &[0, 1, 0, 4]);
    let opts = AccelOptions::default();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let four = rayon::ThreadPoolBuilder::new()
        .num_threads(4)
        .build()
        .unwrap();
    let a = one.install(|| Geometry::<f32>::build(&shapes, &opts));
    let b = four.install(|| Geometry::<f32>::build(&shapes, &opts));
    let c = Geometry::<f32>::build(
        &shapes,
        &AccelOptions {
            parallel_build: false,
            ..opts
        },
    );
    assert_eq!(a.bvh(), b.bvh());
    assert_eq!(a.bvh(), c.bvh());
    let rays = random_rays::<f32>(&mut rng, 2_000);
    for r in &rays {
        let (x, y) = (a.intersect(r), b.intersect(r));
        assert_eq!(x.map(|h| (h.t, h.prim_id)), y.map(|h| (h.t, h.prim_id)));
    }
}

#[test]
fn f32_and_f64_agree_on_which_primitive() {
    // Well-separated spheres: both precisions must pick the same one, with close t.
    let shapes: Vec<ShapeDesc> = (0..400)
        .map(|i| {
            let (x, y, z) = (i % 8, (i / 8) % 8, i / 64);
            desc(
                Shape::Sphere {
                    center: [f64::from(x) * 3.0, f64::from(y) * 3.0, f64::from(z) * 3.0],
                    radius: 1.0,
                    inside_visible: false,
                },
                0,
            )
        })
        .collect();
    let g32 = Geometry::<f32>::build(&shapes, &AccelOptions::default());
    let g64 = Geometry::<f64>::build(&shapes, &AccelOptions::default());
    let mut rng = Pcg(6);
    let mut hits = 0;
    for _ in 0..5_000 {
        let o = rng.point(-5.0, 25.0);
        let t = rng.point(0.0, 21.0);
        let d: P3 = core::array::from_fn(|k| t[k] - o[k]);
        let r64 = Ray::new(vec3(o[0], o[1], o[2]), vec3(d[0], d[1], d[2]));
        let r32 = Ray::new(
            vec3(o[0] as f32, o[1] as f32, o[2] as f32),
            vec3(d[0] as f32, d[1] as f32, d[2] as f32),
        );
        match (g32.intersect(&r32), g64.intersect(&r64)) {
            (Some(a), Some(b)) => {
                hits += 1;
                // Grazing hits may differ; a clear hit must match.
                if (f64::from(a.t) - b.t).abs() < 1e-3 {
                    assert_eq!(a.prim_id, b.prim_id);
                }
            }
            (None, None) => {}
            (a, b) => {
                // Only a grazing ray may hit in one precision and miss in the other.
                let n: [f64; 3] = match (a, b) {
                    (Some(a), None) => core::array::from_fn(|k| f64::from(a.geometric_normal[k])),
                    (None, Some(b)) => core::array::from_fn(|k| b.geometric_normal[k]),
                    _ => unreachable!(),
                };
                let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let cos = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]).abs() / len;
                assert!(cos < 1e-2, "non-grazing disagreement, cos {cos}");
            }
        }
    }
    assert!(hits > 1_000);
}
