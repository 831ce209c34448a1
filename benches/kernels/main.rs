//! The kernel benchmarks: one criterion group per kernel, every implementation side by
//! side on the same fixed-seed inputs. See `benches/RESULTS.md` for the results and
//! `benches/run-targets.sh` for the per-target runs.
//!
//! Implementation names: `vecexpr` (expression templates), `vecexpr_fma` (the same with
//! explicit `mul_add`), `eager` (every operator a temporary, `benches::eager`), `hand`
//! (hand-written loop or formula), `vecexpr_vec3a` (vecexpr's padded `Vec3A`), `glam_vec3`, `glam_vec3a`, `glam_vec4`, `nalgebra`,
//! `ultraviolet` (`Vec3x8`, SoA packets of 8), `vecexpr_f32x8` and `vecexpr_f32x16`
//! (vecexpr on the explicit lane types of `vecexpr::simd`, run through `Isa::dispatch`
//! with AVX2 and AVX-512 whatever the build target; geometry kernels only). Size labels: `3` and `4` (one vector),
//! `aos4096` (4096 vectors, array of structures), `soa8x4096` and `soa16x4096` (the same
//! 4096 as SoA packets), `1K` … `16M` (one long vector of that many `f32`).

mod abcde;
mod bandwidth;
mod geometry;
mod linear;
mod mat3;

use benches::data::Pcg32;
use benches::eager::{Eager, FromF32};
use criterion::Criterion;
use ultraviolet::{f32x8, Vec3x8};
use vecexpr::typenum::{U16, U3, U8};
use vecexpr::{Packet, Vector};

/// Eight `f32` lanes.
type P8 = Packet<f32, U8>;
/// Sixteen `f32` lanes.
type P16 = Packet<f32, U16>;
/// One vecexpr 3-vector.
type V3 = Vector<f32, U3>;

/// Every representation of one batch of 3-vectors.
struct Batch {
    arr: Vec<[f32; 3]>,
    vx: Vec<V3>,
    eager: Vec<Eager<f32, U3>>,
    glam3: Vec<glam::Vec3>,
    glam3a: Vec<glam::Vec3A>,
    v3a: Vec<vecexpr::Vec3A>,
    na: Vec<nalgebra::Vector3<f32>>,
    p8: Vec<Vector<P8, U3>>,
    p16: Vec<Vector<P16, U3>>,
    e8: Vec<Eager<P8, U3>>,
    uv: Vec<Vec3x8>,
    soa: benches::data::Soa,
    /// Packets of 8 for `vecexpr::simd::F32x8` (`benches::data::aosoa`).
    lanes8: Vec<f32>,
    /// Packets of 16 for `vecexpr::simd::F32x16`.
    lanes16: Vec<f32>,
}

impl Batch {
    fn new(arr: Vec<[f32; 3]>) -> Self {
        let p8: Vec<Vector<P8, U3>> = arr
            .chunks_exact(8)
            .map(|c| Vector::from_fn(|k| P8::from_fn(|l| c[l][k])))
            .collect();
        Self {
            vx: arr.iter().map(|&v| V3::from(v)).collect(),
            eager: arr.iter().map(|&v| Eager::from3(v)).collect(),
            glam3: arr.iter().map(|&v| glam::Vec3::from(v)).collect(),
            glam3a: arr.iter().map(|&v| glam::Vec3A::from(v)).collect(),
            v3a: arr.iter().map(|&v| vecexpr::Vec3A::from(v)).collect(),
            na: arr.iter().map(|&v| nalgebra::Vector3::from(v)).collect(),
            p16: arr
                .chunks_exact(16)
                .map(|c| Vector::from_fn(|k| P16::from_fn(|l| c[l][k])))
                .collect(),
            e8: p8.iter().map(|p| Eager::from_fn(|k| p[k])).collect(),
            uv: p8
                .iter()
                .map(|p| {
                    let lanes =
                        |k: usize| f32x8::from(<[f32; 8]>::try_from(p[k].as_slice()).unwrap());
                    Vec3x8::new(lanes(0), lanes(1), lanes(2))
                })
                .collect(),
            soa: benches::data::Soa::from_aos(&arr),
            lanes8: benches::data::aosoa(&arr, 8),
            lanes16: benches::data::aosoa(&arr, 16),
            p8,
            arr,
        }
    }

    /// `n` random vectors with components in $[-1, 1)$.
    fn random(rng: &mut Pcg32, n: usize) -> Self {
        Self::new(rng.vec3s(n))
    }
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    bandwidth::bench(&mut c);
    abcde::bench(&mut c);
    linear::axpy(&mut c);
    linear::dot(&mut c);
    geometry::normalize(&mut c);
    geometry::cross(&mut c);
    geometry::reflect(&mut c);
    geometry::refract(&mut c);
    geometry::reflect_normalize(&mut c);
    geometry::normalize_zero_lane(&mut c);
    mat3::bench(&mut c);
    mat3::bench4(&mut c);
    c.final_summary();
}
