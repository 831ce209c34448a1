//! The scalar types an expression computes with: plain floats and SoA packets.
//!
//! [`Scalar`] is what an element of a [`Vector`](crate::Vector) must be: `f32`, `f64`,
//! or a [`Packet`](crate::Packet) of several lanes of one of them. Every operation is
//! lane-wise, so the same generic expression code serves one ray and a packet of sixteen.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// An element type of a vector: `f32`, `f64`, or an SoA packet of either.
///
/// All methods act lane by lane. Comparisons return [`Scalar::Mask`], which
/// [`Scalar::select`] consumes.
///
/// # NaN and the two kinds of minimum
/// - [`Scalar::minimum`] and [`Scalar::maximum`] propagate NaN: the result is NaN when
///   either operand is, and `-0.0` counts as less than `+0.0` (IEEE 754-2019 `minimum`
///   and `maximum`, the same as the unstable `f32::minimum`). Every minimum and maximum
///   on vectors uses them: the element-wise [`Expr::min`](crate::Expr::min) and
///   [`Expr::max`](crate::Expr::max), the reductions
///   [`Expr::min_element`](crate::Expr::min_element) and
///   [`Expr::max_element`](crate::Expr::max_element), and
///   [`Packet::reduce_min`](crate::Packet::reduce_min) /
///   [`Packet::reduce_max`](crate::Packet::reduce_max), for plain floats, packets and
///   the SIMD lane types alike (per lane).
/// - [`Scalar::min`] and [`Scalar::max`] are the one-instruction x86 `minps`/`maxps`
///   rule: `a.min(b)` is `if a < b { a } else { b }`, so when either operand is NaN the
///   result is `b`. Robust slab tests rely on it (a NaN distance is replaced by the running
///   bound); use it in kernels that want exactly that.
/// - [`Real::min_num`] and [`Real::max_num`] are IEEE `minNum`/`maxNum` (NaN ignored) on
///   plain floats.
///
/// Sums ([`Expr::sum`](crate::Expr::sum), `dot`, `length`) follow IEEE addition: NaN if
/// any term is NaN, and NaN for `+∞ + −∞`.
pub trait Scalar:
    Copy
    + Debug
    + Default
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
{
    /// The type of one lane: `f32` or `f64`.
    type Elem: Real;
    /// A lane-wise boolean: `bool` for plain floats, a lane mask for packets.
    type Mask: Mask;
    /// Number of lanes (1 for plain floats).
    const LANES: usize;
    /// Whether kernels with a rare slow path (the rescaling of
    /// [`Expr::normalize`](crate::Expr::normalize)) compute it inline, selecting its
    /// result lane by lane, instead of calling an out-of-line cold function for the whole
    /// value. `false` by default; the explicit SIMD lane types of [`crate::simd`] set it,
    /// because their operations compile to single instructions only when inlined into a
    /// function compiled for their instruction set: an out-of-line slow path would run
    /// every lane operation as a call.
    const INLINE_SLOW_PATHS: bool = false;

    /// Every lane set to `x`.
    fn splat(x: Self::Elem) -> Self;
    /// Zero in every lane.
    #[inline(always)]
    fn zero() -> Self {
        Self::splat(<Self::Elem as Real>::ZERO)
    }
    /// One in every lane.
    #[inline(always)]
    fn one() -> Self {
        Self::splat(<Self::Elem as Real>::ONE)
    }
    /// Every lane set to `x` converted (rounded to nearest) to the lane type.
    #[inline(always)]
    fn splat_f64(x: f64) -> Self {
        Self::splat(<Self::Elem as Real>::from_f64(x))
    }
    /// Lane-wise `if self < rhs { self } else { rhs }` (NaN gives `rhs`: the x86
    /// `minps` rule, one instruction; see [`Scalar::minimum`] for the NaN-propagating
    /// minimum that vectors use).
    fn min(self, rhs: Self) -> Self;
    /// Lane-wise `if self > rhs { self } else { rhs }` (NaN gives `rhs`: the x86
    /// `maxps` rule; see [`Scalar::maximum`]).
    fn max(self, rhs: Self) -> Self;
    /// Lane-wise IEEE 754-2019 `minimum`: NaN if either operand is NaN, otherwise the
    /// smaller, with `-0.0` less than `+0.0`. The rule of every minimum on vectors.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::Scalar;
    /// assert!(Scalar::minimum(1.0f32, f32::NAN).is_nan());
    /// assert!(Scalar::minimum(f32::NAN, 1.0f32).is_nan());
    /// assert_eq!(Scalar::minimum(0.0f64, -0.0).to_bits(), (-0.0f64).to_bits());
    /// // The x86 rule of `min` instead gives the second operand:
    /// assert_eq!(Scalar::min(f32::NAN, 1.0f32), 1.0);
    /// ```
    fn minimum(self, rhs: Self) -> Self;
    /// Lane-wise IEEE 754-2019 `maximum`: NaN if either operand is NaN, otherwise the
    /// larger, with `+0.0` greater than `-0.0`. The rule of every maximum on vectors.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{Packet, Scalar, typenum::U4};
    /// let a = Packet::<f32, U4>::from_fn(|i| i as f32);
    /// let b = Packet::<f32, U4>::from_fn(|i| if i == 2 { f32::NAN } else { 1.5 });
    /// let m = Scalar::maximum(a, b);
    /// assert_eq!((m.lane(0), m.lane(1), m.lane(3)), (1.5, 1.5, 3.0));
    /// assert!(m.lane(2).is_nan());
    /// ```
    fn maximum(self, rhs: Self) -> Self;
    /// Lane-wise absolute value (clears the sign bit, so `-0.0` gives `0.0` and NaN stays NaN).
    fn abs(self) -> Self;
    /// Lane-wise correctly rounded square root (NaN for negative lanes).
    fn sqrt(self) -> Self;
    /// Lane-wise `1 / self`, correctly rounded.
    #[inline(always)]
    fn recip(self) -> Self {
        Self::one() / self
    }
    /// Lane-wise fused multiply-add `self * a + b` with a single rounding.
    ///
    /// On targets without hardware FMA this is a library call and slow; it is never
    /// introduced implicitly.
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// Lane-wise `self < rhs`.
    fn lt(self, rhs: Self) -> Self::Mask;
    /// Lane-wise `self <= rhs`.
    fn le(self, rhs: Self) -> Self::Mask;
    /// Lane-wise `self > rhs`.
    #[inline(always)]
    fn gt(self, rhs: Self) -> Self::Mask {
        rhs.lt(self)
    }
    /// Lane-wise `self >= rhs`.
    #[inline(always)]
    fn ge(self, rhs: Self) -> Self::Mask {
        rhs.le(self)
    }
    /// Lane-wise `self == rhs` (IEEE: NaN is unequal to everything, `-0.0 == 0.0`).
    fn eq_mask(self, rhs: Self) -> Self::Mask;
    /// Lane-wise `if mask { a } else { b }`.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// Lane `i` (panics if `i >= LANES`).
    fn lane(self, i: usize) -> Self::Elem;
    /// Lane-wise: is the value neither infinite nor NaN?
    fn is_finite_mask(self) -> Self::Mask;
    /// Lane-wise: is the value NaN?
    #[inline(always)]
    fn is_nan_mask(self) -> Self::Mask {
        self.eq_mask(self).not()
    }
}

/// A lane-wise boolean produced by comparisons on a [`Scalar`].
pub trait Mask: Copy + Debug + PartialEq + Send + Sync + 'static {
    /// Number of lanes.
    const LANES: usize;
    /// Every lane set to `b`.
    fn splat_bool(b: bool) -> Self;
    /// Lane-wise and.
    fn and(self, rhs: Self) -> Self;
    /// Lane-wise or.
    fn or(self, rhs: Self) -> Self;
    /// Lane-wise not.
    fn not(self) -> Self;
    /// Are all lanes true?
    fn all(self) -> bool;
    /// Is any lane true?
    fn any(self) -> bool;
    /// Lane `i` as a `bool` (panics if `i >= LANES`).
    fn test(self, i: usize) -> bool;
}

impl Mask for bool {
    const LANES: usize = 1;
    #[inline(always)]
    fn splat_bool(b: bool) -> Self {
        b
    }
    #[inline(always)]
    fn and(self, rhs: Self) -> Self {
        self & rhs
    }
    #[inline(always)]
    fn or(self, rhs: Self) -> Self {
        self | rhs
    }
    #[inline(always)]
    fn not(self) -> Self {
        !self
    }
    #[inline(always)]
    fn all(self) -> bool {
        self
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
    #[inline(always)]
    fn test(self, i: usize) -> bool {
        assert!(i == 0, "lane {i} out of range for a scalar mask");
        self
    }
}

/// A plain floating-point type, `f32` or `f64`: a one-lane [`Scalar`] with an order and
/// the usual transcendental functions.
pub trait Real: Scalar<Elem = Self, Mask = bool> + PartialOrd + core::fmt::Display {
    /// The unsigned integer of the same width, for bit manipulation (`u32` or `u64`).
    type Bits: LaneBits;
    /// Zero.
    const ZERO: Self;
    /// One.
    const ONE: Self;
    /// Machine epsilon: the difference between 1 and the next larger value.
    const EPSILON: Self;
    /// Positive infinity.
    const INFINITY: Self;
    /// Negative infinity.
    const NEG_INFINITY: Self;
    /// A quiet NaN.
    const NAN: Self;
    /// Largest finite value.
    const MAX: Self;
    /// Smallest positive normal value.
    const MIN_POSITIVE: Self;
    /// π.
    const PI: Self;
    /// Number of significand bits including the implicit one (24 or 53).
    const MANTISSA_DIGITS: u32;

    /// Round an `f64` to this type.
    fn from_f64(x: f64) -> Self;
    /// Widen (or keep) to `f64`, exactly.
    fn to_f64(self) -> f64;
    /// Converts an `i32`, rounding to nearest.
    fn from_i32(x: i32) -> Self;
    /// The raw IEEE bits.
    fn to_bits(self) -> Self::Bits;
    /// From raw IEEE bits.
    fn from_bits(bits: Self::Bits) -> Self;
    /// IEEE `minNum`: the non-NaN operand when exactly one is NaN.
    fn min_num(self, rhs: Self) -> Self;
    /// IEEE `maxNum`: the non-NaN operand when exactly one is NaN.
    fn max_num(self, rhs: Self) -> Self;
    /// `self` raised to a floating-point power.
    fn powf(self, e: Self) -> Self;
    /// `self` raised to an integer power (run-time exponent).
    fn powi(self, e: i32) -> Self;
    /// Largest integer not greater than `self`.
    fn floor(self) -> Self;
    /// Smallest integer not less than `self`.
    fn ceil(self) -> Self;
    /// Sine (radians).
    fn sin(self) -> Self;
    /// Cosine (radians).
    fn cos(self) -> Self;
    /// Tangent (radians).
    fn tan(self) -> Self;
    /// Arc cosine, in radians.
    fn acos(self) -> Self;
    /// Four-quadrant arc tangent of `self / x`, in radians.
    fn atan2(self, x: Self) -> Self;
    /// Is the value NaN?
    fn is_nan(self) -> bool;
    /// Is the value finite?
    fn is_finite(self) -> bool;
    /// Copies the sign of `sign` onto the magnitude of `self`.
    fn copysign(self, sign: Self) -> Self;
    /// The next representable value toward +∞ (identity on +∞ and NaN).
    fn next_up(self) -> Self;
    /// The next representable value toward −∞ (identity on −∞ and NaN).
    fn next_down(self) -> Self;
    /// An approximate $1 / \sqrt{x}$: the integer "magic constant" estimate refined by
    /// one Newton–Raphson step $y (3/2 - x y^2 / 2)$, with no square root or division.
    ///
    /// The constants are Lomont's (C. Lomont, "Fast inverse square root", 2003:
    /// `0x5f375a86` for `f32`, `0x5fe6eb50c7b537a9` for `f64`); the relative error is at
    /// most about 1.8e-3 in either precision, so it is an approximation for speed, not a
    /// replacement for `sqrt().recip()`. Meant for positive normal `x`: zero gives a large
    /// finite value, negative input and NaN give NaN or garbage.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::Real;
    /// let y = 4.0f32.rsqrt_approx();
    /// assert!((y - 0.5).abs() < 0.5 * 2e-3);
    /// ```
    fn rsqrt_approx(self) -> Self;
}

/// The raw bits of one lane (`u32` or `u64`), used for packet masks.
pub trait LaneBits:
    Copy
    + Debug
    + Default
    + Eq
    + Send
    + Sync
    + 'static
    + core::ops::BitAnd<Output = Self>
    + core::ops::BitOr<Output = Self>
    + core::ops::Not<Output = Self>
{
    /// All bits clear (false).
    const NONE: Self;
    /// All bits set (true).
    const ALL: Self;
}

impl LaneBits for u32 {
    const NONE: Self = 0;
    const ALL: Self = u32::MAX;
}

impl LaneBits for u64 {
    const NONE: Self = 0;
    const ALL: Self = u64::MAX;
}

macro_rules! impl_real {
    ($t:ident, $bits:ident, $magic:expr) => {
        impl Scalar for $t {
            type Elem = $t;
            type Mask = bool;
            const LANES: usize = 1;
            #[inline(always)]
            fn splat(x: $t) -> Self {
                x
            }
            #[inline(always)]
            fn min(self, rhs: Self) -> Self {
                if self < rhs {
                    self
                } else {
                    rhs
                }
            }
            #[inline(always)]
            fn max(self, rhs: Self) -> Self {
                if self > rhs {
                    self
                } else {
                    rhs
                }
            }
            #[inline(always)]
            fn minimum(self, rhs: Self) -> Self {
                // IEEE 754-2019 (section 9.6) `minimum`.
                if self < rhs {
                    self
                } else if rhs < self {
                    rhs
                } else if self == rhs {
                    // Equal, zeros of either sign included: -0.0 if either is.
                    if self.is_sign_negative() {
                        self
                    } else {
                        rhs
                    }
                } else {
                    // Unordered: at least one NaN; the sum is NaN.
                    self + rhs
                }
            }
            #[inline(always)]
            fn maximum(self, rhs: Self) -> Self {
                // IEEE 754-2019 (section 9.6) `maximum`.
                if self > rhs {
                    self
                } else if rhs > self {
                    rhs
                } else if self == rhs {
                    if self.is_sign_positive() {
                        self
                    } else {
                        rhs
                    }
                } else {
                    self + rhs
                }
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn mul_add(self, a: Self, b: Self) -> Self {
                <$t>::mul_add(self, a, b)
            }
            #[inline(always)]
            fn lt(self, rhs: Self) -> bool {
                self < rhs
            }
            #[inline(always)]
            fn le(self, rhs: Self) -> bool {
                self <= rhs
            }
            #[inline(always)]
            fn eq_mask(self, rhs: Self) -> bool {
                self == rhs
            }
            #[inline(always)]
            fn select(mask: bool, a: Self, b: Self) -> Self {
                if mask {
                    a
                } else {
                    b
                }
            }
            #[inline(always)]
            fn lane(self, i: usize) -> $t {
                assert!(i == 0, "lane {i} out of range for a scalar");
                self
            }
            #[inline(always)]
            fn is_finite_mask(self) -> bool {
                <$t>::is_finite(self)
            }
        }

        impl Real for $t {
            type Bits = $bits;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const EPSILON: Self = <$t>::EPSILON;
            const INFINITY: Self = <$t>::INFINITY;
            const NEG_INFINITY: Self = <$t>::NEG_INFINITY;
            const NAN: Self = <$t>::NAN;
            const MAX: Self = <$t>::MAX;
            const MIN_POSITIVE: Self = <$t>::MIN_POSITIVE;
            const PI: Self = core::$t::consts::PI;
            const MANTISSA_DIGITS: u32 = <$t>::MANTISSA_DIGITS;
            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn from_i32(x: i32) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_bits(self) -> $bits {
                <$t>::to_bits(self)
            }
            #[inline(always)]
            fn from_bits(bits: $bits) -> Self {
                <$t>::from_bits(bits)
            }
            #[inline(always)]
            fn min_num(self, rhs: Self) -> Self {
                <$t>::min(self, rhs)
            }
            #[inline(always)]
            fn max_num(self, rhs: Self) -> Self {
                <$t>::max(self, rhs)
            }
            #[inline(always)]
            fn powf(self, e: Self) -> Self {
                <$t>::powf(self, e)
            }
            #[inline(always)]
            fn powi(self, e: i32) -> Self {
                <$t>::powi(self, e)
            }
            #[inline(always)]
            fn floor(self) -> Self {
                <$t>::floor(self)
            }
            #[inline(always)]
            fn ceil(self) -> Self {
                <$t>::ceil(self)
            }
            #[inline(always)]
            fn sin(self) -> Self {
                <$t>::sin(self)
            }
            #[inline(always)]
            fn cos(self) -> Self {
                <$t>::cos(self)
            }
            #[inline(always)]
            fn tan(self) -> Self {
                <$t>::tan(self)
            }
            #[inline(always)]
            fn acos(self) -> Self {
                <$t>::acos(self)
            }
            #[inline(always)]
            fn atan2(self, x: Self) -> Self {
                <$t>::atan2(self, x)
            }
            #[inline(always)]
            fn is_nan(self) -> bool {
                <$t>::is_nan(self)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn copysign(self, sign: Self) -> Self {
                <$t>::copysign(self, sign)
            }
            #[inline]
            fn next_up(self) -> Self {
                // IEEE 754 nextUp by bit manipulation.
                if self.is_nan() || self == <$t>::INFINITY {
                    return self;
                }
                let bits = self.to_bits();
                let abs = bits & !(1 << (<$bits>::BITS - 1));
                let next = if abs == 0 {
                    1 // smallest positive subnormal, from either zero
                } else if bits == abs {
                    bits + 1
                } else {
                    bits - 1
                };
                <$t>::from_bits(next)
            }
            #[inline]
            fn next_down(self) -> Self {
                // A positive value is one step down in its bits (+inf's step down is
                // MAX); zero, negatives, -inf and NaN take nextUp's cases.
                if self > 0.0 {
                    return <$t>::from_bits(self.to_bits() - 1);
                }
                -(-self).next_up()
            }
            #[inline(always)]
            fn rsqrt_approx(self) -> Self {
                let half = 0.5 * self;
                let y = <$t>::from_bits(($magic as $bits).wrapping_sub(self.to_bits() >> 1));
                y * (1.5 - half * y * y)
            }
        }
    };
}

impl_real!(f32, u32, 0x5f37_5a86u32);
impl_real!(f64, u64, 0x5fe6_eb50_c7b5_37a9u64);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_max_follow_minps_rule() {
        assert_eq!(Scalar::min(1.0f32, 2.0), 1.0);
        assert!(Scalar::min(1.0f32, f32::NAN).is_nan());
        assert_eq!(Scalar::min(f32::NAN, 1.0f32), 1.0);
        assert_eq!(Scalar::max(f64::NAN, 1.0f64), 1.0);
        assert_eq!(1.0f32.min_num(f32::NAN), 1.0);
    }

    #[test]
    fn minimum_maximum_propagate_nan() {
        for (a, b) in [(1.0f32, f32::NAN), (f32::NAN, 1.0), (f32::NAN, f32::NAN)] {
            assert!(Scalar::minimum(a, b).is_nan());
            assert!(Scalar::maximum(a, b).is_nan());
        }
        assert_eq!(Scalar::minimum(1.0f64, 2.0), 1.0);
        assert_eq!(Scalar::maximum(1.0f64, 2.0), 2.0);
        assert_eq!(Scalar::minimum(f64::NEG_INFINITY, 2.0), f64::NEG_INFINITY);
        for (a, b) in [(0.0f32, -0.0f32), (-0.0, 0.0)] {
            assert!(Scalar::minimum(a, b).is_sign_negative());
            assert!(Scalar::maximum(a, b).is_sign_positive());
        }
    }

    #[test]
    fn next_up_down() {
        assert_eq!(0.0f32.next_up(), f32::from_bits(1));
        assert_eq!((-0.0f32).next_up(), f32::from_bits(1));
        assert_eq!(1.0f64.next_up(), 1.0 + f64::EPSILON);
        assert_eq!(1.0f32.next_down(), 1.0 - f32::EPSILON / 2.0);
        assert_eq!(f32::INFINITY.next_up(), f32::INFINITY);
        assert_eq!((-f32::MIN_POSITIVE).next_up(), -f32::from_bits(0x007f_ffff));
        // Bit for bit the standard library's, on both sides of every special case.
        let f32s = [
            0.0f32,
            -0.0,
            f32::from_bits(1),
            f32::MIN_POSITIVE,
            1.0,
            3.5e7,
            f32::MAX,
            f32::INFINITY,
            f32::NAN,
        ];
        for x in f32s.into_iter().flat_map(|x| [x, -x]) {
            assert_eq!(
                Real::next_down(x).to_bits(),
                f32::next_down(x).to_bits(),
                "{x:e}"
            );
            assert_eq!(
                Real::next_up(x).to_bits(),
                f32::next_up(x).to_bits(),
                "{x:e}"
            );
        }
        let f64s = [
            0.0f64,
            f64::from_bits(1),
            1.0,
            f64::MAX,
            f64::INFINITY,
            f64::NAN,
        ];
        for x in f64s.into_iter().flat_map(|x| [x, -x]) {
            assert_eq!(
                Real::next_down(x).to_bits(),
                f64::next_down(x).to_bits(),
                "{x:e}"
            );
            assert_eq!(
                Real::next_up(x).to_bits(),
                f64::next_up(x).to_bits(),
                "{x:e}"
            );
        }
    }

    #[test]
    fn rsqrt_approx_is_close() {
        let mut worst = 0.0f64;
        for i in 1..2000 {
            let x = i as f64 * 0.37;
            let exact = 1.0 / x.sqrt();
            let e64 = (x.rsqrt_approx() - exact).abs() / exact;
            let e32 = ((x as f32).rsqrt_approx() as f64 - exact).abs() / exact;
            assert!(e64 < 1.8e-3 && e32 < 1.8e-3, "x = {x}: {e64} {e32}");
            worst = worst.max(e64).max(e32);
        }
        // An approximation, not a correctly rounded result.
        assert!(worst > 1e-4, "{worst}");
        assert_eq!(0.0f32.rsqrt_approx() * 0.0, 0.0);
    }
}
