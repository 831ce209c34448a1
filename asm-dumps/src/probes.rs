//! The probes: one exported, never-inlined function per kernel and type.
//!
//! Inputs come by reference and the result goes out through `&mut`, so nothing is
//! optimised away and the body is only the kernel. Names say kernel, then type:
//! `f32x3` is one `Vec3<f32>`, `f32x4` one padded 4-vector, `packet8`/`packet16` one SoA
//! packet of 8 or 16 three-vectors (`Vec3<Packet<f32, U8|U16>>`), `f32x8`/`f32x16` the
//! same on vecexpr's explicit lane types (`vecexpr::simd`), `glam_vec3a` the glam
//! equivalent, `fma` the variant written with explicit fused multiply-adds (only checked
//! on targets with FMA: plain `x86-64` turns each into a call to `fmaf`).
//!
//! Inspect any of them with `cargo asm -p asm-dumps --lib <name>` (cargo-show-asm), or
//! read the checked-in dumps under `asm-dumps/dumps/<target>/`.

use crate::kernels;
use glam::{Mat3A, Vec3, Vec3A};
use vecexpr::typenum::{U1024, U16, U3, U4, U8};
use vecexpr::{Expr, Packet, Scalar, Vector};

/// One `f32` 3-vector.
pub type Vec3F32 = Vector<f32, U3>;
/// One `f64` 3-vector.
pub type Vec3F64 = Vector<f64, U3>;
/// One `f32` 4-vector (a 3-vector padded with a zero `w`).
pub type Vec4F32 = Vector<f32, U4>;
/// Eight `f32` lanes.
pub type P8 = Packet<f32, U8>;
/// Sixteen `f32` lanes.
pub type P16 = Packet<f32, U16>;
/// Eight 3-vectors in SoA form.
pub type Soa8 = Vector<P8, U3>;
/// Sixteen 3-vectors in SoA form.
pub type Soa16 = Vector<P16, U3>;
/// A long vector of 1024 `f32`.
pub type Long1k = Vector<f32, U1024>;

// ----- reflect: R = I - 2 N (N·I) -------------------------------------------------------

/// Reflects one `f32` 3-vector with vecexpr.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_f32x3(i: &Vec3F32, n: &Vec3F32, out: &mut Vec3F32) {
    *out = i.reflect(n);
}

/// Reflects one `f64` 3-vector with vecexpr.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_f64x3(i: &Vec3F64, n: &Vec3F64, out: &mut Vec3F64) {
    *out = i.reflect(n);
}

/// Reflects one padded `f32` 4-vector with vecexpr (`w = 0` stays 0).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_f32x4(i: &Vec4F32, n: &Vec4F32, out: &mut Vec4F32) {
    *out = i.reflect(n);
}

/// Reflects eight rays in SoA form with vecexpr.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_packet8(i: &Soa8, n: &Soa8, out: &mut Soa8) {
    *out = i.reflect(n);
}

/// Reflects sixteen rays in SoA form with vecexpr.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_packet16(i: &Soa16, n: &Soa16, out: &mut Soa16) {
    *out = i.reflect(n);
}

/// Reflects one `f32` 3-vector written with explicit FMA:
/// $R = \mathrm{fma}(-N, 2 (N \cdot I), I)$.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_fma_f32x3(i: &Vec3F32, n: &Vec3F32, out: &mut Vec3F32) {
    let d = n.dot(i);
    *out = (-n).mul_add(d + d, i).eval();
}

/// Reflects sixteen rays in SoA form written with explicit FMA.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_fma_packet16(i: &Soa16, n: &Soa16, out: &mut Soa16) {
    let d = n.dot(i);
    *out = (-n).mul_add(d + d, i).eval();
}

/// glam's `Vec3A::reflect`, the comparison for [`reflect_f32x3`].
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_glam_vec3a(i: &Vec3A, n: &Vec3A, out: &mut Vec3A) {
    *out = i.reflect(*n);
}

/// glam's unpadded `Vec3::reflect`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_glam_vec3(i: &Vec3, n: &Vec3, out: &mut Vec3) {
    *out = i.reflect(*n);
}

// ----- refract ---------------------------------------------------------------------------

/// Refracts one `f32` 3-vector (zero on total internal reflection, as glam does).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn refract_f32x3(i: &Vec3F32, n: &Vec3F32, eta: &f32, out: &mut Vec3F32) {
    *out = i.refract_masked(n, *eta).0;
}

/// Refracts sixteen rays in SoA form (zero in totally internally reflected lanes).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn refract_packet16(i: &Soa16, n: &Soa16, eta: &P16, out: &mut Soa16) {
    *out = i.refract_masked(n, *eta).0;
}

/// glam's `Vec3A::refract`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn refract_glam_vec3a(i: &Vec3A, n: &Vec3A, eta: &f32, out: &mut Vec3A) {
    *out = i.refract(*n, *eta);
}

// ----- normalize -------------------------------------------------------------------------

/// Normalises one `f32` 3-vector (robust: a cold out-of-line path handles zero,
/// tiny and huge vectors).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn normalize_f32x3(v: &Vec3F32, out: &mut Vec3F32) {
    *out = v.normalize();
}

/// Normalises sixteen 3-vectors in SoA form.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn normalize_packet16(v: &Soa16, out: &mut Soa16) {
    *out = v.normalize();
}

/// glam's `Vec3A::normalize` (no check for zero or overflow).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn normalize_glam_vec3a(v: &Vec3A, out: &mut Vec3A) {
    *out = v.normalize();
}

// ----- reflect then normalize (the packet target kernel) --------------------------------

/// Reflects and normalises sixteen rays in SoA form.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_normalize_packet16(i: &Soa16, n: &Soa16, out: &mut Soa16) {
    *out = kernels::reflect_normalize(i, n);
}

/// Reflects and normalises eight rays in SoA form.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_normalize_packet8(i: &Soa8, n: &Soa8, out: &mut Soa8) {
    *out = kernels::reflect_normalize(i, n);
}

/// glam: `i.reflect(n).normalize()` on one `Vec3A`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_normalize_glam_vec3a(i: &Vec3A, n: &Vec3A, out: &mut Vec3A) {
    *out = i.reflect(*n).normalize();
}

/// Eight 3-vectors on vecexpr's explicit AVX2 lanes (`vecexpr::simd::F32x8`).
pub type Lanes8 = Vector<vecexpr::simd::F32x8, U3>;
/// Sixteen 3-vectors on vecexpr's explicit AVX-512 lanes (`vecexpr::simd::F32x16`).
pub type Lanes16 = Vector<vecexpr::simd::F32x16, U3>;

/// Reflects and normalises eight rays on explicit AVX2 lanes, compiled for AVX2 + FMA
/// whatever the target (as `Isa::dispatch` compiles a kernel): the robust normalize's
/// rescaling is inline, lane by lane, so the only branch is the test whether any lane
/// needs it.
///
/// # Safety
/// Call it only on a CPU with AVX2 and FMA (`vecexpr::simd::Isa::Avx2.is_available()`).
#[unsafe(no_mangle)]
#[inline(never)]
#[target_feature(enable = "avx2,fma")]
pub fn reflect_normalize_f32x8(i: &Lanes8, n: &Lanes8, out: &mut Lanes8) {
    *out = kernels::reflect_normalize(i, n);
}

/// Reflects and normalises sixteen rays on explicit AVX-512 lanes, compiled for
/// AVX-512F whatever the target.
///
/// # Safety
/// Call it only on a CPU with AVX-512F (`vecexpr::simd::Isa::Avx512.is_available()`).
#[unsafe(no_mangle)]
#[inline(never)]
#[target_feature(enable = "avx512f,avx2,fma")]
pub fn reflect_normalize_f32x16(i: &Lanes16, n: &Lanes16, out: &mut Lanes16) {
    *out = kernels::reflect_normalize(i, n);
}

// ----- ray/sphere ------------------------------------------------------------------------

/// Ray/sphere distance for one ray ($+\infty$ on a miss).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn sphere_hit_f32x3(o: &Vec3F32, d: &Vec3F32, center: &Vec3F32, radius: &f32, t: &mut f32) {
    *t = kernels::sphere_hit(o, d, center, *radius, 1e-4);
}

/// Ray/sphere distances for sixteen rays in SoA form against one sphere (splat).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn sphere_hit_packet16(o: &Soa16, d: &Soa16, center: &Soa16, radius: &P16, t: &mut P16) {
    *t = kernels::sphere_hit(o, d, center, *radius, P16::splat(1e-4));
}

// ----- other kernels of the benchmarks ----------------------------------------------------

/// `a*b + c*d - e` over 1024 `f32`, fused by vecexpr.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn abcde_f32_1k(a: &Long1k, b: &Long1k, c: &Long1k, d: &Long1k, e: &Long1k, out: &mut Long1k) {
    kernels::abcde([a, b, c, d, e], out);
}

/// `a*b + c*d - e` over 1024 `f32`, the hand-written loop.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn abcde_hand_f32_1k(
    a: &[f32; 1024],
    b: &[f32; 1024],
    c: &[f32; 1024],
    d: &[f32; 1024],
    e: &[f32; 1024],
    out: &mut [f32; 1024],
) {
    for i in 0..1024 {
        out[i] = a[i] * b[i] + c[i] * d[i] - e[i];
    }
}

/// $y \leftarrow a x + y$ over 1024 `f32`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn axpy_f32_1k(a: &f32, x: &Long1k, y: &mut Long1k) {
    *y += x * *a;
}

/// $x \cdot y$ over 1024 `f32` (32 interleaved partial sums).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn dot_f32_1k(x: &Long1k, y: &Long1k, out: &mut f32) {
    *out = x.dot(y);
}

/// Cross product of two `f32` 3-vectors.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn cross_f32x3(a: &Vec3F32, b: &Vec3F32, out: &mut Vec3F32) {
    *out = a.cross(b);
}

/// glam's `Vec3A::cross`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn cross_glam_vec3a(a: &Vec3A, b: &Vec3A, out: &mut Vec3A) {
    *out = a.cross(*b);
}

/// A 3×3 matrix (columns) times a 3-vector.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn mat3_vec3_f32(m: &[Vec3F32; 3], v: &Vec3F32, out: &mut Vec3F32) {
    *out = kernels::mat3_mul(m, v);
}

/// glam's `Mat3A * Vec3A`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn mat3_vec3_glam_mat3a(m: &Mat3A, v: &Vec3A, out: &mut Vec3A) {
    *out = *m * *v;
}

/// `vecexpr::Mat3<f32> * Vector<f32, U3>` (`vecexpr::Matrix`, column-major).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn mat3_vec3_matrix(m: &vecexpr::Mat3<f32>, v: &Vec3F32, out: &mut Vec3F32) {
    *out = m * v;
}

/// `vecexpr::Mat4<f32> * Vector<f32, U4>`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn mat4_vec4_matrix(m: &vecexpr::Mat4<f32>, v: &Vec4F32, out: &mut Vec4F32) {
    *out = m * v;
}

/// glam's `Mat4 * Vec4`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn mat4_vec4_glam_mat4(m: &glam::Mat4, v: &glam::Vec4, out: &mut glam::Vec4) {
    *out = *m * *v;
}

/// `vecexpr::Mat4<f32> * vecexpr::Mat4<f32>`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn mat4_mat4_matrix(
    a: &vecexpr::Mat4<f32>,
    b: &vecexpr::Mat4<f32>,
    out: &mut vecexpr::Mat4<f32>,
) {
    *out = a * b;
}

/// glam's `Mat4 * Mat4`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn mat4_mat4_glam_mat4(a: &glam::Mat4, b: &glam::Mat4, out: &mut glam::Mat4) {
    *out = *a * *b;
}

// ----- vecexpr's padded single 3-vector (`vecexpr::Vec3A`) ---------------------------------

/// Reflects one `vecexpr::Vec3A` (16-byte aligned, one register).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_vec3a(i: &vecexpr::Vec3A, n: &vecexpr::Vec3A, out: &mut vecexpr::Vec3A) {
    *out = i.reflect(*n);
}

/// Normalises one `vecexpr::Vec3A` (robust: zero, tiny and huge vectors take a cold
/// out-of-line path).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn normalize_vec3a(v: &vecexpr::Vec3A, out: &mut vecexpr::Vec3A) {
    *out = v.normalize();
}

/// `i.reflect(n).normalize()` on one `vecexpr::Vec3A`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_normalize_vec3a(i: &vecexpr::Vec3A, n: &vecexpr::Vec3A, out: &mut vecexpr::Vec3A) {
    *out = i.reflect(*n).normalize();
}

/// Normalises one `vecexpr::Vec3A` with `normalize_fast`: the plain formula, no range
/// test (what glam's `Vec3A::normalize` computes).
#[unsafe(no_mangle)]
#[inline(never)]
pub fn normalize_fast_vec3a(v: &vecexpr::Vec3A, out: &mut vecexpr::Vec3A) {
    *out = v.normalize_fast();
}

/// `i.reflect(n).normalize_fast()` on one `vecexpr::Vec3A`.
#[unsafe(no_mangle)]
#[inline(never)]
pub fn reflect_normalize_fast_vec3a(
    i: &vecexpr::Vec3A,
    n: &vecexpr::Vec3A,
    out: &mut vecexpr::Vec3A,
) {
    *out = i.reflect(*n).normalize_fast();
}
