//! Watertightness: rays starting inside a closed triangle mesh never escape with the
//! watertight test, even when aimed exactly at shared vertices and edges (Woop et al.
//! 2013, section 5).

use tracer::geometry::{AccelOptions, Geometry, GeometryBuilder, TriangleTest};
use tracer::scene::desc::{Shape, ShapeDesc, P3};
use tracer::Ray;
use vecexpr::{vec3, Expr, Real, Vec3};

/// A closed UV sphere: `rings` latitude bands, `segments` longitudes, shared vertices,
/// outward (counter-clockwise) winding.
fn uv_sphere(center: P3, radius: f64, rings: usize, segments: usize) -> (Vec<P3>, Vec<[u32; 3]>) {
    let mut pos = vec![[center[0], center[1], center[2] + radius]];
    for i in 1..rings {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let phi = std::f64::consts::TAU * j as f64 / segments as f64;
            pos.push([
                center[0] + radius * theta.sin() * phi.cos(),
                center[1] + radius * theta.sin() * phi.sin(),
                center[2] + radius * theta.cos(),
            ]);
        }
    }
    pos.push([center[0], center[1], center[2] - radius]);
    let south = (pos.len() - 1) as u32;
    let at = |i: usize, j: usize| (1 + (i - 1) * segments + j % segments) as u32;
    let mut tris = Vec::new();
    for j in 0..segments {
        tris.push([0, at(1, j), at(1, j + 1)]);
        tris.push([south, at(rings - 1, j + 1), at(rings - 1, j)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            tris.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    (pos, tris)
}

/// Fixed-seed xorshift64*.
struct Rng(u64);

impl Rng {
    fn f(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn to_t<T: Real>(p: &P3) -> Vec3<T> {
    vec3(
        <T as Real>::from_f64(p[0]),
        <T as Real>::from_f64(p[1]),
        <T as Real>::from_f64(p[2]),
    )
}

/// Shoots rays from points inside toward every vertex, every edge midpoint and random
/// directions; returns how many escaped.
fn escapes<T: tracer::Float>(
    g: &Geometry<T>,
    pos: &[P3],
    tris: &[[u32; 3]],
    center: P3,
    radius: f64,
    rng: &mut Rng,
) -> usize {
    let mut targets: Vec<P3> = pos.to_vec();
    for t in tris {
        for k in 0..3 {
            let (a, b) = (pos[t[k] as usize], pos[t[(k + 1) % 3] as usize]);
            targets.push(core::array::from_fn(|i| 0.5 * (a[i] + b[i])));
        }
    }
    for _ in 0..5_000 {
        let d: P3 = core::array::from_fn(|_| rng.f() - 0.5);
        targets.push(core::array::from_fn(|i| center[i] + d[i]));
    }
    let mut escaped = 0;
    for (n, target) in targets.iter().enumerate() {
        // The centre (rays through vertices exactly), then random inner points.
        let origin: P3 = if n % 2 == 0 {
            center
        } else {
            core::array::from_fn(|i| center[i] + 0.3 * radius * (rng.f() - 0.5))
        };
        let o = to_t::<T>(&origin);
        let d = to_t::<T>(&core::array::from_fn(|i| target[i] - origin[i]));
        if d.iter().all(|&x| x == T::ZERO) {
            continue;
        }
        let r = Ray::new(o, d);
        let hit = g.intersect(&r);
        if hit.is_none() {
            escaped += 1;
        }
        assert_eq!(g.occluded(&r), hit.is_some());
    }
    escaped
}

macro_rules! watertight_tests {
    ($m:ident, $t:ty) => {
        mod $m {
            use super::*;
            type T = $t;

            #[test]
            fn closed_sphere_mesh_never_leaks() {
                let (center, radius) = ([100.25, -50.5, 30.125], 7.0);
                let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
                // Brute force on a coarser mesh to keep the test fast.
                for (use_bvh, rings, segments) in [(true, 48, 96), (false, 12, 24)] {
                    let (pos, tris) = uv_sphere(center, radius, rings, segments);
                    let p: Vec<Vec3<T>> = pos.iter().map(to_t).collect();
                    let opts = AccelOptions {
                        use_bvh,
                        ..AccelOptions::default()
                    };
                    let g = GeometryBuilder::<T>::new()
                        .add_mesh(&p, &tris, None, 0)
                        .build(&opts);
                    assert_eq!(g.stats().triangles, tris.len());
                    assert_eq!(
                        escapes(&g, &pos, &tris, center, radius, &mut rng),
                        0,
                        "bvh {use_bvh}"
                    );
                    // Möller–Trumbore may leak through shared edges and vertices (it
                    // typically does here); `escapes` still checks that `occluded`
                    // agrees with `intersect` for it.
                    let mt = AccelOptions {
                        triangle: TriangleTest::MollerTrumbore,
                        ..opts
                    };
                    let g = GeometryBuilder::<T>::new()
                        .add_mesh(&p, &tris, None, 0)
                        .build(&mt);
                    escapes(&g, &pos, &tris, center, radius, &mut rng);
                }
            }

            #[test]
            fn closed_box_of_polygons_never_leaks() {
                // A cube of six quads (triangulated by ear clipping), given as NFF
                // polygons with shared corner coordinates.
                let (lo, hi) = (-1.3, 2.7);
                let c = |x: u8, y: u8, z: u8| -> P3 {
                    [
                        if x == 1 { hi } else { lo },
                        if y == 1 { hi } else { lo },
                        if z == 1 { hi } else { lo },
                    ]
                };
                let faces = [
                    [c(0, 0, 0), c(0, 1, 0), c(1, 1, 0), c(1, 0, 0)],
                    [c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)],
                    [c(0, 0, 0), c(1, 0, 0), c(1, 0, 1), c(0, 0, 1)],
                    [c(0, 1, 0), c(0, 1, 1), c(1, 1, 1), c(1, 1, 0)],
                    [c(0, 0, 0), c(0, 0, 1), c(0, 1, 1), c(0, 1, 0)],
                    [c(1, 0, 0), c(1, 1, 0), c(1, 1, 1), c(1, 0, 1)],
                ];
                let shapes: Vec<ShapeDesc> = faces
                    .iter()
                    .map(|f| ShapeDesc {
                        shape: Shape::Polygon {
                            vertices: f.to_vec(),
                        },
                        material: 0,
                        line: 0,
                    })
                    .collect();
                let g = Geometry::<T>::build(&shapes, &AccelOptions::default());
                assert_eq!(g.stats().triangles, 12);
                let mut rng = Rng(7);
                let mid = 0.5 * (lo + hi);
                for _ in 0..20_000 {
                    // Aim at a random point on a random edge or corner of the cube.
                    let mut t: P3 = core::array::from_fn(|_| if rng.f() < 0.5 { lo } else { hi });
                    let free = (rng.f() * 4.0) as usize;
                    if free < 3 {
                        t[free] = lo + (hi - lo) * rng.f();
                    }
                    let o: P3 = core::array::from_fn(|_| mid + (rng.f() - 0.5) * 2.0);
                    let d = to_t::<T>(&core::array::from_fn(|i| t[i] - o[i]));
                    let r = Ray::new(to_t::<T>(&o), d);
                    let h = g.intersect(&r).unwrap_or_else(|| panic!("escaped: {r:?}"));
                    assert!(h.prim_id < 6);
                    // Leaving through a face: its outward normal faces along the ray.
                    assert!(h.geometric_normal.dot(&r.dir) >= T::ZERO);
                }
            }
        }
    };
}

watertight_tests!(f32_tests, f32);
watertight_tests!(f64_tests, f64);
