//! [`Vec3A`]: a single `f32` 3-vector padded to 16 bytes, computed in one SIMD register.
//!
//! `Vector<f32, U3>` is 12 bytes: loading it takes an 8-byte and a 4-byte load and its
//! `z` lane is computed with scalar instructions. `Vec3A` stores `[x, y, z, 0]` aligned to
//! 16 bytes, so a load, an operation and a store are one instruction each (the layout of
//! glam's `Vec3A`). Its kernels compute exactly what the same kernels of
//! `Vector<f32, U3>` compute (same operations in the same order), so switching storage
//! never changes a result bit.

use crate::expr::{Expr, Operand};
use crate::scalar::Scalar;
use crate::simd::Lanes4;
use crate::vector::Vector;
use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Index, Mul, MulAssign, Neg, Sub, SubAssign};
use typenum::U3;

/// The register type of the kernels: an SSE register on x86-64, an array packet elsewhere.
#[cfg(target_arch = "x86_64")]
type Reg = crate::simd::F32x4;
#[cfg(not(target_arch = "x86_64"))]
type Reg = crate::packet::Packet<f32, typenum::U4>;

/// The few register operations beyond [`Scalar`] that the kernels need.
trait RegExt: Scalar<Elem = f32> {
    fn load(a: &Lanes4) -> Self;
    fn store(self) -> Lanes4;
    /// $(x_0 + x_1) + x_2$ in lane 0 (and 1).
    fn sum3_low(self) -> Self;
    /// Lane 0 in every lane.
    fn splat0(self) -> Self;
    /// `[y, z, x, w]`.
    fn yzx(self) -> Self;
    /// `[z, x, y, w]`.
    fn zxy(self) -> Self;
    /// The bits of lane 0.
    fn lane0_bits(self) -> u32;
}

#[cfg(target_arch = "x86_64")]
impl RegExt for Reg {
    #[inline(always)]
    fn load(a: &Lanes4) -> Self {
        Self::load_aligned(a)
    }
    #[inline(always)]
    fn store(self) -> Lanes4 {
        self.store_aligned()
    }
    #[inline(always)]
    fn sum3_low(self) -> Self {
        self.hsum3_low()
    }
    #[inline(always)]
    fn splat0(self) -> Self {
        self.shuffle::<0>()
    }
    #[inline(always)]
    fn yzx(self) -> Self {
        self.shuffle::<0b11_00_10_01>()
    }
    #[inline(always)]
    fn zxy(self) -> Self {
        self.shuffle::<0b11_01_00_10>()
    }
    #[inline(always)]
    fn lane0_bits(self) -> u32 {
        self.bits0()
    }
}

#[cfg(not(target_arch = "x86_64"))]
impl RegExt for Reg {
    #[inline(always)]
    fn load(a: &Lanes4) -> Self {
        Self::from_fn(|i| a.0[i])
    }
    #[inline(always)]
    fn store(self) -> Lanes4 {
        Lanes4(core::array::from_fn(|i| self.as_slice()[i]))
    }
    #[inline(always)]
    fn sum3_low(self) -> Self {
        let x = self.as_slice();
        Self::splat((x[0] + x[1]) + x[2])
    }
    #[inline(always)]
    fn splat0(self) -> Self {
        Self::splat(self.as_slice()[0])
    }
    #[inline(always)]
    fn yzx(self) -> Self {
        let x = self.as_slice();
        Self::from_fn(|i| x[[1, 2, 0, 3][i]])
    }
    #[inline(always)]
    fn zxy(self) -> Self {
        let x = self.as_slice();
        Self::from_fn(|i| x[[2, 0, 1, 3][i]])
    }
    #[inline(always)]
    fn lane0_bits(self) -> u32 {
        self.as_slice()[0].to_bits()
    }
}

/// A 3-vector of `f32` padded to 16 bytes and aligned to 16: `[x, y, z, 0]` in one SIMD
/// register.
///
/// Use it for single vectors in hot code (one ray, one normal); use `Vector<f32, U3>`
/// where 12-byte storage matters (large arrays of points) and packets
/// (`Vector<PacketF32x8, U3>`, or the registers of [`crate::simd`]) for many vectors at
/// once.
///
/// - By value, the operators are eager and one instruction each: `a + b`, `a * 2.0`,
///   `-a` give a `Vec3A` (as in glam).
/// - By reference, the operators are lazy like those of `&Vector<f32, U3>`: `&a * 2.0 + &b`
///   builds the same tree (holding a copy of `a`), mixes with vectors, and `Vec3A` works in
///   every generic function over `Expr<Scalar = f32, Dim = U3>`; [`Vec3A::from_expr`]
///   evaluates a tree back into a `Vec3A`.
/// - The kernels ([`dot`](Vec3A::dot), [`cross`](Vec3A::cross),
///   [`normalize`](Vec3A::normalize), [`reflect`](Vec3A::reflect), ...) are methods that
///   compute in the register and give, bit for bit, what the same method of
///   `Vector<f32, U3>` gives.
///
/// The fourth lane is zero after construction; operations may leave anything there
/// (`a / 0.0` puts NaN in it), but nothing ever reads it: comparisons, formatting,
/// indexing and every kernel see `x`, `y`, `z` only.
///
/// # Examples
/// ```
/// use vecexpr::{vec3, Expr, Vec3A};
/// let i = Vec3A::new(1.0, -1.0, 0.0);
/// let n = Vec3A::Y;
/// assert_eq!(i.reflect(n), Vec3A::new(1.0, 1.0, 0.0));
/// // The same bits as the 12-byte vector:
/// let v = vec3(1.0f32, -1.0, 0.0);
/// assert_eq!(i.reflect(n).to_vector(), v.reflect(&vec3(0.0, 1.0, 0.0)));
/// // By reference it is a lazy expression like any vector.
/// let r = Vec3A::from_expr(&i * 2.0 + &v);
/// assert_eq!(r, Vec3A::new(3.0, -3.0, 0.0));
/// assert_eq!(core::mem::size_of::<Vec3A>(), 16);
/// ```
#[derive(Clone, Copy, Default)]
#[repr(transparent)]
pub struct Vec3A(Lanes4);

impl Vec3A {
    /// All zeros.
    pub const ZERO: Self = Self::new(0.0, 0.0, 0.0);
    /// All ones.
    pub const ONE: Self = Self::new(1.0, 1.0, 1.0);
    /// The unit `x` axis.
    pub const X: Self = Self::new(1.0, 0.0, 0.0);
    /// The unit `y` axis.
    pub const Y: Self = Self::new(0.0, 1.0, 0.0);
    /// The unit `z` axis.
    pub const Z: Self = Self::new(0.0, 0.0, 1.0);

    /// The vector `(x, y, z)`.
    ///
    /// # Examples
    /// ```
    /// let v = vecexpr::Vec3A::new(1.0, 2.0, 3.0);
    /// assert_eq!((v.x(), v.y(), v.z()), (1.0, 2.0, 3.0));
    /// ```
    #[inline(always)]
    pub const fn new(x: f32, y: f32, z: f32) -> Self {
        Self(Lanes4([x, y, z, 0.0]))
    }

    /// Every component set to `v`.
    #[inline(always)]
    pub const fn splat(v: f32) -> Self {
        Self::new(v, v, v)
    }

    /// Component 0.
    #[inline(always)]
    pub fn x(self) -> f32 {
        self.0 .0[0]
    }
    /// Component 1.
    #[inline(always)]
    pub fn y(self) -> f32 {
        self.0 .0[1]
    }
    /// Component 2.
    #[inline(always)]
    pub fn z(self) -> f32 {
        self.0 .0[2]
    }

    /// The components as an array.
    #[inline(always)]
    pub fn to_array(self) -> [f32; 3] {
        [self.x(), self.y(), self.z()]
    }

    /// The 12-byte vector with the same components.
    #[inline(always)]
    pub fn to_vector(self) -> Vector<f32, U3> {
        Vector::from(self.to_array())
    }

    /// Evaluates any expression of three `f32` (a lazy tree, a `Vector<f32, U3>`, a
    /// borrowed `Vec3A`) into a `Vec3A`.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Vec3A};
    /// let a = Vec3A::new(1.0, 2.0, 3.0);
    /// let b = vec3(1.0f32, 1.0, 1.0);
    /// assert_eq!(Vec3A::from_expr(&a - &b), Vec3A::new(0.0, 1.0, 2.0));
    /// ```
    #[inline(always)]
    pub fn from_expr<E: Operand<f32, U3>>(e: E) -> Self {
        let e = e.into_expr();
        Self::new(e.coeff(0), e.coeff(1), e.coeff(2))
    }

    #[inline(always)]
    fn reg(self) -> Reg {
        Reg::load(&self.0)
    }

    #[inline(always)]
    fn from_reg(r: Reg) -> Self {
        Self(r.store())
    }

    /// $x \cdot y$ in lane 0, summed left to right as `Vector::dot` does.
    #[inline(always)]
    fn dot_reg(a: Reg, b: Reg) -> Reg {
        (a * b).sum3_low()
    }

    /// $x_0 y_0 + x_1 y_1 + x_2 y_2$, summed left to right (as [`Expr::dot`]).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::Vec3A;
    /// assert_eq!(Vec3A::new(1.0, 2.0, 3.0).dot(Vec3A::new(4.0, 5.0, 6.0)), 32.0);
    /// ```
    #[inline(always)]
    pub fn dot(self, rhs: Self) -> f32 {
        Self::dot_reg(self.reg(), rhs.reg()).lane(0)
    }

    /// $\lVert x \rVert^2$.
    #[inline(always)]
    pub fn length_squared(self) -> f32 {
        self.dot(self)
    }

    /// $\lVert x \rVert$ (overflows to ∞ when the squares do).
    #[inline(always)]
    pub fn length(self) -> f32 {
        self.length_squared().sqrt()
    }

    /// The cross product $x \times y$, with the component formula of [`Expr::cross`].
    ///
    /// # Examples
    /// ```
    /// use vecexpr::Vec3A;
    /// assert_eq!(Vec3A::X.cross(Vec3A::Y), Vec3A::Z);
    /// ```
    #[inline(always)]
    pub fn cross(self, rhs: Self) -> Self {
        let (a, b) = (self.reg(), rhs.reg());
        // (a_y b_z - a_z b_y, a_z b_x - a_x b_z, a_x b_y - a_y b_x).
        Self::from_reg(a.yzx() * b.zxy() - a.zxy() * b.yzx())
    }

    /// The unit vector $x / \lVert x \rVert$ with the rules of [`Expr::normalize`]: the
    /// zero vector gives zero, tiny and huge vectors are rescaled first (out of line,
    /// rarely taken), infinite or NaN components give NaN. The result equals
    /// `self.to_vector().normalize()` bit for bit.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::Vec3A;
    /// assert_eq!(Vec3A::new(3.0, 0.0, 4.0).normalize(), Vec3A::new(0.6, 0.0, 0.8));
    /// assert_eq!(Vec3A::ZERO.normalize(), Vec3A::ZERO);
    /// assert_eq!(Vec3A::new(1e-30, 0.0, 0.0).normalize(), Vec3A::X);
    /// ```
    #[inline(always)]
    pub fn normalize(self) -> Self {
        let v = self.reg();
        let l2 = Self::dot_reg(v, v);
        // Fast path: the squared length is a normal, finite number. Its bits minus those
        // of MIN_POSITIVE are then below MAX - MIN_POSITIVE as unsigned integers; zero,
        // subnormals, infinity and NaN all fall outside (zero and subnormals wrap around).
        let bits = l2.lane0_bits();
        let min = f32::MIN_POSITIVE.to_bits();
        if bits.wrapping_sub(min) <= f32::MAX.to_bits() - min {
            // x * (1 / sqrt(l2)), as Vector::normalize computes it.
            let inv = l2.sqrt().recip().splat0();
            return Self::from_reg(v * inv);
        }
        Self::from_reg(normalize_slow(v))
    }

    /// The unit vector $x / \sqrt{x \cdot x}$ without the range test of
    /// [`normalize`](Vec3A::normalize): one square root and one division of every
    /// component by it, the formula (and the instructions) of glam's `Vec3A::normalize`.
    /// Each component is `c / self.length()` correctly rounded, so it may differ from
    /// `normalize` (which multiplies by the reciprocal length, as every vecexpr vector
    /// does) in the last bit. Where the squared length is not a normal number the result
    /// is what the formula gives: NaN for the zero vector, infinities or NaN when the
    /// squared length underflows, zeros when it overflows. For hot paths whose vectors are
    /// known to be in range (components between about $10^{-19}$ and $10^{19}$ in
    /// magnitude: the difference of two distinct points of a scene, a primitive's normal).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::Vec3A;
    /// let v = Vec3A::new(3.0, 0.0, 4.0);
    /// assert_eq!(v.normalize_fast(), Vec3A::new(0.6, 0.0, 0.8));
    /// assert_eq!(v.normalize_fast().x(), 3.0 / v.length());
    /// assert!(Vec3A::ZERO.normalize_fast().x().is_nan());
    /// assert_eq!(Vec3A::ZERO.normalize(), Vec3A::ZERO);
    /// ```
    #[inline(always)]
    pub fn normalize_fast(self) -> Self {
        let v = self.reg();
        let len = Self::dot_reg(v, v).sqrt().splat0();
        Self::from_reg(v / len)
    }

    /// The reflection $R = I - 2 N (N \cdot I)$ of the incident direction `self` about
    /// the unit normal `n` (as [`Expr::reflect`], bit for bit).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::Vec3A;
    /// let r = Vec3A::new(1.0, -1.0, 0.0).reflect(Vec3A::Y);
    /// assert_eq!(r, Vec3A::new(1.0, 1.0, 0.0));
    /// ```
    #[inline(always)]
    pub fn reflect(self, n: Self) -> Self {
        let (i, n) = (self.reg(), n.reg());
        let d = Self::dot_reg(n, i);
        let d2 = (d + d).splat0();
        Self::from_reg(i - n * d2)
    }

    /// Element-wise minimum: NaN where either element is NaN, `-0.0` below `+0.0`
    /// ([`Scalar::minimum`], the rule of every minimum on vectors).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::Vec3A;
    /// let m = Vec3A::new(1.0, 5.0, f32::NAN).min(Vec3A::splat(2.0));
    /// assert_eq!((m.x(), m.y()), (1.0, 2.0));
    /// assert!(m.z().is_nan());
    /// ```
    #[inline(always)]
    pub fn min(self, rhs: Self) -> Self {
        Self::from_reg(Scalar::minimum(self.reg(), rhs.reg()))
    }

    /// Element-wise maximum: NaN where either element is NaN, `+0.0` above `-0.0`
    /// ([`Scalar::maximum`]).
    #[inline(always)]
    pub fn max(self, rhs: Self) -> Self {
        Self::from_reg(Scalar::maximum(self.reg(), rhs.reg()))
    }

    /// Element-wise absolute value.
    #[inline(always)]
    pub fn abs(self) -> Self {
        Self::from_reg(Scalar::abs(self.reg()))
    }
}

/// The rare path of [`Vec3A::normalize`]: the 12-byte vector's rescaling, out of line.
/// On x86-64 it has the C calling convention, which passes and returns the register in
/// `xmm0` (the Rust one passes SIMD values through memory), so the hot path keeps the
/// vector in a register.
#[cfg(target_arch = "x86_64")]
#[cold]
#[inline(never)]
// Called from Rust only: the C convention is used for its register passing, not for FFI.
#[allow(improper_ctypes_definitions)]
extern "C" fn normalize_slow(v: Reg) -> Reg {
    Vec3A::from(crate::expr::geometry::normalize(
        Vec3A::from_reg(v).to_vector(),
    ))
    .reg()
}

/// The rare path of [`Vec3A::normalize`]: the 12-byte vector's rescaling, out of line.
#[cfg(not(target_arch = "x86_64"))]
#[cold]
#[inline(never)]
fn normalize_slow(v: Reg) -> Reg {
    Vec3A::from(crate::expr::geometry::normalize(
        Vec3A::from_reg(v).to_vector(),
    ))
    .reg()
}

impl PartialEq for Vec3A {
    /// Compares `x`, `y`, `z` (IEEE: NaN is unequal, `-0.0 == 0.0`); the padding lane is
    /// ignored.
    #[inline]
    fn eq(&self, other: &Self) -> bool {
        self.to_array() == other.to_array()
    }
}

impl fmt::Debug for Vec3A {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.to_array()).finish()
    }
}

impl fmt::Display for Vec3A {
    /// `[x, y, z]`, each component with the formatter's options.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.to_vector(), f)
    }
}

impl Index<usize> for Vec3A {
    type Output = f32;
    /// Component `i`.
    ///
    /// # Panics
    /// If `i > 2`.
    #[inline(always)]
    fn index(&self, i: usize) -> &f32 {
        &self.0 .0[..3][i]
    }
}

impl From<Vector<f32, U3>> for Vec3A {
    #[inline(always)]
    fn from(v: Vector<f32, U3>) -> Self {
        Self::new(v[0], v[1], v[2])
    }
}

impl From<Vec3A> for Vector<f32, U3> {
    #[inline(always)]
    fn from(v: Vec3A) -> Self {
        v.to_vector()
    }
}

impl From<[f32; 3]> for Vec3A {
    #[inline(always)]
    fn from(a: [f32; 3]) -> Self {
        Self::new(a[0], a[1], a[2])
    }
}

impl From<Vec3A> for [f32; 3] {
    #[inline(always)]
    fn from(v: Vec3A) -> Self {
        v.to_array()
    }
}

// ----- eager operators by value: one register operation each ----------------------------

macro_rules! eager_ops {
    ($tr:ident, $f:ident, $atr:ident, $af:ident, $op:tt) => {
        impl $tr for Vec3A {
            type Output = Vec3A;
            #[inline(always)]
            fn $f(self, rhs: Vec3A) -> Vec3A {
                Vec3A::from_reg(self.reg() $op rhs.reg())
            }
        }
        impl $tr<f32> for Vec3A {
            type Output = Vec3A;
            #[inline(always)]
            fn $f(self, rhs: f32) -> Vec3A {
                Vec3A::from_reg(self.reg() $op Reg::splat(rhs))
            }
        }
        impl $tr<Vec3A> for f32 {
            type Output = Vec3A;
            #[inline(always)]
            fn $f(self, rhs: Vec3A) -> Vec3A {
                Vec3A::from_reg(Reg::splat(self) $op rhs.reg())
            }
        }
        impl $atr for Vec3A {
            #[inline(always)]
            fn $af(&mut self, rhs: Vec3A) {
                *self = *self $op rhs;
            }
        }
        impl $atr<f32> for Vec3A {
            #[inline(always)]
            fn $af(&mut self, rhs: f32) {
                *self = *self $op rhs;
            }
        }
    };
}
eager_ops!(Add, add, AddAssign, add_assign, +);
eager_ops!(Sub, sub, SubAssign, sub_assign, -);
eager_ops!(Mul, mul, MulAssign, mul_assign, *);
eager_ops!(Div, div, DivAssign, div_assign, /);

impl Neg for Vec3A {
    type Output = Vec3A;
    #[inline(always)]
    fn neg(self) -> Vec3A {
        Vec3A::from_reg(-self.reg())
    }
}

// ----- in lazy trees: a leaf of three f32 --------------------------------------------------
// `Vec3A` itself is the `Expr` (it is `Copy`), not `&Vec3A`: a method call on a `&Vec3A`
// then reaches the register kernels above instead of the lazy `Expr` methods.

impl Expr for Vec3A {
    type Scalar = f32;
    type Dim = U3;
    #[inline(always)]
    fn coeff(&self, i: usize) -> f32 {
        self.0 .0[..3][i]
    }
}

/// `&a` as an operand copies the 16 bytes into the tree.
impl<T: Scalar, N: generic_array::ArrayLength> Operand<T, N> for &Vec3A
where
    f32: crate::expr::SameScalar<T>,
    U3: crate::expr::SameDim<N>,
{
    type Expr = crate::expr::Conform<Vec3A, T, N>;
    #[inline(always)]
    fn into_expr(self) -> Self::Expr {
        crate::expr::Conform::new(*self)
    }
}

#[cfg(test)]
mod tests {
    use super::Vec3A;
    use crate::{vec3, Expr};

    #[test]
    fn normalize_fast_is_each_component_over_the_length() {
        // A deterministic sweep over signs and magnitudes from 1e-15 to 1e15 (squared
        // lengths inside the normal range): each component is `c / length()` bit for
        // bit, within one ulp of `normalize`.
        let mut state = 0x2545_f491_u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state
        };
        for _ in 0..20_000 {
            let e = (next() % 31) as i32 - 15;
            let c = |r: u32| ((r % 2001) as f32 / 1000.0 - 1.0) * 10f32.powi(e);
            let v = Vec3A::new(c(next()), c(next()), c(next()));
            if v == Vec3A::ZERO {
                continue;
            }
            let fast = v.normalize_fast().to_array();
            let plain = v.to_array().map(|c| c / v.length());
            assert_eq!(fast.map(f32::to_bits), plain.map(f32::to_bits), "{v:?}");
            for (f, r) in fast.iter().zip(v.normalize().to_array()) {
                assert!(
                    (f.to_bits() as i64 - r.to_bits() as i64).abs() <= 1,
                    "{v:?}"
                );
            }
        }
        // Outside the range it is the formula: zero gives NaN, overflow zeros.
        assert!(Vec3A::ZERO
            .normalize_fast()
            .to_array()
            .iter()
            .all(|x| x.is_nan()));
        assert_eq!(Vec3A::new(1e30, 0.0, 0.0).normalize_fast(), Vec3A::ZERO);
    }

    #[test]
    fn kernels_match_vector_bits() {
        let cases = [
            (vec3(0.3f32, -0.7, 0.2), vec3(0.0f32, 0.6, 0.8)),
            (vec3(1e-30f32, 0.0, 0.0), vec3(1.0f32, 0.0, 0.0)),
            (vec3(1e30f32, -1e30, 1e29), vec3(0.5f32, 0.5, 0.70710677)),
            (vec3(-0.0f32, 0.0, -0.0), vec3(-0.0f32, -0.0, 0.0)),
            (vec3(f32::NAN, 1.0, 2.0), vec3(0.0f32, 1.0, 0.0)),
            (vec3(f32::INFINITY, 1.0, 2.0), vec3(1.0f32, 2.0, 3.0)),
        ];
        for (a, b) in cases {
            let (va, vb) = (Vec3A::from(a), Vec3A::from(b));
            let bits =
                |v: crate::Vec3<f32>| v.as_slice().iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(va.normalize().to_vector()),
                bits(a.normalize()),
                "{a:?}"
            );
            assert_eq!(
                bits(va.reflect(vb).to_vector()),
                bits(a.reflect(&b)),
                "{a:?}"
            );
            assert_eq!(bits(va.cross(vb).to_vector()), bits(a.cross(&b)), "{a:?}");
            assert_eq!(va.dot(vb).to_bits(), a.dot(&b).to_bits(), "{a:?}");
        }
    }
}
