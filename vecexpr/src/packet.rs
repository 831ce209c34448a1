//! SoA packets: several lanes of `f32` or `f64` that act as one [`Scalar`].
//!
//! A `Vector<Packet<f32, U8>, U3>` holds eight 3-vectors in structure-of-arrays form
//! (all x, then all y, then all z), so any generic vecexpr formula applied to it
//! computes eight results at once with one SIMD operation per component and operator on a
//! target whose registers are eight lanes wide (AVX2 for 8 × f32, AVX-512 for 16 × f32).
//!
//! Every lane operation here is a fixed-length loop over `L` lanes that LLVM unrolls and
//! turns into vector instructions; the checked-in assembly (`asm-dumps/`) shows the
//! result per target.

use crate::scalar::{LaneBits, Mask, Real, Scalar};
use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use generic_array::{ArrayLength, GenericArray};

/// `L` lanes of the float type `T`, operated on lane-wise.
///
/// # Examples
/// ```
/// use vecexpr::{Packet, Scalar, typenum::U8};
/// let p = Packet::<f32, U8>::from_fn(|i| i as f32);
/// let q = p * p + Packet::splat(1.0);
/// assert_eq!(q.lane(3), 10.0);
/// ```
#[repr(transparent)]
pub struct Packet<T: Real, L: ArrayLength>(pub GenericArray<T, L>);

/// A lane-wise boolean for [`Packet`]: each lane is all ones (true) or all zeros (false),
/// the layout SIMD compare instructions produce and blend instructions consume.
#[repr(transparent)]
pub struct PacketMask<T: Real, L: ArrayLength>(pub GenericArray<T::Bits, L>);

impl<T: Real, L: ArrayLength> Clone for Packet<T, L> {
    #[inline(always)]
    fn clone(&self) -> Self {
        Self(self.0.clone())
    }
}
impl<T: Real, L: ArrayLength> Copy for Packet<T, L> where GenericArray<T, L>: Copy {}
impl<T: Real, L: ArrayLength> Clone for PacketMask<T, L> {
    #[inline(always)]
    fn clone(&self) -> Self {
        Self(self.0.clone())
    }
}
impl<T: Real, L: ArrayLength> Copy for PacketMask<T, L> where GenericArray<T::Bits, L>: Copy {}

impl<T: Real, L: ArrayLength> Packet<T, L> {
    /// Number of lanes.
    pub const LANES: usize = L::USIZE;

    /// A packet whose lane `i` is `f(i)`.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> T) -> Self {
        let mut out = Self(GenericArray::default());
        for i in 0..L::USIZE {
            out.0[i] = f(i);
        }
        out
    }

    /// The lanes as a slice.
    #[inline(always)]
    pub fn as_slice(&self) -> &[T] {
        &self.0
    }

    /// The lanes as a mutable slice.
    #[inline(always)]
    pub fn as_mut_slice(&mut self) -> &mut [T] {
        &mut self.0
    }

    /// Sum of all lanes (sequential order).
    #[inline]
    pub fn reduce_add(self) -> T {
        self.0.iter().fold(T::ZERO, |a, &b| a + b)
    }

    /// Smallest lane: NaN if any lane is NaN, `-0.0` below `+0.0`
    /// ([`Scalar::minimum`]).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{Packet, typenum::U4};
    /// let p = Packet::<f32, U4>::from_fn(|i| 2.0 - i as f32);
    /// assert_eq!(p.reduce_min(), -1.0);
    /// let q = Packet::<f32, U4>::from_fn(|i| if i == 1 { f32::NAN } else { 1.0 });
    /// assert!(q.reduce_min().is_nan());
    /// ```
    #[inline]
    pub fn reduce_min(self) -> T {
        self.0
            .iter()
            .skip(1)
            .fold(self.0[0], |a, &b| Scalar::minimum(a, b))
    }

    /// Largest lane: NaN if any lane is NaN, `+0.0` above `-0.0`
    /// ([`Scalar::maximum`]).
    #[inline]
    pub fn reduce_max(self) -> T {
        self.0
            .iter()
            .skip(1)
            .fold(self.0[0], |a, &b| Scalar::maximum(a, b))
    }

    #[inline(always)]
    fn zip(self, rhs: Self, f: impl Fn(T, T) -> T) -> Self {
        let mut out = self.clone();
        for i in 0..L::USIZE {
            out.0[i] = f(self.0[i], rhs.0[i]);
        }
        out
    }

    #[inline(always)]
    fn map_lanes(self, f: impl Fn(T) -> T) -> Self {
        let mut out = self.clone();
        for i in 0..L::USIZE {
            out.0[i] = f(self.0[i]);
        }
        out
    }

    #[inline(always)]
    fn cmp(self, rhs: Self, f: impl Fn(T, T) -> bool) -> PacketMask<T, L> {
        let mut out = PacketMask(GenericArray::default());
        for i in 0..L::USIZE {
            out.0[i] = if f(self.0[i], rhs.0[i]) {
                T::Bits::ALL
            } else {
                T::Bits::NONE
            };
        }
        out
    }
}

impl<T: Real, L: ArrayLength> PacketMask<T, L> {
    /// A mask whose lane `i` is `f(i)`.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> bool) -> Self {
        let mut out = Self(GenericArray::default());
        for i in 0..L::USIZE {
            out.0[i] = if f(i) { T::Bits::ALL } else { T::Bits::NONE };
        }
        out
    }

    /// Number of true lanes.
    #[inline]
    pub fn count(self) -> usize {
        self.0.iter().filter(|&&b| b != T::Bits::NONE).count()
    }

    #[inline(always)]
    fn zip(self, rhs: Self, f: impl Fn(T::Bits, T::Bits) -> T::Bits) -> Self {
        let mut out = self.clone();
        for i in 0..L::USIZE {
            out.0[i] = f(self.0[i], rhs.0[i]);
        }
        out
    }
}

impl<T: Real, L: ArrayLength> Mask for PacketMask<T, L>
where
    GenericArray<T::Bits, L>: Copy,
{
    const LANES: usize = L::USIZE;
    #[inline(always)]
    fn splat_bool(b: bool) -> Self {
        Self::from_fn(|_| b)
    }
    #[inline(always)]
    fn and(self, rhs: Self) -> Self {
        self.zip(rhs, |a, b| a & b)
    }
    #[inline(always)]
    fn or(self, rhs: Self) -> Self {
        self.zip(rhs, |a, b| a | b)
    }
    #[inline(always)]
    fn not(self) -> Self {
        let mut out = self;
        for i in 0..L::USIZE {
            out.0[i] = !self.0[i];
        }
        out
    }
    #[inline(always)]
    fn all(self) -> bool {
        let mut acc = T::Bits::ALL;
        for i in 0..L::USIZE {
            acc = acc & self.0[i];
        }
        acc != T::Bits::NONE
    }
    #[inline(always)]
    fn any(self) -> bool {
        let mut acc = T::Bits::NONE;
        for i in 0..L::USIZE {
            acc = acc | self.0[i];
        }
        acc != T::Bits::NONE
    }
    #[inline(always)]
    fn test(self, i: usize) -> bool {
        self.0[i] != T::Bits::NONE
    }
}

impl<T: Real, L: ArrayLength> PartialEq for PacketMask<T, L> {
    fn eq(&self, other: &Self) -> bool {
        self.0 == other.0
    }
}

impl<T: Real, L: ArrayLength> fmt::Debug for PacketMask<T, L> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list()
            .entries(self.0.iter().map(|&b| b != T::Bits::NONE))
            .finish()
    }
}

impl<T: Real, L: ArrayLength> Default for Packet<T, L> {
    #[inline(always)]
    fn default() -> Self {
        Self(GenericArray::default())
    }
}

/// Lane-wise equality of all lanes (IEEE: a NaN lane makes packets unequal).
impl<T: Real, L: ArrayLength> PartialEq for Packet<T, L> {
    fn eq(&self, other: &Self) -> bool {
        self.0 == other.0
    }
}

impl<T: Real, L: ArrayLength> fmt::Debug for Packet<T, L> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.0.iter()).finish()
    }
}

impl<T: Real, L: ArrayLength> From<GenericArray<T, L>> for Packet<T, L> {
    #[inline(always)]
    fn from(a: GenericArray<T, L>) -> Self {
        Self(a)
    }
}

macro_rules! packet_binop {
    ($tr:ident, $f:ident, $atr:ident, $af:ident, $op:tt) => {
        impl<T: Real, L: ArrayLength> $tr for Packet<T, L>
        where
            GenericArray<T, L>: Copy,
        {
            type Output = Self;
            #[inline(always)]
            fn $f(self, rhs: Self) -> Self {
                self.zip(rhs, |a, b| a $op b)
            }
        }
        impl<T: Real, L: ArrayLength> $atr for Packet<T, L>
        where
            GenericArray<T, L>: Copy,
        {
            #[inline(always)]
            fn $af(&mut self, rhs: Self) {
                *self = self.zip(rhs, |a, b| a $op b);
            }
        }
    };
}
packet_binop!(Add, add, AddAssign, add_assign, +);
packet_binop!(Sub, sub, SubAssign, sub_assign, -);
packet_binop!(Mul, mul, MulAssign, mul_assign, *);
packet_binop!(Div, div, DivAssign, div_assign, /);

impl<T: Real, L: ArrayLength> Neg for Packet<T, L>
where
    GenericArray<T, L>: Copy,
{
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map_lanes(|a| -a)
    }
}

impl<T: Real, L: ArrayLength> Scalar for Packet<T, L>
where
    GenericArray<T, L>: Copy,
    GenericArray<T::Bits, L>: Copy,
{
    type Elem = T;
    type Mask = PacketMask<T, L>;
    const LANES: usize = L::USIZE;

    #[inline(always)]
    fn splat(x: T) -> Self {
        Self::from_fn(|_| x)
    }
    #[inline(always)]
    fn min(self, rhs: Self) -> Self {
        self.zip(rhs, Scalar::min)
    }
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        self.zip(rhs, Scalar::max)
    }
    #[inline(always)]
    fn minimum(self, rhs: Self) -> Self {
        self.zip(rhs, Scalar::minimum)
    }
    #[inline(always)]
    fn maximum(self, rhs: Self) -> Self {
        self.zip(rhs, Scalar::maximum)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        self.map_lanes(Scalar::abs)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map_lanes(Scalar::sqrt)
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        let mut out = self;
        for i in 0..L::USIZE {
            out.0[i] = Scalar::mul_add(self.0[i], a.0[i], b.0[i]);
        }
        out
    }
    #[inline(always)]
    fn lt(self, rhs: Self) -> Self::Mask {
        self.cmp(rhs, |a, b| a < b)
    }
    #[inline(always)]
    fn le(self, rhs: Self) -> Self::Mask {
        self.cmp(rhs, |a, b| a <= b)
    }
    #[inline(always)]
    fn eq_mask(self, rhs: Self) -> Self::Mask {
        self.cmp(rhs, |a, b| a == b)
    }
    #[inline(always)]
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self {
        // Bitwise blend: (a & m) | (b & !m), one blend or ternary-logic instruction.
        let mut out = a;
        for i in 0..L::USIZE {
            let m = mask.0[i];
            out.0[i] = T::from_bits((a.0[i].to_bits() & m) | (b.0[i].to_bits() & !m));
        }
        out
    }
    #[inline(always)]
    fn lane(self, i: usize) -> T {
        self.0[i]
    }
    #[inline(always)]
    fn is_finite_mask(self) -> Self::Mask {
        self.cmp(self, |a, _| a.is_finite())
    }
}
