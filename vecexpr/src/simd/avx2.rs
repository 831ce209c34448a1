//! Eight `f32` lanes in one AVX register (`__m256`), for CPUs with AVX2 and FMA.

use super::{Isa, SimdF32, SimdMask};
use crate::scalar::{Mask, Scalar};
use core::arch::x86_64::*;

/// Eight `f32` lanes in an AVX register.
///
/// Create values only on a CPU with AVX2 and FMA (inside [`Isa::dispatch`] with
/// [`Isa::Avx2`], or after checking [`Isa::is_available`]); constructors check it in
/// builds with debug assertions.
#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct F32x8(pub __m256);

/// The comparison result of [`F32x8`]: each lane all ones (true) or all zeros.
#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct M32x8(pub __m256);

// SAFETY (for every intrinsic call in this file): a value of `F32x8` or `M32x8` exists
// only on a CPU with AVX2 and FMA (the contract of the type, checked by `check` in the
// constructors in debug builds), and every intrinsic below needs at most AVX, AVX2 or FMA.

#[inline(always)]
fn check() {
    debug_assert!(Isa::Avx2.is_available(), "F32x8 needs AVX2 and FMA");
}

impl F32x8 {
    /// The lanes as an array.
    #[inline(always)]
    pub fn to_array(self) -> [f32; 8] {
        let mut out = [0.0f32; 8];
        // SAFETY: AVX (type contract); `out` has room for eight unaligned floats.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
        out
    }

    /// From an array of lanes.
    #[inline(always)]
    pub fn from_array(a: [f32; 8]) -> Self {
        check();
        // SAFETY: AVX (checked in debug builds, the caller's contract); `a` holds eight
        // floats.
        Self(unsafe { _mm256_loadu_ps(a.as_ptr()) })
    }

    #[inline(always)]
    fn add_(self, rhs: Self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_add_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn sub_(self, rhs: Self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_sub_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn mul_(self, rhs: Self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_mul_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn div_(self, rhs: Self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_div_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn neg_(self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_xor_ps(self.0, _mm256_set1_ps(-0.0)) })
    }
}

lane_boilerplate!(F32x8, M32x8, 8);

impl Mask for M32x8 {
    const LANES: usize = 8;
    #[inline(always)]
    fn splat_bool(b: bool) -> Self {
        check();
        let bits = if b { u32::MAX } else { 0 };
        // SAFETY: AVX (checked in debug builds, the caller's contract).
        Self(unsafe { _mm256_castsi256_ps(_mm256_set1_epi32(bits as i32)) })
    }
    #[inline(always)]
    fn and(self, rhs: Self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_and_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn or(self, rhs: Self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_or_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn not(self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_xor_ps(self.0, Self::splat_bool(true).0) })
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.bitmask() == 0xff
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.bitmask() != 0
    }
    #[inline(always)]
    fn test(self, i: usize) -> bool {
        assert!(i < 8, "lane {i} out of range for 8 lanes");
        self.bitmask() >> i & 1 != 0
    }
}

vector_mask_plain_bits!(M32x8, 8);

impl SimdMask for M32x8 {
    #[inline(always)]
    fn bitmask(self) -> u32 {
        // SAFETY: AVX (type contract).
        unsafe { _mm256_movemask_ps(self.0) as u32 }
    }
    #[inline(always)]
    fn from_bitmask(bits: u32) -> Self {
        check();
        // SAFETY: AVX2 (checked in debug builds, the caller's contract). Lane i keeps
        // bit i, then compares equal to it.
        unsafe {
            let lanes = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            let b = _mm256_and_si256(_mm256_set1_epi32(bits as i32), lanes);
            Self(_mm256_castsi256_ps(_mm256_cmpeq_epi32(b, lanes)))
        }
    }
}

impl Scalar for F32x8 {
    type Elem = f32;
    type Mask = M32x8;
    const LANES: usize = 8;
    // The slow path of `normalize` stays inside the caller's instruction set.
    const INLINE_SLOW_PATHS: bool = true;

    #[inline(always)]
    fn splat(x: f32) -> Self {
        check();
        // SAFETY: AVX (checked in debug builds, the caller's contract).
        Self(unsafe { _mm256_set1_ps(x) })
    }
    #[inline(always)]
    fn min(self, rhs: Self) -> Self {
        // vminps returns the second operand unless the first is smaller: the NaN rule of
        // `Scalar::min`.
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_min_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_max_ps(self.0, rhs.0) })
    }
    // IEEE 754-2019 `minimum`/`maximum` from the x86 rule `min(a, b) = a < b ? a : b`
    // (Intel SDM, MINPS/MAXPS): `min(a, b)` and `min(b, a)` agree unless the operands are
    // unordered or equal zeros, where each returns a different operand. Or-ing the two
    // keeps the sign bit of a -0.0 and the all-ones exponent and non-zero significand of a
    // NaN, so the or is `minimum`. For `maximum` the and of the two keeps +0.0, and an or
    // with the unordered mask (all ones, a NaN) makes NaN lanes NaN.
    #[inline(always)]
    fn minimum(self, rhs: Self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_or_ps(_mm256_min_ps(self.0, rhs.0), _mm256_min_ps(rhs.0, self.0)) })
    }
    #[inline(always)]
    fn maximum(self, rhs: Self) -> Self {
        // SAFETY: AVX (type contract).
        unsafe {
            let m = _mm256_and_ps(_mm256_max_ps(self.0, rhs.0), _mm256_max_ps(rhs.0, self.0));
            Self(_mm256_or_ps(
                m,
                _mm256_cmp_ps::<_CMP_UNORD_Q>(self.0, rhs.0),
            ))
        }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        // SAFETY: FMA (type contract).
        Self(unsafe { _mm256_fmadd_ps(self.0, a.0, b.0) })
    }
    #[inline(always)]
    fn lt(self, rhs: Self) -> M32x8 {
        // SAFETY: AVX (type contract).
        M32x8(unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self.0, rhs.0) })
    }
    #[inline(always)]
    fn le(self, rhs: Self) -> M32x8 {
        // SAFETY: AVX (type contract).
        M32x8(unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, rhs.0) })
    }
    #[inline(always)]
    fn eq_mask(self, rhs: Self) -> M32x8 {
        // SAFETY: AVX (type contract).
        M32x8(unsafe { _mm256_cmp_ps::<_CMP_EQ_OQ>(self.0, rhs.0) })
    }
    #[inline(always)]
    fn select(mask: M32x8, a: Self, b: Self) -> Self {
        // blendv takes the second operand where the mask's sign bit is set.
        // SAFETY: AVX (type contract).
        Self(unsafe { _mm256_blendv_ps(b.0, a.0, mask.0) })
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        self.to_array()[i]
    }
    #[inline(always)]
    fn is_finite_mask(self) -> M32x8 {
        // |x| < inf is false for infinities and NaN.
        self.abs().lt(Self::splat(f32::INFINITY))
    }
}

impl SimdF32 for F32x8 {
    const ISA: Isa = Isa::Avx2;
    #[inline(always)]
    fn load(s: &[f32]) -> Self {
        check();
        let s = &s[..8];
        // SAFETY: AVX (checked in debug builds, the caller's contract); `s` holds eight
        // floats.
        Self(unsafe { _mm256_loadu_ps(s.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        let out = &mut out[..8];
        // SAFETY: AVX (type contract); `out` has room for eight floats.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        // SAFETY: AVX (type contract). (|self|) | (sign & -0.0).
        unsafe {
            let s = _mm256_set1_ps(-0.0);
            Self(_mm256_or_ps(
                _mm256_andnot_ps(s, self.0),
                _mm256_and_ps(s, sign.0),
            ))
        }
    }
    #[inline(always)]
    fn transpose8(recs: &[&[f32; 8]]) -> [Self; 8] {
        check();
        let r = &recs[..8];
        // SAFETY: AVX (type contract, checked above in debug builds); each load reads one
        // record's eight values. The 8x8 transpose: pairs of records interleaved, then
        // quadruples, within each 128-bit half; then the halves exchanged. (No
        // closures: one left out of line would not be compiled with AVX.)
        unsafe {
            let mut v = [_mm256_setzero_ps(); 8];
            for (i, v) in v.iter_mut().enumerate() {
                *v = _mm256_loadu_ps(r[i].as_ptr());
            }
            let u0 = _mm256_unpacklo_ps(v[0], v[1]);
            let u1 = _mm256_unpacklo_ps(v[2], v[3]);
            let u2 = _mm256_unpacklo_ps(v[4], v[5]);
            let u3 = _mm256_unpacklo_ps(v[6], v[7]);
            let w0 = _mm256_unpackhi_ps(v[0], v[1]);
            let w1 = _mm256_unpackhi_ps(v[2], v[3]);
            let w2 = _mm256_unpackhi_ps(v[4], v[5]);
            let w3 = _mm256_unpackhi_ps(v[6], v[7]);
            // Per 128-bit half, `q[k]` holds value k of records 0-3 (`q[k + 4]`: 4-7).
            let q = [
                _mm256_shuffle_ps::<0x44>(u0, u1),
                _mm256_shuffle_ps::<0xEE>(u0, u1),
                _mm256_shuffle_ps::<0x44>(w0, w1),
                _mm256_shuffle_ps::<0xEE>(w0, w1),
                _mm256_shuffle_ps::<0x44>(u2, u3),
                _mm256_shuffle_ps::<0xEE>(u2, u3),
                _mm256_shuffle_ps::<0x44>(w2, w3),
                _mm256_shuffle_ps::<0xEE>(w2, w3),
            ];
            [
                Self(_mm256_permute2f128_ps::<0x20>(q[0], q[4])),
                Self(_mm256_permute2f128_ps::<0x20>(q[1], q[5])),
                Self(_mm256_permute2f128_ps::<0x20>(q[2], q[6])),
                Self(_mm256_permute2f128_ps::<0x20>(q[3], q[7])),
                Self(_mm256_permute2f128_ps::<0x31>(q[0], q[4])),
                Self(_mm256_permute2f128_ps::<0x31>(q[1], q[5])),
                Self(_mm256_permute2f128_ps::<0x31>(q[2], q[6])),
                Self(_mm256_permute2f128_ps::<0x31>(q[3], q[7])),
            ]
        }
    }
    #[inline(always)]
    fn reduce_min(self) -> f32 {
        // SAFETY: AVX (type contract). The two halves, then as four lanes.
        let half = unsafe {
            _mm_min_ps(
                _mm256_castps256_ps128(self.0),
                _mm256_extractf128_ps::<1>(self.0),
            )
        };
        super::F32x4(half).reduce_min()
    }
    #[inline(always)]
    fn reduce_max(self) -> f32 {
        // SAFETY: AVX (type contract). The two halves, then as four lanes.
        let half = unsafe {
            _mm_max_ps(
                _mm256_castps256_ps128(self.0),
                _mm256_extractf128_ps::<1>(self.0),
            )
        };
        super::F32x4(half).reduce_max()
    }
}
