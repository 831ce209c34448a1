//! Four `f32` lanes in one SSE register (`__m128`); SSE2 is part of every x86-64 CPU.

use super::{Isa, SimdF32, SimdMask};
use crate::scalar::{Mask, Scalar};
use core::arch::x86_64::*;

/// Four `f32` lanes in an SSE register.
#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct F32x4(pub __m128);

/// The comparison result of [`F32x4`]: each lane all ones (true) or all zeros.
#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct M32x4(pub __m128);

// SAFETY (for every intrinsic call in this file): the intrinsics need SSE or SSE2, which
// every x86-64 CPU has (they are in the target's baseline features).

impl F32x4 {
    /// The lanes as an array.
    #[inline(always)]
    pub fn to_array(self) -> [f32; 4] {
        let mut out = [0.0f32; 4];
        // SAFETY: SSE baseline; `out` has room for four unaligned floats.
        unsafe { _mm_storeu_ps(out.as_mut_ptr(), self.0) };
        out
    }

    /// From an array of lanes.
    #[inline(always)]
    pub fn from_array(a: [f32; 4]) -> Self {
        // SAFETY: SSE baseline; `a` holds four floats.
        Self(unsafe { _mm_loadu_ps(a.as_ptr()) })
    }

    #[inline(always)]
    fn add_(self, rhs: Self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_add_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn sub_(self, rhs: Self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_sub_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn mul_(self, rhs: Self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_mul_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn div_(self, rhs: Self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_div_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn neg_(self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_xor_ps(self.0, _mm_set1_ps(-0.0)) })
    }
}

/// Register-level helpers of the padded 3-vector [`crate::Vec3A`]: lane shuffles and the
/// horizontal sums that keep the scalar summation order.
impl F32x4 {
    /// From a 16-byte aligned array (one aligned load).
    #[inline(always)]
    pub(crate) fn load_aligned(a: &super::Lanes4) -> Self {
        // SAFETY: SSE baseline; `Lanes4` is four floats aligned to 16 bytes.
        Self(unsafe { _mm_load_ps(a.0.as_ptr()) })
    }

    /// Into a 16-byte aligned array (one aligned store).
    #[inline(always)]
    pub(crate) fn store_aligned(self) -> super::Lanes4 {
        let mut out = super::Lanes4([0.0; 4]);
        // SAFETY: SSE baseline; `Lanes4` is four floats aligned to 16 bytes.
        unsafe { _mm_store_ps(out.0.as_mut_ptr(), self.0) };
        out
    }

    /// Lanes `[I0, I1, I2, I3]` of `self` (`IMM` packs the four 2-bit indices, lane 0 lowest).
    #[inline(always)]
    pub(crate) fn shuffle<const IMM: i32>(self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_shuffle_ps::<IMM>(self.0, self.0) })
    }

    /// $(x_0 + x_1) + x_2$ in lanes 0 and 1 (the left-to-right order of a scalar sum;
    /// lane 3 never enters), other lanes unspecified.
    #[inline(always)]
    pub(crate) fn hsum3_low(self) -> Self {
        // x1 in every lane, then x2 in every lane.
        let y = self.shuffle::<0b01_01_01_01>();
        let z = self.shuffle::<0b10_10_10_10>();
        self.add_(y).add_(z)
    }

    /// The bits of lane 0.
    #[inline(always)]
    pub(crate) fn bits0(self) -> u32 {
        // SAFETY: SSE2 baseline; a bit cast and a move to a general register.
        unsafe { _mm_cvtsi128_si32(_mm_castps_si128(self.0)) as u32 }
    }
}

lane_boilerplate!(F32x4, M32x4, 4);

impl Mask for M32x4 {
    const LANES: usize = 4;
    #[inline(always)]
    fn splat_bool(b: bool) -> Self {
        let bits = if b { u32::MAX } else { 0 };
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_castsi128_ps(_mm_set1_epi32(bits as i32)) })
    }
    #[inline(always)]
    fn and(self, rhs: Self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_and_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn or(self, rhs: Self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_or_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn not(self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_xor_ps(self.0, Self::splat_bool(true).0) })
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.bitmask() == 0xf
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.bitmask() != 0
    }
    #[inline(always)]
    fn test(self, i: usize) -> bool {
        assert!(i < 4, "lane {i} out of range for 4 lanes");
        self.bitmask() >> i & 1 != 0
    }
}

vector_mask_plain_bits!(M32x4, 4);

impl SimdMask for M32x4 {
    #[inline(always)]
    fn bitmask(self) -> u32 {
        // SAFETY: SSE baseline.
        unsafe { _mm_movemask_ps(self.0) as u32 }
    }
    #[inline(always)]
    fn from_bitmask(bits: u32) -> Self {
        // SAFETY: SSE2 baseline. Lane i keeps bit i, then compares equal to it.
        unsafe {
            let lanes = _mm_setr_epi32(1, 2, 4, 8);
            let b = _mm_and_si128(_mm_set1_epi32(bits as i32), lanes);
            Self(_mm_castsi128_ps(_mm_cmpeq_epi32(b, lanes)))
        }
    }
}

impl Scalar for F32x4 {
    type Elem = f32;
    type Mask = M32x4;
    const LANES: usize = 4;
    // The slow path of `normalize` stays inside the caller's instruction set.
    const INLINE_SLOW_PATHS: bool = true;

    #[inline(always)]
    fn splat(x: f32) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_set1_ps(x) })
    }
    #[inline(always)]
    fn min(self, rhs: Self) -> Self {
        // minps returns the second operand unless the first is smaller: the NaN rule of
        // `Scalar::min`.
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_min_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_max_ps(self.0, rhs.0) })
    }
    // IEEE 754-2019 `minimum`/`maximum` from the x86 rule `min(a, b) = a < b ? a : b`
    // (Intel SDM, MINPS/MAXPS): `min(a, b)` and `min(b, a)` agree unless the operands are
    // unordered or equal zeros, where each returns a different operand. Or-ing the two
    // keeps the sign bit of a -0.0 and the all-ones exponent and non-zero significand of a
    // NaN, so the or is `minimum`. For `maximum` the and of the two keeps +0.0, and an or
    // with the unordered mask (all ones, a NaN) makes NaN lanes NaN.
    #[inline(always)]
    fn minimum(self, rhs: Self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_or_ps(_mm_min_ps(self.0, rhs.0), _mm_min_ps(rhs.0, self.0)) })
    }
    #[inline(always)]
    fn maximum(self, rhs: Self) -> Self {
        // SAFETY: SSE baseline.
        unsafe {
            let m = _mm_and_ps(_mm_max_ps(self.0, rhs.0), _mm_max_ps(rhs.0, self.0));
            Self(_mm_or_ps(m, _mm_cmpunord_ps(self.0, rhs.0)))
        }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_andnot_ps(_mm_set1_ps(-0.0), self.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: SSE baseline.
        Self(unsafe { _mm_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        // SSE2 has no fused multiply-add: one correctly rounded `f32::mul_add` a lane.
        let (x, a, b) = (self.to_array(), a.to_array(), b.to_array());
        Self::from_array(core::array::from_fn(|i| x[i].mul_add(a[i], b[i])))
    }
    #[inline(always)]
    fn lt(self, rhs: Self) -> M32x4 {
        // SAFETY: SSE baseline.
        M32x4(unsafe { _mm_cmplt_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn le(self, rhs: Self) -> M32x4 {
        // SAFETY: SSE baseline.
        M32x4(unsafe { _mm_cmple_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn eq_mask(self, rhs: Self) -> M32x4 {
        // SAFETY: SSE baseline.
        M32x4(unsafe { _mm_cmpeq_ps(self.0, rhs.0) })
    }
    #[inline(always)]
    fn select(mask: M32x4, a: Self, b: Self) -> Self {
        // SAFETY: SSE baseline. (a & m) | (b & !m).
        Self(unsafe { _mm_or_ps(_mm_and_ps(mask.0, a.0), _mm_andnot_ps(mask.0, b.0)) })
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        self.to_array()[i]
    }
    #[inline(always)]
    fn is_finite_mask(self) -> M32x4 {
        // |x| < inf is false for infinities and NaN.
        self.abs().lt(Self::splat(f32::INFINITY))
    }
}

impl SimdF32 for F32x4 {
    const ISA: Isa = Isa::Sse2;
    #[inline(always)]
    fn load(s: &[f32]) -> Self {
        let s = &s[..4];
        // SAFETY: SSE baseline; `s` holds four floats.
        Self(unsafe { _mm_loadu_ps(s.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        let out = &mut out[..4];
        // SAFETY: SSE baseline; `out` has room for four floats.
        unsafe { _mm_storeu_ps(out.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        // SAFETY: SSE baseline. (|self|) | (sign & -0.0).
        unsafe {
            let s = _mm_set1_ps(-0.0);
            Self(_mm_or_ps(_mm_andnot_ps(s, self.0), _mm_and_ps(s, sign.0)))
        }
    }
    #[inline(always)]
    fn transpose8(recs: &[&[f32; 8]]) -> [Self; 8] {
        let r = &recs[..4];
        let mut out = [Self::zero(); 8];
        // SAFETY: SSE baseline; each load reads four of a record's eight values. Two
        // 4x4 transposes (unpack pairs, then move halves): values 0-3, then 4-7.
        unsafe {
            for (o, out) in [0, 4].into_iter().zip(out.chunks_exact_mut(4)) {
                let a = _mm_loadu_ps(r[0][o..].as_ptr());
                let b = _mm_loadu_ps(r[1][o..].as_ptr());
                let c = _mm_loadu_ps(r[2][o..].as_ptr());
                let d = _mm_loadu_ps(r[3][o..].as_ptr());
                let (ab_lo, ab_hi) = (_mm_unpacklo_ps(a, b), _mm_unpackhi_ps(a, b));
                let (cd_lo, cd_hi) = (_mm_unpacklo_ps(c, d), _mm_unpackhi_ps(c, d));
                out[0] = Self(_mm_movelh_ps(ab_lo, cd_lo));
                out[1] = Self(_mm_movehl_ps(cd_lo, ab_lo));
                out[2] = Self(_mm_movelh_ps(ab_hi, cd_hi));
                out[3] = Self(_mm_movehl_ps(cd_hi, ab_hi));
            }
        }
        out
    }
    #[inline(always)]
    fn reduce_min(self) -> f32 {
        // SAFETY: SSE baseline. Halves, then pairs.
        unsafe {
            let h = _mm_min_ps(self.0, _mm_movehl_ps(self.0, self.0));
            _mm_cvtss_f32(_mm_min_ss(h, _mm_shuffle_ps::<0b01>(h, h)))
        }
    }
    #[inline(always)]
    fn reduce_max(self) -> f32 {
        // SAFETY: SSE baseline. Halves, then pairs.
        unsafe {
            let h = _mm_max_ps(self.0, _mm_movehl_ps(self.0, self.0));
            _mm_cvtss_f32(_mm_max_ss(h, _mm_shuffle_ps::<0b01>(h, h)))
        }
    }
}
