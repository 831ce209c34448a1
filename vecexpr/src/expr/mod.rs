//! Expression nodes: pure data describing a computation, and the traits that tie them
//! together.
//!
//! A node stores its operands and, as a type parameter, the operation; it does no
//! arithmetic. Arithmetic happens only when an expression is evaluated
//! ([`Expr::eval`], [`Vector::assign`](crate::Vector::assign)), one element at a time
//! through [`Expr::coeff`] in the single loop of [`crate::assign`].

pub(crate) mod geometry;

use crate::op::{AbsOp, EqOp, GeOp, GtOp, LeOp, LtOp, MaxOp, MinOp, MulOp, RecipOp, SqrtOp};
use crate::scalar::Real;
use crate::scalar::{Mask, Scalar};
use crate::vector::Vector;
use core::marker::PhantomData;
use generic_array::ArrayLength;
use typenum::Unsigned;
use typenum::U3;

/// A lazy vector-valued expression of dimension `Dim` over the scalar `Scalar`.
///
/// Implemented by borrowed vectors (`&Vector`), by owned vectors wrapped in [`Owned`],
/// and by every node type. Element `i` of the result is `coeff(i)`; evaluation calls it
/// once per element, in one loop, so a tree of element-wise nodes is computed in a single
/// fused pass with no temporaries.
///
/// Non-element-wise operations (`dot`, `sum`, `normalize`, `cross`, `reflect`, ...) are
/// provided methods that evaluate each child exactly once.
pub trait Expr: Sized {
    /// The element type.
    type Scalar: Scalar;
    /// The dimension, a typenum unsigned integer.
    type Dim: ArrayLength;

    /// Element `i` of the result. `i < Dim::USIZE`; larger indices panic.
    fn coeff(&self, i: usize) -> Self::Scalar;

    // ----- evaluation -------------------------------------------------------------------

    /// Computes the expression into a new vector, in one loop over the elements.
    ///
    /// The result lives on the stack; for very long vectors (a million elements) use
    /// [`Expr::eval_boxed`] or [`Vector::assign`] into a boxed vector.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// let (a, b) = (vec3(1.0f32, 2.0, 3.0), vec3(4.0f32, 5.0, 6.0));
    /// assert_eq!((&a * 2.0 + &b).eval(), vec3(6.0, 9.0, 12.0));
    /// ```
    #[inline(always)]
    fn eval(self) -> Vector<Self::Scalar, Self::Dim> {
        Vector::from_generic_array(crate::assign::eval(&self))
    }

    /// Computes the expression into a new heap-allocated vector, never touching the stack
    /// with the whole result.
    #[inline]
    fn eval_boxed(self) -> Box<Vector<Self::Scalar, Self::Dim>> {
        Vector::boxed_from_fn(|i| self.coeff(i))
    }

    // ----- lazy element-wise operations --------------------------------------------------

    /// Element-wise minimum, lazily: NaN where either element is NaN, `-0.0` below
    /// `+0.0` ([`Scalar::minimum`], per lane for packets).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// let a = vec3(1.0f32, 5.0, f32::NAN);
    /// let m = a.min(&vec3(2.0, 3.0, 0.0)).eval();
    /// assert_eq!((m[0], m[1]), (1.0, 3.0));
    /// assert!(m[2].is_nan());
    /// // A scalar operand is broadcast: clamp from above.
    /// assert_eq!(vec3(1.0f32, 5.0, 2.0).min(2.5).eval(), vec3(1.0, 2.5, 2.0));
    /// ```
    #[inline(always)]
    fn min<R: Operand<Self::Scalar, Self::Dim>>(self, rhs: R) -> Binary<Self, R::Expr, MinOp> {
        Binary::new(self, rhs.into_expr())
    }
    /// Element-wise maximum, lazily: NaN where either element is NaN, `+0.0` above
    /// `-0.0` ([`Scalar::maximum`], per lane for packets).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// let relu = vec3(-1.0f64, 0.5, 2.0).max(0.0).eval();
    /// assert_eq!(relu, vec3(0.0, 0.5, 2.0));
    /// assert!(vec3(1.0f64, f64::NAN, 0.0).max(0.0).eval()[1].is_nan());
    /// ```
    #[inline(always)]
    fn max<R: Operand<Self::Scalar, Self::Dim>>(self, rhs: R) -> Binary<Self, R::Expr, MaxOp> {
        Binary::new(self, rhs.into_expr())
    }
    /// Element-wise $|x_i|$, lazily.
    #[inline(always)]
    fn abs(self) -> Unary<Self, AbsOp> {
        Unary::new(self)
    }
    /// Element-wise $\sqrt{x_i}$, lazily.
    #[inline(always)]
    fn sqrt(self) -> Unary<Self, SqrtOp> {
        Unary::new(self)
    }
    /// Element-wise $1 / x_i$, lazily.
    #[inline(always)]
    fn recip(self) -> Unary<Self, RecipOp> {
        Unary::new(self)
    }
    /// Element-wise fused multiply-add $x_i a_i + c_i$ with one rounding, lazily.
    ///
    /// Rust never contracts `a * b + c` into an FMA by itself, because the result differs
    /// in the last bit; this node asks for it explicitly. On a target without hardware FMA
    /// (plain `x86-64`) each element becomes a library call, so build with
    /// `-C target-cpu=x86-64-v3` or newer when using it in hot code.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// let (x, a, c) = (vec3(1.0f64, 2.0, 3.0), vec3(2.0f64, 2.0, 2.0), vec3(0.5f64, 0.5, 0.5));
    /// assert_eq!(x.mul_add(&a, &c).eval(), vec3(2.5, 4.5, 6.5));
    /// // Scalars broadcast: x * 2 + 1.
    /// assert_eq!(x.mul_add(2.0, 1.0).eval(), vec3(3.0, 5.0, 7.0));
    /// // One rounding: (1 + e)(1 - e) - 1 is -e^2 exactly, where the unfused form gives 0.
    /// let e = f64::EPSILON;
    /// let fused = vec3(1.0 + e, 0.0, 0.0).mul_add(1.0 - e, -1.0).eval();
    /// assert_eq!(fused[0], -e * e);
    /// assert_eq!((&vec3(1.0 + e, 0.0, 0.0) * (1.0 - e) - 1.0).eval()[0], 0.0);
    /// ```
    #[inline(always)]
    fn mul_add<A, C>(self, a: A, c: C) -> MulAdd<Self, A::Expr, C::Expr>
    where
        A: Operand<Self::Scalar, Self::Dim>,
        C: Operand<Self::Scalar, Self::Dim>,
    {
        MulAdd {
            a: self,
            b: a.into_expr(),
            c: c.into_expr(),
        }
    }
    /// This expression wrapped in a node that has the operators `+ - * /`, for code
    /// generic over `E: Expr` (or [`ExprOf`]), where the compiler cannot see the
    /// operators of `E` itself. It reads `self` unchanged and costs nothing.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr, ExprOf, Scalar};
    /// fn double_plus_one<T: Scalar, E: ExprOf<T>>(e: E) -> vecexpr::Vector<T, E::Dim> {
    ///     (e.ops() * T::splat_f64(2.0) + T::one()).eval()
    /// }
    /// assert_eq!(double_plus_one(&vec3(1.0f32, 2.0, 3.0)), vec3(3.0, 5.0, 7.0));
    /// ```
    #[inline(always)]
    fn ops(self) -> Conform<Self, Self::Scalar, Self::Dim> {
        Conform::new(self)
    }
    /// Multiplies every element by the scalar `s`, lazily (`self * s` for generic code
    /// where the scalar type is a type parameter).
    #[inline(always)]
    fn scale(self, s: Self::Scalar) -> Binary<Self, Splat<Self::Scalar, Self::Dim>, MulOp> {
        Binary::new(self, Splat::new(s))
    }
    /// Applies `f` to every element, lazily (inside the one evaluation loop, like any
    /// node).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr, Real};
    /// let v = vec3(0.0f32, 1.5, -2.25);
    /// assert_eq!(v.map(Real::floor).eval(), vec3(0.0, 1.0, -3.0));
    /// // A closure in a larger tree: (2 v)^2 + 1.
    /// assert_eq!((&v * 2.0).map(|x| x * x).sum(), 0.0 + 9.0 + 20.25);
    /// ```
    #[inline(always)]
    fn map<F: Fn(Self::Scalar) -> Self::Scalar>(self, f: F) -> Map<Self, F> {
        Map { inner: self, f }
    }
    /// Element-wise $x_i < y_i$, lazily.
    #[inline(always)]
    fn lt<R: Operand<Self::Scalar, Self::Dim>>(self, rhs: R) -> Compare<Self, R::Expr, LtOp> {
        Compare::new(self, rhs.into_expr())
    }
    /// Element-wise $x_i \le y_i$, lazily.
    #[inline(always)]
    fn le<R: Operand<Self::Scalar, Self::Dim>>(self, rhs: R) -> Compare<Self, R::Expr, LeOp> {
        Compare::new(self, rhs.into_expr())
    }
    /// Element-wise $x_i > y_i$, lazily.
    #[inline(always)]
    fn gt<R: Operand<Self::Scalar, Self::Dim>>(self, rhs: R) -> Compare<Self, R::Expr, GtOp> {
        Compare::new(self, rhs.into_expr())
    }
    /// Element-wise $x_i \ge y_i$, lazily.
    #[inline(always)]
    fn ge<R: Operand<Self::Scalar, Self::Dim>>(self, rhs: R) -> Compare<Self, R::Expr, GeOp> {
        Compare::new(self, rhs.into_expr())
    }
    /// Element-wise IEEE $x_i = y_i$, lazily.
    #[inline(always)]
    fn eq_mask<R: Operand<Self::Scalar, Self::Dim>>(self, rhs: R) -> Compare<Self, R::Expr, EqOp> {
        Compare::new(self, rhs.into_expr())
    }

    // ----- reductions: each child is evaluated once ------------------------------------

    /// $\sum_i x_i$.
    ///
    /// Below 64 elements the sum runs left to right; from 64 elements up it uses 32
    /// interleaved partial sums (so it vectorises), which changes the rounding order.
    /// NaN follows IEEE addition: the sum is NaN if any element is NaN, or if it adds
    /// `+∞` and `−∞` (per lane for packets).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr, Vector, typenum::U100};
    /// assert_eq!(vec3(1.0f32, 2.0, 3.0).sum(), 6.0);
    /// assert_eq!((&vec3(1.0f32, 2.0, 3.0) * 2.0).sum(), 12.0);
    /// assert_eq!(Vector::<f64, U100>::from_fn(|i| i as f64).sum(), 4950.0);
    /// assert!(vec3(1.0f32, f32::NAN, 3.0).sum().is_nan());
    /// ```
    #[inline(always)]
    fn sum(self) -> Self::Scalar {
        crate::assign::sum(|i| self.coeff(i), Self::Dim::USIZE)
    }
    /// $\sum_i x_i y_i$ (same summation order as [`Expr::sum`]).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// assert_eq!(vec3(1.0f32, 2.0, 3.0).dot(&vec3(4.0, 5.0, 6.0)), 32.0);
    /// ```
    #[inline(always)]
    fn dot<R: Operand<Self::Scalar, Self::Dim>>(self, rhs: R) -> Self::Scalar {
        let rhs = rhs.into_expr();
        crate::assign::sum(|i| self.coeff(i) * rhs.coeff(i), Self::Dim::USIZE)
    }
    /// $\sum_i x_i^2$.
    #[inline(always)]
    fn length_squared(self) -> Self::Scalar {
        crate::assign::sum(
            |i| {
                let x = self.coeff(i);
                x * x
            },
            Self::Dim::USIZE,
        )
    }
    /// Euclidean length $\sqrt{\sum_i x_i^2}$ (overflows to ∞ when the squares do).
    #[inline(always)]
    fn length(self) -> Self::Scalar {
        self.length_squared().sqrt()
    }
    /// Smallest element: NaN if any element is NaN, `-0.0` below `+0.0`
    /// ([`Scalar::minimum`]; per lane for packets and SIMD lanes).
    ///
    /// # Panics
    /// If the dimension is zero.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// assert_eq!(vec3(3.0f32, -1.0, 2.0).min_element(), -1.0);
    /// assert!(vec3(1.0f32, f32::NAN, 2.0).min_element().is_nan());
    /// ```
    #[inline(always)]
    fn min_element(self) -> Self::Scalar {
        crate::assign::fold1(|i| self.coeff(i), Self::Dim::USIZE, Scalar::minimum)
    }
    /// Largest element: NaN if any element is NaN, `+0.0` above `-0.0`
    /// ([`Scalar::maximum`]; per lane for packets and SIMD lanes).
    ///
    /// # Panics
    /// If the dimension is zero.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr, Packet, Scalar, Vector, typenum::{U3, U4}};
    /// assert_eq!(vec3(3.0f64, -1.0, 2.0).max_element(), 3.0);
    /// // Per lane: lane 2 of the second component is NaN.
    /// type P = Packet<f32, U4>;
    /// let v = Vector::<P, U3>::from_fn(|c| P::from_fn(|l| {
    ///     if c == 1 && l == 2 { f32::NAN } else { (c + l) as f32 }
    /// }));
    /// let m = v.max_element();
    /// assert_eq!((m.lane(0), m.lane(1), m.lane(3)), (2.0, 3.0, 5.0));
    /// assert!(m.lane(2).is_nan());
    /// ```
    #[inline(always)]
    fn max_element(self) -> Self::Scalar {
        crate::assign::fold1(|i| self.coeff(i), Self::Dim::USIZE, Scalar::maximum)
    }
    /// The unit vector $x / \lVert x \rVert$.
    ///
    /// Never NaN for finite input: a zero vector gives the zero vector, and vectors whose
    /// squared length underflows or overflows are rescaled by their largest magnitude
    /// first, so `[1e-30, 0, 0]` and `[1e30, 1e30, 0]` normalise correctly in `f32`.
    /// Infinite or NaN components give NaN. For packets each lane is treated separately.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// assert_eq!(vec3(3.0f32, 0.0, 4.0).normalize(), vec3(0.6, 0.0, 0.8));
    /// assert_eq!(vec3(0.0f32, 0.0, 0.0).normalize(), vec3(0.0, 0.0, 0.0));
    /// ```
    #[inline(always)]
    fn normalize(self) -> Vector<Self::Scalar, Self::Dim> {
        geometry::normalize(self.eval())
    }
    /// An approximate unit vector $x \cdot \widetilde{\mathrm{rsqrt}}(\lVert x \rVert^2)$
    /// using [`Real::rsqrt_approx`] (a magic-constant estimate and one Newton step)
    /// instead of a square root and a division.
    ///
    /// The direction is exact to rounding; the length is $1 \pm 1.8 \cdot 10^{-3}$.
    /// Unlike [`Expr::normalize`] there is no rescaling: the squared length must be a
    /// normal number (the zero vector still gives zero). For speed-versus-accuracy
    /// comparisons; use [`Expr::normalize`] where unit length matters.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// let u = vec3(3.0f32, 0.0, 4.0).normalize_approx();
    /// assert!((u.length() - 1.0).abs() < 2e-3);
    /// assert_eq!(u[1], 0.0);
    /// ```
    #[inline(always)]
    fn normalize_approx(self) -> Vector<Self::Scalar, Self::Dim>
    where
        Self::Scalar: Real,
    {
        let v = self.eval();
        let r = (&v).length_squared().rsqrt_approx();
        (&v).scale(r).eval()
    }
    /// Cross product $x \times y$ of two 3-vectors.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// assert_eq!(vec3(1.0f32, 0.0, 0.0).cross(&vec3(0.0, 1.0, 0.0)), vec3(0.0, 0.0, 1.0));
    /// ```
    #[inline(always)]
    fn cross<R>(self, rhs: R) -> Vector<Self::Scalar, Self::Dim>
    where
        Self::Dim: Dim3,
        R: Operand<Self::Scalar, Self::Dim>,
    {
        geometry::cross(self.eval(), rhs.into_expr().eval())
    }
    /// Reflection of the incident direction `self` about the normal `n`:
    /// $R = I - 2 N (N \cdot I)$. `n` must be unit length; `self` need not be.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// let r = vec3(1.0f32, -1.0, 0.0).reflect(&vec3(0.0, 1.0, 0.0));
    /// assert_eq!(r, vec3(1.0, 1.0, 0.0));
    /// ```
    #[inline(always)]
    fn reflect<R: Operand<Self::Scalar, Self::Dim>>(self, n: R) -> Vector<Self::Scalar, Self::Dim> {
        geometry::reflect(self.eval(), n.into_expr().eval())
    }
    /// Refraction of the unit incident direction `self` through a surface with unit
    /// normal `n` (pointing against `self`), with $\eta = n_1 / n_2$, by Snell's law:
    ///
    /// $k = 1 - \eta^2 (1 - (N \cdot I)^2)$; if $k < 0$ the ray is totally internally
    /// reflected and the result is `None`; otherwise
    /// $T = \eta I - (\eta (N \cdot I) + \sqrt{k}) N$, a unit vector.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Expr};
    /// let n = vec3(0.0f64, 1.0, 0.0);
    /// // Straight through at normal incidence, whatever eta.
    /// assert_eq!(vec3(0.0, -1.0, 0.0).refract(&n, 1.5), Some(vec3(0.0, -1.0, 0.0)));
    /// // Grazing exit from glass: total internal reflection.
    /// let i = vec3(0.8f64, -0.6, 0.0);
    /// assert_eq!(i.refract(&n, 1.5), None);
    /// ```
    #[inline(always)]
    fn refract<R: Operand<Self::Scalar, Self::Dim>>(
        self,
        n: R,
        eta: Self::Scalar,
    ) -> Option<Vector<Self::Scalar, Self::Dim>>
    where
        Self::Scalar: Real,
    {
        let (t, ok) = geometry::refract(self.eval(), n.into_expr().eval(), eta);
        ok.then_some(t)
    }
    /// [`Expr::refract`] for any scalar, packets included: returns the refracted
    /// direction and a mask that is true where refraction happened. Lanes with total
    /// internal reflection hold the zero vector.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{Expr, Mask, Packet, Scalar, Vector, typenum::{U2, U3}};
    /// type P = Packet<f64, U2>;
    /// // Two rays leaving glass (eta = 1.5): lane 0 along the normal, lane 1 at a
    /// // grazing angle beyond the critical one.
    /// let i = Vector::<P, U3>::from([
    ///     P::from_fn(|l| [0.0, 0.8][l]),
    ///     P::from_fn(|l| [-1.0, -0.6][l]),
    ///     P::splat(0.0),
    /// ]);
    /// let n = Vector::<P, U3>::from([P::splat(0.0), P::splat(1.0), P::splat(0.0)]);
    /// let (t, refracted) = i.refract_masked(&n, P::splat(1.5));
    /// assert!(refracted.test(0) && !refracted.test(1));
    /// assert_eq!((t[1].lane(0), t[1].lane(1)), (-1.0, 0.0)); // the TIR lane is zero
    /// ```
    #[inline(always)]
    fn refract_masked<R: Operand<Self::Scalar, Self::Dim>>(
        self,
        n: R,
        eta: Self::Scalar,
    ) -> Refracted<Self::Scalar, Self::Dim> {
        geometry::refract(self.eval(), n.into_expr().eval(), eta)
    }
}

/// Something that can stand as an operand of an expression with scalar `T` and
/// dimension `N`: another expression of the same scalar and dimension, an owned or
/// borrowed [`Vector`], or a single scalar (broadcast to every element).
///
/// Vectors and expressions are operands of any scalar and dimension at the level of the
/// impl; their own scalar and dimension are then checked by [`SameScalar`] and
/// [`SameDim`], whose errors say in plain words which of the two differs. What is left
/// for this trait's own error is something that is neither a vector expression nor a `T`:
/// most often a float literal in code generic over `T`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not a `{T}` or an expression of `{T}`: in code generic over the scalar, write a constant as `T::splat_f64(0.5)`, not `0.5`",
    label = "not an operand of an expression of scalar `{T}`",
    note = "a float literal has a concrete type (`f32` or `f64`), never a type parameter `T`; `Scalar::splat_f64` (or `T::one()`, `T::zero()`) builds a constant of any scalar, packets included",
    note = "with concrete types, the literal must have the vector's scalar type: `&v * 2.0f32` for `f32` vectors"
)]
pub trait Operand<T: Scalar, N: ArrayLength> {
    /// The expression this operand becomes.
    type Expr: Expr<Scalar = T, Dim = N>;
    /// Converts into the expression.
    fn into_expr(self) -> Self::Expr;
}

/// Any vector expression of scalar `T` that can also stand as an operand: the one bound
/// a function generic over expressions needs (see [`crate::guide`]).
///
/// Implemented for every [`Expr`] with scalar `T` that is an [`Operand`] of its own
/// scalar and dimension: borrowed and owned vectors, [`crate::Vec3A`], every node.
/// Reach its operators through [`Expr::ops`].
///
/// # Examples
/// ```
/// use vecexpr::{vec3, Expr, ExprOf, Real};
/// fn rms<T: Real, E: ExprOf<T>>(e: E) -> T {
///     use vecexpr::typenum::Unsigned;
///     (e.length_squared() / T::from_f64(E::Dim::USIZE as f64)).sqrt()
/// }
/// assert_eq!(rms(&vec3(2.0f32, 2.0, 2.0)), 2.0);
/// assert_eq!(rms(&vec3(1.0f64, 2.0, 3.0) * 2.0), (56.0f64 / 3.0).sqrt());
/// ```
pub trait ExprOf<T: Scalar>: Expr<Scalar = T> + Operand<T, <Self as Expr>::Dim> {}

impl<T: Scalar, E> ExprOf<T> for E where E: Expr<Scalar = T> + Operand<T, <E as Expr>::Dim> {}

/// Proof that a dimension `Self` equals `N`: implemented only for `N` itself.
///
/// Every vector and expression operand requires it of its own dimension, so `U3 + U4`
/// fails here with an error that says so.
///
/// ```compile_fail
/// use vecexpr::{Vector, Expr, typenum::{U3, U4}};
/// let (a, b) = (Vector::<f32, U3>::splat(1.0), Vector::<f32, U4>::splat(1.0));
/// let c = (&a + &b).eval();
/// ```
#[diagnostic::on_unimplemented(
    message = "dimension mismatch: both operands must have the same dimension; change one with `extend`, `truncate` or `resize_down`",
    label = "this operand's dimension differs from the other side's",
    note = "the dimensions, as typenum numbers, are `{Self}` and `{N}` (`UInt<UInt<UTerm, B1>, B1>` is U3, `UInt<UInt<UInt<UTerm, B1>, B0>, B0>` is U4)"
)]
pub trait SameDim<N> {}

impl<N: ArrayLength> SameDim<N> for N {}

/// Proof that a scalar type `Self` equals `T`: implemented only for `T` itself, with the
/// (identity) conversion that lets an operand's elements be read as `T`.
///
/// ```compile_fail
/// use vecexpr::{vec3, Expr};
/// let c = (&vec3(1.0f32, 2.0, 3.0) + &vec3(1.0f64, 2.0, 3.0)).eval();
/// ```
#[diagnostic::on_unimplemented(
    message = "scalar type mismatch: an expression of `{T}` cannot take an operand of `{Self}`; convert it first, e.g. `Vector::from_fn(|i| v[i] as {T})`",
    label = "this operand has elements of `{Self}`, the other side `{T}`",
    note = "vecexpr never converts between scalar types implicitly (f32 with f32, f64 with f64, a packet with the same packet)"
)]
pub trait SameScalar<T> {
    /// The value as `T` (the identity).
    fn same(self) -> T;
}

impl<T: Scalar> SameScalar<T> for T {
    #[inline(always)]
    fn same(self) -> T {
        self
    }
}

/// Every expression is a source for the evaluation loops of [`crate::assign`].
impl<E: Expr> crate::assign::Source for E {
    type Item = E::Scalar;
    #[inline(always)]
    fn at(&self, i: usize) -> E::Scalar {
        self.coeff(i)
    }
}

/// Proof that a dimension is 3, for [`Expr::cross`].
///
/// ```compile_fail
/// use vecexpr::{vec4, Expr};
/// let c = vec4(1.0f32, 0.0, 0.0, 0.0).cross(&vec4(0.0f32, 1.0, 0.0, 0.0));
/// ```
#[diagnostic::on_unimplemented(
    message = "`cross` is defined for 3-vectors only; `truncate()` a 4-vector to 3 first, or use the 2-D `perp_dot`-style `a[0] * b[1] - a[1] * b[0]`",
    label = "this expression's dimension is `{Self}`, not U3",
    note = "`UInt<UInt<UTerm, B1>, B1>` is U3"
)]
pub trait Dim3: ArrayLength {}

impl Dim3 for U3 {}

/// The result of [`Expr::refract_masked`]: the refracted directions and the mask of
/// lanes that refracted (false where totally internally reflected).
pub type Refracted<T, N> = (Vector<T, N>, <T as Scalar>::Mask);

/// A lazy mask-valued expression (element-wise comparisons and their combinations),
/// consumed by [`crate::select`].
pub trait MaskExpr: Sized {
    /// The element mask type (`bool` or a packet mask).
    type Mask: Mask;
    /// The dimension.
    type Dim: ArrayLength;
    /// Element `i` of the mask.
    fn mask(&self, i: usize) -> Self::Mask;

    /// Element-wise and, lazily.
    #[inline(always)]
    fn and<R: MaskExpr<Mask = Self::Mask, Dim = Self::Dim>>(self, rhs: R) -> MaskAnd<Self, R> {
        MaskAnd { lhs: self, rhs }
    }
    /// Element-wise or, lazily.
    #[inline(always)]
    fn or<R: MaskExpr<Mask = Self::Mask, Dim = Self::Dim>>(self, rhs: R) -> MaskOr<Self, R> {
        MaskOr { lhs: self, rhs }
    }
    /// Element-wise not, lazily.
    #[inline(always)]
    fn not(self) -> MaskNot<Self> {
        MaskNot { inner: self }
    }
    /// Are all elements (all lanes) true?
    #[inline]
    fn all(&self) -> bool {
        (0..Self::Dim::USIZE).all(|i| self.mask(i).all())
    }
    /// Is any element (any lane) true?
    #[inline]
    fn any(&self) -> bool {
        (0..Self::Dim::USIZE).any(|i| self.mask(i).any())
    }
    /// Evaluates into a vector of masks.
    #[inline]
    fn eval(self) -> Vector<Self::Mask, Self::Dim> {
        Vector::from_fn(|i| self.mask(i))
    }
}

/// A scalar broadcast to every element: the right operand of `v * 2.0`.
#[must_use = "expressions are lazy: call .eval() or assign them to compute"]
#[derive(Clone, Copy, Debug)]
pub struct Splat<T, N> {
    pub(crate) value: T,
    pub(crate) dim: PhantomData<N>,
}

impl<T, N> Splat<T, N> {
    /// A broadcast of `value`.
    #[inline(always)]
    pub fn new(value: T) -> Self {
        Self {
            value,
            dim: PhantomData,
        }
    }
}

/// An owned vector used as a leaf (`a + b` where `a` and `b` are moved in).
#[must_use = "expressions are lazy: call .eval() or assign them to compute"]
#[derive(Clone, Debug)]
pub struct Owned<T, N: ArrayLength>(pub Vector<T, N>);

impl<T: Copy, N: ArrayLength> Copy for Owned<T, N> where Vector<T, N>: Copy {}

/// An operand whose scalar and dimension were checked to be `T` and `N`
/// ([`SameScalar`], [`SameDim`]): reads the inner expression unchanged. Operators wrap
/// their right operand in it; it costs nothing after inlining.
#[must_use = "expressions are lazy: call .eval() or assign them to compute"]
#[derive(Clone, Copy, Debug)]
pub struct Conform<E, T, N> {
    pub(crate) inner: E,
    pub(crate) ty: PhantomData<(T, N)>,
}

impl<E, T, N> Conform<E, T, N> {
    /// Wraps `inner`.
    #[inline(always)]
    pub fn new(inner: E) -> Self {
        Self {
            inner,
            ty: PhantomData,
        }
    }
}

/// An element-wise binary operation `O(lhs, rhs)`: `+ - * /`, `min`, `max`.
#[must_use = "expressions are lazy: call .eval() or assign them to compute"]
#[derive(Clone, Copy, Debug)]
pub struct Binary<L, R, O> {
    pub(crate) lhs: L,
    pub(crate) rhs: R,
    pub(crate) op: PhantomData<O>,
}

impl<L, R, O> Binary<L, R, O> {
    /// The node `O(lhs, rhs)`.
    #[inline(always)]
    pub fn new(lhs: L, rhs: R) -> Self {
        Self {
            lhs,
            rhs,
            op: PhantomData,
        }
    }
}

/// An element-wise unary operation `O(inner)`: `-`, `abs`, `sqrt`, `recip`.
#[must_use = "expressions are lazy: call .eval() or assign them to compute"]
#[derive(Clone, Copy, Debug)]
pub struct Unary<E, O> {
    pub(crate) inner: E,
    pub(crate) op: PhantomData<O>,
}

impl<E, O> Unary<E, O> {
    /// The node `O(inner)`.
    #[inline(always)]
    pub fn new(inner: E) -> Self {
        Self {
            inner,
            op: PhantomData,
        }
    }
}

/// Fused multiply-add $a \cdot b + c$ per element, with one rounding.
#[must_use = "expressions are lazy: call .eval() or assign them to compute"]
#[derive(Clone, Copy, Debug)]
pub struct MulAdd<A, B, C> {
    pub(crate) a: A,
    pub(crate) b: B,
    pub(crate) c: C,
}

/// Per-element choice `if mask { a } else { b }`.
#[must_use = "expressions are lazy: call .eval() or assign them to compute"]
#[derive(Clone, Copy, Debug)]
pub struct Select<M, A, B> {
    pub(crate) mask: M,
    pub(crate) a: A,
    pub(crate) b: B,
}

/// A user function applied to every element.
#[must_use = "expressions are lazy: call .eval() or assign them to compute"]
#[derive(Clone, Copy)]
pub struct Map<E, F> {
    pub(crate) inner: E,
    pub(crate) f: F,
}

/// An element-wise comparison producing a mask.
#[must_use = "expressions are lazy: call .eval() or use them in select"]
#[derive(Clone, Copy, Debug)]
pub struct Compare<L, R, O> {
    pub(crate) lhs: L,
    pub(crate) rhs: R,
    pub(crate) op: PhantomData<O>,
}

impl<L, R, O> Compare<L, R, O> {
    /// The comparison node `O(lhs, rhs)`.
    #[inline(always)]
    pub fn new(lhs: L, rhs: R) -> Self {
        Self {
            lhs,
            rhs,
            op: PhantomData,
        }
    }
}

/// Element-wise `lhs and rhs` on masks.
#[must_use = "expressions are lazy: call .eval() or use them in select"]
#[derive(Clone, Copy, Debug)]
pub struct MaskAnd<L, R> {
    pub(crate) lhs: L,
    pub(crate) rhs: R,
}

/// Element-wise `lhs or rhs` on masks.
#[must_use = "expressions are lazy: call .eval() or use them in select"]
#[derive(Clone, Copy, Debug)]
pub struct MaskOr<L, R> {
    pub(crate) lhs: L,
    pub(crate) rhs: R,
}

/// Element-wise `not inner` on masks.
#[must_use = "expressions are lazy: call .eval() or use them in select"]
#[derive(Clone, Copy, Debug)]
pub struct MaskNot<E> {
    pub(crate) inner: E,
}

/// Per-element choice between two expressions: `if mask[i] { a[i] } else { b[i] }`.
///
/// For packets the choice is per lane. Both `a` and `b` are evaluated for every element
/// (no branches), which is what SIMD blends do.
///
/// # Examples
/// ```
/// use vecexpr::{select, vec3, Expr};
/// let a = vec3(1.0f32, -2.0, 3.0);
/// let zero = vec3(0.0f32, 0.0, 0.0);
/// let relu = select(a.gt(&zero), &a, &zero).eval();
/// assert_eq!(relu, vec3(1.0, 0.0, 3.0));
/// ```
#[inline(always)]
pub fn select<T, N, M, A, B>(mask: M, a: A, b: B) -> Select<M, A::Expr, B::Expr>
where
    T: Scalar,
    N: ArrayLength,
    M: MaskExpr<Mask = T::Mask, Dim = N>,
    A: Operand<T, N>,
    B: Operand<T, N>,
{
    Select {
        mask,
        a: a.into_expr(),
        b: b.into_expr(),
    }
}
