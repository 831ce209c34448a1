//! Explicit SIMD lane types and run-time instruction-set dispatch (x86-64).
//!
//! This is the only module of the workspace that uses `core::arch` intrinsics. It
//! provides three [`Scalar`]s of `f32` lanes, each one machine register wide:
//!
//! | type | lanes | register | mask | instruction set |
//! |---|---|---|---|---|
//! | [`F32x4`] | 4 | `__m128` | [`M32x4`] (`__m128`, all-ones lanes) | SSE2 |
//! | [`F32x8`] | 8 | `__m256` | [`M32x8`] (`__m256`, all-ones lanes) | AVX2 + FMA |
//! | [`F32x16`] | 16 | `__m512` | [`M32x16`] (`__mmask16`, one bit a lane) | AVX-512F |
//!
//! `Vector<F32x8, U3>` is then an SoA packet of eight 3-vectors, and every generic
//! vecexpr expression (dot, cross, `+`, `*`, select, ...) runs on it unchanged, one
//! instruction per component and operation. Each operation computes exactly what the
//! scalar `f32` operation computes lane by lane (IEEE single precision, correctly
//! rounded `+ - * / sqrt`, no contraction into FMA): `min`/`max` are `minps`/`maxps`,
//! which implement the `if a < b { a } else { b }` rule of [`Scalar::min`] (NaN gives
//! the second operand), and [`Scalar::minimum`]/[`Scalar::maximum`] (the NaN-propagating
//! rule of every minimum and maximum on vectors) take three to five instructions. Only
//! [`Scalar::mul_add`] fuses, as it does for `f32`.
//!
//! # Dispatch
//! [`Isa::detect`] finds the widest instruction set of the running CPU;
//! [`Isa::dispatch`] runs a [`Kernel`] — code generic over [`SimdF32`] — instantiated
//! with the matching lane type inside a function compiled with
//! `#[target_feature(enable = ...)]`. As long as the kernel's code is `#[inline(always)]`
//! down to the lane operations (all of which are), the whole kernel is compiled for that
//! instruction set, so one binary carries all three.
//!
//! # Safety contract
//! The AVX2 and AVX-512 lane types must only be created on a CPU that has those
//! instructions: that is what [`Isa::dispatch`] guarantees for the kernel it runs, and
//! every constructor checks it in builds with debug assertions. (SSE2 is part of x86-64.)
//!
//! On other targets the lane types and `dispatch` do not exist; [`Isa::available`] is
//! empty and [`Isa::detect`] returns `None`.

use crate::scalar::{Mask, Scalar};
use core::fmt;

/// `plain_bits` of a mask type that wraps a vector of `$n` 32-bit lanes (all ones or
/// all zeros): the lanes' bits (`1 << lane`) as [`SimdMask::bitmask`] gives them, read
/// from memory without an intrinsic (for `PartialEq` and `Debug`, compiled for the
/// baseline).
#[cfg(target_arch = "x86_64")]
macro_rules! vector_mask_plain_bits {
    ($m:ident, $n:expr) => {
        impl $m {
            fn plain_bits(&self) -> u32 {
                let p = (self as *const Self).cast::<[u32; $n]>();
                // SAFETY: the type is a `repr(transparent)` wrapper of a vector of `$n`
                // 32-bit lanes in memory order, as large as `[u32; $n]`; every bit
                // pattern is a valid `u32`, and the read is unaligned.
                let lanes = unsafe { core::ptr::read_unaligned(p) };
                lanes
                    .iter()
                    .enumerate()
                    .fold(0, |b, (i, &l)| b | (l >> 31) << i)
            }
        }
    };
}

/// Operator and formatting boilerplate of a lane type with inherent `add_`, `sub_`,
/// `mul_`, `div_`, `neg_` and `to_array` methods.
#[cfg(target_arch = "x86_64")]
macro_rules! lane_boilerplate {
    ($t:ident, $m:ident, $n:expr) => {
        impl core::ops::Add for $t {
            type Output = Self;
            #[inline(always)]
            fn add(self, rhs: Self) -> Self {
                self.add_(rhs)
            }
        }
        impl core::ops::Sub for $t {
            type Output = Self;
            #[inline(always)]
            fn sub(self, rhs: Self) -> Self {
                self.sub_(rhs)
            }
        }
        impl core::ops::Mul for $t {
            type Output = Self;
            #[inline(always)]
            fn mul(self, rhs: Self) -> Self {
                self.mul_(rhs)
            }
        }
        impl core::ops::Div for $t {
            type Output = Self;
            #[inline(always)]
            fn div(self, rhs: Self) -> Self {
                self.div_(rhs)
            }
        }
        impl core::ops::Neg for $t {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                self.neg_()
            }
        }
        impl core::ops::AddAssign for $t {
            #[inline(always)]
            fn add_assign(&mut self, rhs: Self) {
                *self = self.add_(rhs);
            }
        }
        impl core::ops::SubAssign for $t {
            #[inline(always)]
            fn sub_assign(&mut self, rhs: Self) {
                *self = self.sub_(rhs);
            }
        }
        impl core::ops::MulAssign for $t {
            #[inline(always)]
            fn mul_assign(&mut self, rhs: Self) {
                *self = self.mul_(rhs);
            }
        }
        impl core::ops::DivAssign for $t {
            #[inline(always)]
            fn div_assign(&mut self, rhs: Self) {
                *self = self.div_(rhs);
            }
        }
        impl Default for $t {
            /// Zero in every lane.
            #[inline(always)]
            fn default() -> Self {
                <Self as crate::Scalar>::splat(0.0)
            }
        }
        impl $t {
            /// The lanes, read from memory without an intrinsic: `PartialEq` and `Debug`
            /// are compiled for the baseline, where an intrinsic of a wider instruction
            /// set would be a function call (`asm-dumps/tests/intrinsic_calls.rs`).
            fn plain_lanes(&self) -> [f32; $n] {
                // SAFETY: the type is a `repr(transparent)` wrapper of a vector of `$n`
                // `f32` lanes in memory order, as large as `[f32; $n]`; every bit pattern
                // is a valid `f32`, and the read is unaligned.
                unsafe { core::ptr::read_unaligned((self as *const Self).cast::<[f32; $n]>()) }
            }
        }
        /// Lane-wise IEEE equality of all lanes (a NaN lane makes packets unequal).
        impl PartialEq for $t {
            fn eq(&self, other: &Self) -> bool {
                self.plain_lanes() == other.plain_lanes()
            }
        }
        impl core::fmt::Debug for $t {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.debug_list().entries(self.plain_lanes().iter()).finish()
            }
        }
        impl PartialEq for $m {
            fn eq(&self, other: &Self) -> bool {
                self.plain_bits() == other.plain_bits()
            }
        }
        impl core::fmt::Debug for $m {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                let b = self.plain_bits();
                f.debug_list()
                    .entries((0..$n).map(|i| b >> i & 1 != 0))
                    .finish()
            }
        }
    };
}

/// Four `f32` lanes aligned to 16 bytes: one SSE register in memory, loaded and stored
/// with single aligned instructions (the storage of [`crate::Vec3A`]).
#[derive(Clone, Copy, PartialEq, Default)]
#[repr(C, align(16))]
pub(crate) struct Lanes4(pub(crate) [f32; 4]);

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;
#[cfg(target_arch = "x86_64")]
mod sse2;
#[cfg(all(test, target_arch = "x86_64"))]
mod tests;

#[cfg(target_arch = "x86_64")]
pub use avx2::{F32x8, M32x8};
#[cfg(target_arch = "x86_64")]
pub use avx512::{F32x16, M32x16};
#[cfg(target_arch = "x86_64")]
pub use sse2::{F32x4, M32x4};

/// Asks the CPU to bring the cache line holding `p` into the first-level cache, without
/// waiting for it (x86-64 `prefetcht0`; nothing elsewhere). A hint only: it never faults,
/// whatever `p` points at, and changes no result.
#[inline(always)]
pub fn prefetch<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: SSE is part of x86-64, and a prefetch reads nothing the program sees
        // and cannot fault, so any address is allowed.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// An x86-64 instruction set the lane types are compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Isa {
    /// SSE2, 4 lanes ([`F32x4`]): every x86-64 CPU.
    Sse2,
    /// AVX2 and FMA, 8 lanes ([`F32x8`]).
    Avx2,
    /// AVX-512F, 16 lanes ([`F32x16`]).
    Avx512,
}

impl Isa {
    /// All instruction sets, narrowest first.
    pub const ALL: [Isa; 3] = [Isa::Sse2, Isa::Avx2, Isa::Avx512];

    /// Lanes of its `f32` type.
    pub const fn lanes(self) -> usize {
        match self {
            Isa::Sse2 => 4,
            Isa::Avx2 => 8,
            Isa::Avx512 => 16,
        }
    }

    /// The lower-case name (`sse2`, `avx2`, `avx512`), as the command line spells it.
    pub const fn name(self) -> &'static str {
        match self {
            Isa::Sse2 => "sse2",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }

    /// Parses [`Isa::name`].
    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|i| i.name() == s)
    }

    /// Does the running CPU have this instruction set? (Cached by the standard library
    /// after the first query.)
    #[inline]
    pub fn is_available(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            match self {
                Isa::Sse2 => true,
                Isa::Avx2 => {
                    std::arch::is_x86_feature_detected!("avx2")
                        && std::arch::is_x86_feature_detected!("fma")
                }
                Isa::Avx512 => std::arch::is_x86_feature_detected!("avx512f"),
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = self;
            false
        }
    }

    /// The instruction sets of the running CPU, narrowest first.
    pub fn available() -> Vec<Isa> {
        Self::ALL.into_iter().filter(|i| i.is_available()).collect()
    }

    /// The widest instruction set of the running CPU (`None` off x86-64).
    pub fn detect() -> Option<Isa> {
        Self::available().last().copied()
    }

    /// Runs `kernel` with the lane type of this instruction set, compiled for it.
    ///
    /// # Panics
    /// If the running CPU lacks the instruction set ([`Isa::is_available`]).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::simd::{Isa, Kernel, SimdF32};
    /// use vecexpr::Scalar;
    ///
    /// /// The sum of a slice, `S::LANES` floats at a time.
    /// struct Sum<'a>(&'a [f32]);
    /// impl Kernel for Sum<'_> {
    ///     type Output = f32;
    ///     #[inline(always)]
    ///     fn run<S: SimdF32>(self) -> f32 {
    ///         let mut acc = S::zero();
    ///         let mut chunks = self.0.chunks_exact(S::LANES);
    ///         for c in &mut chunks {
    ///             acc += S::load(c);
    ///         }
    ///         let mut lanes = [0.0f32; 16];
    ///         acc.store(&mut lanes);
    ///         lanes.iter().sum::<f32>() + chunks.remainder().iter().sum::<f32>()
    ///     }
    /// }
    ///
    /// let data: Vec<f32> = (0..100).map(|i| i as f32).collect();
    /// // Every instruction set of this CPU gives the same (exact) sum.
    /// for isa in Isa::available() {
    ///     assert_eq!(isa.dispatch(Sum(&data)), 4950.0);
    /// }
    /// ```
    #[cfg(target_arch = "x86_64")]
    #[inline]
    pub fn dispatch<K: Kernel>(self, kernel: K) -> K::Output {
        assert!(
            self.is_available(),
            "this CPU does not support {}",
            self.name()
        );
        match self {
            Isa::Sse2 => entry_sse2(kernel),
            // SAFETY: `is_available` just confirmed AVX2 and FMA.
            Isa::Avx2 => unsafe { entry_avx2(kernel) },
            // SAFETY: `is_available` just confirmed AVX-512F.
            Isa::Avx512 => unsafe { entry_avx512(kernel) },
        }
    }
}

impl fmt::Display for Isa {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Code generic over the lane type, run by [`Isa::dispatch`].
///
/// Mark `run` (and everything it calls that should be compiled for the instruction set)
/// `#[inline(always)]`: only inlined code inherits the entry point's target features.
///
/// # Examples
/// ```
/// use vecexpr::simd::{Isa, Kernel, SimdF32};
/// use vecexpr::typenum::U3;
/// use vecexpr::{Expr, Vector};
///
/// /// Normalises 3-vectors stored as three arrays (x, y, z) in place.
/// struct Normalize<'a>([&'a mut [f32]; 3]);
/// impl Kernel for Normalize<'_> {
///     type Output = ();
///     #[inline(always)]
///     fn run<S: SimdF32>(self) {
///         let [x, y, z] = self.0;
///         for i in (0..x.len()).step_by(S::LANES) {
///             let v = Vector::<S, U3>::from_fn(|c| S::load(&[&*x, &*y, &*z][c][i..]));
///             let u = v.normalize();
///             u[0].store(&mut x[i..]);
///             u[1].store(&mut y[i..]);
///             u[2].store(&mut z[i..]);
///         }
///     }
/// }
///
/// let (mut x, mut y, mut z) = ([3.0f32; 16], [0.0f32; 16], [4.0f32; 16]);
/// Isa::detect().unwrap().dispatch(Normalize([&mut x, &mut y, &mut z]));
/// assert_eq!((x[15], y[15], z[15]), (0.6, 0.0, 0.8));
/// ```
pub trait Kernel {
    /// What the kernel returns.
    type Output;
    /// The kernel instantiated for the lane type `S`.
    fn run<S: SimdF32>(self) -> Self::Output;
}

#[cfg(target_arch = "x86_64")]
#[inline(never)]
fn entry_sse2<K: Kernel>(kernel: K) -> K::Output {
    kernel.run::<F32x4>()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline(never)]
unsafe fn entry_avx2<K: Kernel>(kernel: K) -> K::Output {
    kernel.run::<F32x8>()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2,fma")]
#[inline(never)]
unsafe fn entry_avx512<K: Kernel>(kernel: K) -> K::Output {
    kernel.run::<F32x16>()
}

/// An explicit SIMD register of `f32` lanes: a [`Scalar`] with loads, stores and the
/// few operations the generic trait lacks.
pub trait SimdF32: Scalar<Elem = f32, Mask: SimdMask> {
    /// The instruction set the type is compiled for.
    const ISA: Isa;
    /// Loads lanes `0..LANES` from `s`.
    ///
    /// # Panics
    /// If `s` is shorter than `LANES`.
    fn load(s: &[f32]) -> Self;
    /// Stores the lanes into `out[0..LANES]`.
    ///
    /// # Panics
    /// If `out` is shorter than `LANES`.
    fn store(self, out: &mut [f32]);
    /// Lane-wise: the magnitude of `self` with the sign bit of `sign` (as `f32::copysign`).
    fn copysign(self, sign: Self) -> Self;
    /// Eight values of each of `LANES` records, transposed into eight registers: lane
    /// `l` of `out[k]` is `recs[l][k]` (records in, structure of arrays out).
    ///
    /// # Panics
    /// If `recs` has fewer than `LANES` records.
    fn transpose8(recs: &[&[f32; 8]]) -> [Self; 8];
    /// The smallest lane. With NaN lanes the result is unspecified (one of the lanes).
    fn reduce_min(self) -> f32;
    /// The largest lane. With NaN lanes the result is unspecified (one of the lanes).
    fn reduce_max(self) -> f32;
}

/// A lane mask of a [`SimdF32`] type, convertible to and from a bit mask.
pub trait SimdMask: Mask {
    /// Bit `i` set for each true lane `i`.
    fn bitmask(self) -> u32;
    /// The mask whose lane `i` is bit `i` of `bits` (higher bits ignored).
    fn from_bitmask(bits: u32) -> Self;
}
