//! Sixteen `f32` lanes in one AVX-512 register (`__m512`) with `__mmask16` masks, for
//! CPUs with AVX-512F (only AVX-512F instructions are used).

use super::{Isa, SimdF32, SimdMask};
use crate::scalar::{Mask, Scalar};
use core::arch::x86_64::*;

/// Sixteen `f32` lanes in an AVX-512 register.
///
/// Create values only on a CPU with AVX-512F (inside [`Isa::dispatch`] with
/// [`Isa::Avx512`], or after checking [`Isa::is_available`]); constructors check it in
/// builds with debug assertions.
#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct F32x16(pub __m512);

/// The comparison result of [`F32x16`]: an AVX-512 mask register, bit `i` for lane `i`.
#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct M32x16(pub __mmask16);

// SAFETY (for every intrinsic call in this file): a value of `F32x16` exists only on a CPU
// with AVX-512F (the contract of the type, checked by `check` in the constructors in
// debug builds), and every intrinsic below needs only AVX-512F. (`M32x16` is a plain
// 16-bit integer and needs no intrinsics.)

#[inline(always)]
fn check() {
    debug_assert!(Isa::Avx512.is_available(), "F32x16 needs AVX-512F");
}

impl F32x16 {
    /// The lanes as an array.
    #[inline(always)]
    pub fn to_array(self) -> [f32; 16] {
        let mut out = [0.0f32; 16];
        // SAFETY: AVX-512F (type contract); `out` has room for sixteen unaligned floats.
        unsafe { _mm512_storeu_ps(out.as_mut_ptr(), self.0) };
        out
    }

    /// From an array of lanes.
    #[inline(always)]
    pub fn from_array(a: [f32; 16]) -> Self {
        check();
        // SAFETY: AVX-512F (checked in debug builds, the caller's contract); `a` holds
        // sixteen floats.
        Self(unsafe { _mm512_loadu_ps(a.as_ptr()) })
    }

    #[inline(always)]
    fn bits(self, f: impl Fn(__m512i) -> __m512i) -> Self {
        // SAFETY: AVX-512F (type contract); the casts only reinterpret the register.
        Self(unsafe { _mm512_castsi512_ps(f(_mm512_castps_si512(self.0))) })
    }

    #[inline(always)]
    fn add_(self, rhs: Self) -> Self {
        // SAFETY: AVX-512F (type contract).
        Self(unsafe { _mm512_add_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn sub_(self, rhs: Self) -> Self {
        // SAFETY: AVX-512F (type contract).
        Self(unsafe { _mm512_sub_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn mul_(self, rhs: Self) -> Self {
        // SAFETY: AVX-512F (type contract).
        Self(unsafe { _mm512_mul_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn div_(self, rhs: Self) -> Self {
        // SAFETY: AVX-512F (type contract).
        Self(unsafe { _mm512_div_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn neg_(self) -> Self {
        // SAFETY: AVX-512F (type contract): integer xor with the sign bit.
        self.bits(|x| unsafe { _mm512_xor_si512(x, _mm512_set1_epi32(i32::MIN)) })
    }
}

lane_boilerplate!(F32x16, M32x16, 16);

impl Mask for M32x16 {
    const LANES: usize = 16;
    #[inline(always)]
    fn splat_bool(b: bool) -> Self {
        Self(if b { u16::MAX } else { 0 })
    }
    #[inline(always)]
    fn and(self, rhs: Self) -> Self {
        Self(self.0 & rhs.0)
    }
    #[inline(always)]
    fn or(self, rhs: Self) -> Self {
        Self(self.0 | rhs.0)
    }
    #[inline(always)]
    fn not(self) -> Self {
        Self(!self.0)
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.0 == u16::MAX
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0 != 0
    }
    #[inline(always)]
    fn test(self, i: usize) -> bool {
        assert!(i < 16, "lane {i} out of range for 16 lanes");
        self.0 >> i & 1 != 0
    }
}

impl M32x16 {
    /// The lanes' bits (`1 << lane`), as [`SimdMask::bitmask`] gives them.
    fn plain_bits(&self) -> u32 {
        u32::from(self.0)
    }
}

impl SimdMask for M32x16 {
    #[inline(always)]
    fn bitmask(self) -> u32 {
        u32::from(self.0)
    }
    #[inline(always)]
    fn from_bitmask(bits: u32) -> Self {
        Self(bits as u16)
    }
}

impl Scalar for F32x16 {
    type Elem = f32;
    type Mask = M32x16;
    const LANES: usize = 16;
    // The slow path of `normalize` stays inside the caller's instruction set.
    const INLINE_SLOW_PATHS: bool = true;

    #[inline(always)]
    fn splat(x: f32) -> Self {
        check();
        // SAFETY: AVX-512F (checked in debug builds, the caller's contract).
        Self(unsafe { _mm512_set1_ps(x) })
    }
    #[inline(always)]
    fn min(self, rhs: Self) -> Self {
        // vminps returns the second operand unless the first is smaller: the NaN rule of
        // `Scalar::min`.
        // SAFETY: AVX-512F (type contract).
        Self(unsafe { _mm512_min_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        // SAFETY: AVX-512F (type contract).
        Self(unsafe { _mm512_max_ps(self.0, rhs.0) })
    }
    // IEEE 754-2019 `minimum`/`maximum` from the x86 rule `min(a, b) = a < b ? a : b`
    // (Intel SDM, MINPS/MAXPS): `min(a, b)` and `min(b, a)` agree unless the operands are
    // unordered or equal zeros, where each returns a different operand. Or-ing (in integer lanes: AVX-512F has no float or) the two
    // keeps the sign bit of a -0.0 and the all-ones exponent and non-zero significand of a
    // NaN, so the or is `minimum`. For `maximum` the and of the two keeps +0.0, and a masked
    // move of NaN into the unordered lanes makes them NaN.
    #[inline(always)]
    fn minimum(self, rhs: Self) -> Self {
        // SAFETY: AVX-512F (type contract).
        unsafe {
            let a = _mm512_castps_si512(_mm512_min_ps(self.0, rhs.0));
            let b = _mm512_castps_si512(_mm512_min_ps(rhs.0, self.0));
            Self(_mm512_castsi512_ps(_mm512_or_si512(a, b)))
        }
    }
    #[inline(always)]
    fn maximum(self, rhs: Self) -> Self {
        // SAFETY: AVX-512F (type contract).
        unsafe {
            let a = _mm512_castps_si512(_mm512_max_ps(self.0, rhs.0));
            let b = _mm512_castps_si512(_mm512_max_ps(rhs.0, self.0));
            let m = _mm512_castsi512_ps(_mm512_and_si512(a, b));
            let nan = _mm512_cmp_ps_mask::<_CMP_UNORD_Q>(self.0, rhs.0);
            Self(_mm512_mask_mov_ps(m, nan, _mm512_set1_ps(f32::NAN)))
        }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: AVX-512F (type contract): integer and with the magnitude bits.
        self.bits(|x| unsafe { _mm512_and_si512(x, _mm512_set1_epi32(i32::MAX)) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: AVX-512F (type contract).
        Self(unsafe { _mm512_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        // SAFETY: AVX-512F (type contract).
        Self(unsafe { _mm512_fmadd_ps(self.0, a.0, b.0) })
    }
    #[inline(always)]
    fn lt(self, rhs: Self) -> M32x16 {
        // SAFETY: AVX-512F (type contract).
        M32x16(unsafe { _mm512_cmp_ps_mask::<_CMP_LT_OQ>(self.0, rhs.0) })
    }
    #[inline(always)]
    fn le(self, rhs: Self) -> M32x16 {
        // SAFETY: AVX-512F (type contract).
        M32x16(unsafe { _mm512_cmp_ps_mask::<_CMP_LE_OQ>(self.0, rhs.0) })
    }
    #[inline(always)]
    fn eq_mask(self, rhs: Self) -> M32x16 {
        // SAFETY: AVX-512F (type contract).
        M32x16(unsafe { _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(self.0, rhs.0) })
    }
    #[inline(always)]
    fn select(mask: M32x16, a: Self, b: Self) -> Self {
        // mask_blend takes the second operand where the mask bit is set.
        // SAFETY: AVX-512F (type contract of `a`).
        Self(unsafe { _mm512_mask_blend_ps(mask.0, b.0, a.0) })
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        self.to_array()[i]
    }
    #[inline(always)]
    fn is_finite_mask(self) -> M32x16 {
        // |x| < inf is false for infinities and NaN.
        self.abs().lt(Self::splat(f32::INFINITY))
    }
}

impl SimdF32 for F32x16 {
    const ISA: Isa = Isa::Avx512;
    #[inline(always)]
    fn load(s: &[f32]) -> Self {
        check();
        let s = &s[..16];
        // SAFETY: AVX-512F (checked in debug builds, the caller's contract); `s` holds
        // sixteen floats.
        Self(unsafe { _mm512_loadu_ps(s.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        let out = &mut out[..16];
        // SAFETY: AVX-512F (type contract); `out` has room for sixteen floats.
        unsafe { _mm512_storeu_ps(out.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        // SAFETY: AVX-512F (type contract). (|self|) | (sign & -0.0), in integer lanes.
        unsafe {
            let s = _mm512_set1_epi32(i32::MIN);
            let mag = _mm512_andnot_si512(s, _mm512_castps_si512(self.0));
            let sgn = _mm512_and_si512(s, _mm512_castps_si512(sign.0));
            Self(_mm512_castsi512_ps(_mm512_or_si512(mag, sgn)))
        }
    }
    #[inline(always)]
    fn transpose8(recs: &[&[f32; 8]]) -> [Self; 8] {
        check();
        let r = &recs[..16];
        // SAFETY: AVX-512F (type contract, checked above in debug builds); each load
        // reads one record's eight values. Register `i` holds records `i` and `i + 8`,
        // one per 256-bit half; the 8x8 transpose of AVX2 runs in both halves at once,
        // its last step as one two-register permutation per output. (No closures: one
        // left out of line would not be compiled with AVX-512 and call each intrinsic.)
        unsafe {
            let mut v = [_mm512_setzero_ps(); 8];
            for (i, v) in v.iter_mut().enumerate() {
                let lo = _mm512_castps256_ps512(_mm256_loadu_ps(r[i].as_ptr()));
                let hi = _mm256_castps_pd(_mm256_loadu_ps(r[i + 8].as_ptr()));
                *v = _mm512_castpd_ps(_mm512_insertf64x4::<1>(_mm512_castps_pd(lo), hi));
            }
            let u0 = _mm512_unpacklo_ps(v[0], v[1]);
            let u1 = _mm512_unpacklo_ps(v[2], v[3]);
            let u2 = _mm512_unpacklo_ps(v[4], v[5]);
            let u3 = _mm512_unpacklo_ps(v[6], v[7]);
            let w0 = _mm512_unpackhi_ps(v[0], v[1]);
            let w1 = _mm512_unpackhi_ps(v[2], v[3]);
            let w2 = _mm512_unpackhi_ps(v[4], v[5]);
            let w3 = _mm512_unpackhi_ps(v[6], v[7]);
            // Per 128-bit quarter, `q[k]` holds value k (quarters 0 and 2) or k + 4
            // (quarters 1 and 3) of records 0-3 (`q[k + 4]`: 4-7), plus 8 in the upper
            // half.
            let q = [
                _mm512_shuffle_ps::<0x44>(u0, u1),
                _mm512_shuffle_ps::<0xEE>(u0, u1),
                _mm512_shuffle_ps::<0x44>(w0, w1),
                _mm512_shuffle_ps::<0xEE>(w0, w1),
                _mm512_shuffle_ps::<0x44>(u2, u3),
                _mm512_shuffle_ps::<0xEE>(u2, u3),
                _mm512_shuffle_ps::<0x44>(w2, w3),
                _mm512_shuffle_ps::<0xEE>(w2, w3),
            ];
            // Lanes of the pair (a, b): a's 0-15, then b's as 16-31.
            let low = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27);
            let high =
                _mm512_setr_epi32(4, 5, 6, 7, 20, 21, 22, 23, 12, 13, 14, 15, 28, 29, 30, 31);
            [
                Self(_mm512_permutex2var_ps(q[0], low, q[4])),
                Self(_mm512_permutex2var_ps(q[1], low, q[5])),
                Self(_mm512_permutex2var_ps(q[2], low, q[6])),
                Self(_mm512_permutex2var_ps(q[3], low, q[7])),
                Self(_mm512_permutex2var_ps(q[0], high, q[4])),
                Self(_mm512_permutex2var_ps(q[1], high, q[5])),
                Self(_mm512_permutex2var_ps(q[2], high, q[6])),
                Self(_mm512_permutex2var_ps(q[3], high, q[7])),
            ]
        }
    }
    #[inline(always)]
    fn reduce_min(self) -> f32 {
        // SAFETY: AVX-512F (type contract).
        unsafe { _mm512_reduce_min_ps(self.0) }
    }
    #[inline(always)]
    fn reduce_max(self) -> f32 {
        // SAFETY: AVX-512F (type contract).
        unsafe { _mm512_reduce_max_ps(self.0) }
    }
}
