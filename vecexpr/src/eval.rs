//! Evaluators: how each node computes element `i`, how each node, vector and scalar
//! becomes an operand, and the vector methods that take an expression (`assign`,
//! `update`, `approx_eq`). One impl per node type; the evaluation loops are in
//! [`crate::assign`].

use crate::expr::{
    Binary, Compare, Conform, Expr, Map, MaskAnd, MaskExpr, MaskNot, MaskOr, MulAdd, Operand,
    Owned, SameDim, SameScalar, Select, Splat, Unary,
};
use crate::op::{BinaryOp, CompareOp, UnaryOp};
use crate::packet::Packet;
use crate::scalar::{Mask, Real, Scalar};
use crate::vector::{approx_eq_scalar, Vector};
use generic_array::ArrayLength;

impl<T: Scalar, N: ArrayLength> Expr for &Vector<T, N> {
    type Scalar = T;
    type Dim = N;
    #[inline(always)]
    fn coeff(&self, i: usize) -> T {
        self.as_slice()[i]
    }
}

impl<T: Scalar, N: ArrayLength> Expr for Owned<T, N> {
    type Scalar = T;
    type Dim = N;
    #[inline(always)]
    fn coeff(&self, i: usize) -> T {
        self.0.as_slice()[i]
    }
}

impl<T: Scalar, N: ArrayLength> Expr for Splat<T, N> {
    type Scalar = T;
    type Dim = N;
    #[inline(always)]
    fn coeff(&self, _i: usize) -> T {
        self.value
    }
}

impl<L, R, O> Expr for Binary<L, R, O>
where
    L: Expr,
    R: Expr<Scalar = L::Scalar, Dim = L::Dim>,
    O: BinaryOp,
{
    type Scalar = L::Scalar;
    type Dim = L::Dim;
    #[inline(always)]
    fn coeff(&self, i: usize) -> L::Scalar {
        O::apply(self.lhs.coeff(i), self.rhs.coeff(i))
    }
}

impl<E: Expr, O: UnaryOp> Expr for Unary<E, O> {
    type Scalar = E::Scalar;
    type Dim = E::Dim;
    #[inline(always)]
    fn coeff(&self, i: usize) -> E::Scalar {
        O::apply(self.inner.coeff(i))
    }
}

impl<A, B, C> Expr for MulAdd<A, B, C>
where
    A: Expr,
    B: Expr<Scalar = A::Scalar, Dim = A::Dim>,
    C: Expr<Scalar = A::Scalar, Dim = A::Dim>,
{
    type Scalar = A::Scalar;
    type Dim = A::Dim;
    #[inline(always)]
    fn coeff(&self, i: usize) -> A::Scalar {
        self.a.coeff(i).mul_add(self.b.coeff(i), self.c.coeff(i))
    }
}

impl<M, A, B> Expr for Select<M, A, B>
where
    A: Expr,
    B: Expr<Scalar = A::Scalar, Dim = A::Dim>,
    M: MaskExpr<Mask = <A::Scalar as Scalar>::Mask, Dim = A::Dim>,
{
    type Scalar = A::Scalar;
    type Dim = A::Dim;
    #[inline(always)]
    fn coeff(&self, i: usize) -> A::Scalar {
        Scalar::select(self.mask.mask(i), self.a.coeff(i), self.b.coeff(i))
    }
}

impl<E: Expr, F: Fn(E::Scalar) -> E::Scalar> Expr for Map<E, F> {
    type Scalar = E::Scalar;
    type Dim = E::Dim;
    #[inline(always)]
    fn coeff(&self, i: usize) -> E::Scalar {
        (self.f)(self.inner.coeff(i))
    }
}

impl<E, T, N> Expr for Conform<E, T, N>
where
    E: Expr,
    T: Scalar,
    N: ArrayLength,
    E::Scalar: SameScalar<T>,
    E::Dim: SameDim<N>,
{
    type Scalar = T;
    type Dim = N;
    #[inline(always)]
    fn coeff(&self, i: usize) -> T {
        self.inner.coeff(i).same()
    }
}

impl<L, R, O> MaskExpr for Compare<L, R, O>
where
    L: Expr,
    R: Expr<Scalar = L::Scalar, Dim = L::Dim>,
    O: CompareOp,
{
    type Mask = <L::Scalar as Scalar>::Mask;
    type Dim = L::Dim;
    #[inline(always)]
    fn mask(&self, i: usize) -> Self::Mask {
        O::apply(self.lhs.coeff(i), self.rhs.coeff(i))
    }
}

impl<L: MaskExpr, R: MaskExpr<Mask = L::Mask, Dim = L::Dim>> MaskExpr for MaskAnd<L, R> {
    type Mask = L::Mask;
    type Dim = L::Dim;
    #[inline(always)]
    fn mask(&self, i: usize) -> L::Mask {
        self.lhs.mask(i).and(self.rhs.mask(i))
    }
}

impl<L: MaskExpr, R: MaskExpr<Mask = L::Mask, Dim = L::Dim>> MaskExpr for MaskOr<L, R> {
    type Mask = L::Mask;
    type Dim = L::Dim;
    #[inline(always)]
    fn mask(&self, i: usize) -> L::Mask {
        self.lhs.mask(i).or(self.rhs.mask(i))
    }
}

impl<E: MaskExpr> MaskExpr for MaskNot<E> {
    type Mask = E::Mask;
    type Dim = E::Dim;
    #[inline(always)]
    fn mask(&self, i: usize) -> E::Mask {
        self.inner.mask(i).not()
    }
}

impl<M: Mask, N: ArrayLength> MaskExpr for &Vector<M, N> {
    type Mask = M;
    type Dim = N;
    #[inline(always)]
    fn mask(&self, i: usize) -> M {
        self.as_slice()[i]
    }
}

// ----- operands ---------------------------------------------------------------------------

/// Every expression node is an operand of any scalar and dimension at the impl level; the
/// where-clauses then require its own to be the same ([`SameScalar`], [`SameDim`]), so a
/// mismatch is reported by those traits' plain-word errors instead of as a type mismatch
/// between typenum numbers.
macro_rules! node_operand {
    ([$($g:tt)*] $ty:ty) => {
        impl<$($g)* T__: Scalar, N__: ArrayLength> Operand<T__, N__> for $ty
        where
            $ty: Expr,
            <$ty as Expr>::Scalar: SameScalar<T__>,
            <$ty as Expr>::Dim: SameDim<N__>,
        {
            type Expr = Conform<Self, T__, N__>;
            #[inline(always)]
            fn into_expr(self) -> Self::Expr {
                Conform::new(self)
            }
        }
    };
}

node_operand!(['a, T, N: ArrayLength,] &'a Vector<T, N>);
node_operand!([T, N: ArrayLength,] Owned<T, N>);
node_operand!([T, N,] Splat<T, N>);
node_operand!([L, R, O,] Binary<L, R, O>);
node_operand!([E, O,] Unary<E, O>);
node_operand!([A, B, C,] MulAdd<A, B, C>);
node_operand!([M, A, B,] Select<M, A, B>);
node_operand!([E, F,] Map<E, F>);
node_operand!([E, T, N,] Conform<E, T, N>);
node_operand!([] crate::Vec3A);

/// The vector methods that take or build expressions: assignment, in-place update and
/// normalisation, and comparison against any operand.
impl<T: Scalar, N: ArrayLength> Vector<T, N> {
    /// Evaluates `expr` into `self`, in one loop, without a temporary.
    ///
    /// The borrow checker refuses `a.assign(&a + &b)` (aliasing the destination); use
    /// the in-place forms (`a += &b`, [`Vector::update`]) for that.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{Vector, typenum::U8};
    /// let (a, b) = (Vector::<f64, U8>::splat(1.0), Vector::<f64, U8>::splat(2.0));
    /// let mut out = Vector::<f64, U8>::zero();
    /// out.assign(&a * 3.0 - &b);
    /// assert_eq!(out, Vector::splat(1.0));
    /// ```
    #[inline(always)]
    pub fn assign<E: Operand<T, N>>(&mut self, expr: E) {
        crate::assign::assign_to(self.as_mut_generic_array(), &expr.into_expr());
    }

    /// In-place element-wise update: `self[i] = f(self[i], expr[i])`, in one loop.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::vec3;
    /// let mut a = vec3(1.0f32, 2.0, 3.0);
    /// let b = vec3(1.0f32, 1.0, 1.0);
    /// a.update(&b * 2.0, |old, new| old * new);
    /// assert_eq!(a, vec3(2.0, 4.0, 6.0));
    /// ```
    #[inline(always)]
    pub fn update<E: Operand<T, N>>(&mut self, expr: E, f: impl Fn(T, T) -> T) {
        crate::assign::update(self.as_mut_generic_array(), &expr.into_expr(), f);
    }

    /// Normalises in place (same rules as [`Expr::normalize`]).
    #[inline(always)]
    pub fn normalize_mut(&mut self) {
        let l2 = (&*self).length_squared();
        let min = T::splat(<T::Elem as Real>::MIN_POSITIVE);
        let max = T::splat(<T::Elem as Real>::MAX);
        if l2.ge(min).and(l2.le(max)).all() {
            let inv = l2.sqrt().recip();
            self.apply(|x| x * inv);
        } else {
            *self = (&*self).normalize();
        }
    }

    /// Is every element (every lane, for packets) within `tol` of the other's, relative
    /// to the larger magnitude and absolutely for magnitudes below 1? NaN is never close
    /// to anything; equal infinities are close.
    ///
    /// `|a - b| <= tol * max(1, |a|, |b|)` per element and lane.
    pub fn approx_eq<E: Operand<T, N>>(&self, other: E, tol: T::Elem) -> bool {
        let e = other.into_expr();
        (0..N::USIZE).all(|i| {
            let (a, b) = (self[i], e.coeff(i));
            (0..T::LANES).all(|l| approx_eq_scalar(a.lane(l), b.lane(l), tol))
        })
    }
}

/// An owned vector is moved into the tree as an [`Owned`] leaf.
impl<T: Scalar, N: ArrayLength, T2: Scalar, N2: ArrayLength> Operand<T2, N2> for Vector<T, N>
where
    T: SameScalar<T2>,
    N: SameDim<N2>,
{
    type Expr = Conform<Owned<T, N>, T2, N2>;
    #[inline(always)]
    fn into_expr(self) -> Self::Expr {
        Conform::new(Owned(self))
    }
}

/// A scalar of the expression's own type is broadcast to every element.
impl<T: Scalar, N: ArrayLength> Operand<T, N> for T {
    type Expr = Splat<T, N>;
    #[inline(always)]
    fn into_expr(self) -> Splat<T, N> {
        Splat::new(self)
    }
}

/// A plain `f32`/`f64` next to a packet expression is broadcast to every lane.
macro_rules! lane_operand {
    ($t:ty) => {
        impl<L: ArrayLength, N: ArrayLength> Operand<Packet<$t, L>, N> for $t
        where
            Packet<$t, L>: Scalar,
        {
            type Expr = Splat<Packet<$t, L>, N>;
            #[inline(always)]
            fn into_expr(self) -> Self::Expr {
                Splat::new(Packet::<$t, L>::from_fn(|_| self))
            }
        }
    };
}
lane_operand!(f32);
lane_operand!(f64);

/// A plain `f32` next to an expression of explicit SIMD lanes is broadcast to every lane.
macro_rules! simd_lane_operand {
    ($t:ty) => {
        impl<N: ArrayLength> Operand<$t, N> for f32 {
            type Expr = Splat<$t, N>;
            #[inline(always)]
            fn into_expr(self) -> Self::Expr {
                Splat::new(<$t as Scalar>::splat(self))
            }
        }
    };
}
#[cfg(target_arch = "x86_64")]
simd_lane_operand!(crate::simd::F32x4);
#[cfg(target_arch = "x86_64")]
simd_lane_operand!(crate::simd::F32x8);
#[cfg(target_arch = "x86_64")]
simd_lane_operand!(crate::simd::F32x16);
