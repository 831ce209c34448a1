//! Operator overloading: `+ - * /` and unary `-` on vectors, borrowed vectors and every
//! expression node build new nodes; nothing is computed here.
//!
//! The right operand may be anything that is an [`Operand`] of the left side's scalar
//! and dimension, so `&a + &b`, `&a + b`, `&a * 2.0` and `(&a + &b) * &c` all work, and
//! `U3 + U4` fails to compile at the operator. A scalar on the left (`2.0 * &a`) is
//! supported wherever it is on the right: an `f32` or `f64` with vectors of that float
//! and of its packets and SIMD lanes (broadcast to every lane), and a packet or lane
//! value with vectors of it.

use crate::expr::{Binary, Conform, Expr, Map, MulAdd, Operand, Owned, Select, Splat, Unary};
use crate::op::{AddOp, DivOp, MulOp, NegOp, SubOp};
use crate::packet::Packet;
use crate::scalar::{Real, Scalar};
use crate::vector::Vector;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use generic_array::ArrayLength;

macro_rules! binary_ops {
    ([$($g:tt)*] $ty:ty => $ety:ty, |$s:ident| $conv:expr) => {
        binary_ops!(@one [$($g)*] $ty => $ety, |$s| $conv, Add, add, AddOp);
        binary_ops!(@one [$($g)*] $ty => $ety, |$s| $conv, Sub, sub, SubOp);
        binary_ops!(@one [$($g)*] $ty => $ety, |$s| $conv, Mul, mul, MulOp);
        binary_ops!(@one [$($g)*] $ty => $ety, |$s| $conv, Div, div, DivOp);

        impl<$($g)*> Neg for $ty
        where
            $ety: Expr,
        {
            type Output = Unary<$ety, NegOp>;
            #[inline(always)]
            fn neg(self) -> Self::Output {
                let $s = self;
                Unary::new($conv)
            }
        }

        float_left!([$($g)*] $ty => $ety, |$s| $conv, f32);
        float_left!([$($g)*] $ty => $ety, |$s| $conv, f64);
        packet_left!([$($g)*] $ty => $ety, |$s| $conv);
        #[cfg(target_arch = "x86_64")]
        scalar_left!([$($g)*] $ty => $ety, |$s| $conv, crate::simd::F32x4);
        #[cfg(target_arch = "x86_64")]
        scalar_left!([$($g)*] $ty => $ety, |$s| $conv, crate::simd::F32x8);
        #[cfg(target_arch = "x86_64")]
        scalar_left!([$($g)*] $ty => $ety, |$s| $conv, crate::simd::F32x16);
    };
    (@one [$($g:tt)*] $ty:ty => $ety:ty, |$s:ident| $conv:expr, $tr:ident, $f:ident, $op:ident) => {
        impl<$($g)* Rhs__> $tr<Rhs__> for $ty
        where
            $ety: Expr,
            Rhs__: Operand<<$ety as Expr>::Scalar, <$ety as Expr>::Dim>,
        {
            type Output = Binary<$ety, Rhs__::Expr, $op>;
            #[inline(always)]
            fn $f(self, rhs: Rhs__) -> Self::Output {
                let $s = self;
                Binary::new($conv, rhs.into_expr())
            }
        }
    };
}

macro_rules! scalar_left {
    ([$($g:tt)*] $ty:ty => $ety:ty, |$s:ident| $conv:expr, $t:ty) => {
        scalar_left!(@one [$($g)*] $ty => $ety, |$s| $conv, $t, Add, add, AddOp);
        scalar_left!(@one [$($g)*] $ty => $ety, |$s| $conv, $t, Sub, sub, SubOp);
        scalar_left!(@one [$($g)*] $ty => $ety, |$s| $conv, $t, Mul, mul, MulOp);
        scalar_left!(@one [$($g)*] $ty => $ety, |$s| $conv, $t, Div, div, DivOp);
    };
    (@one [$($g:tt)*] $ty:ty => $ety:ty, |$s:ident| $conv:expr, $t:ty, $tr:ident, $f:ident, $op:ident) => {
        impl<$($g)*> $tr<$ty> for $t
        where
            $ety: Expr<Scalar = $t>,
        {
            type Output = Binary<Splat<$t, <$ety as Expr>::Dim>, $ety, $op>;
            #[inline(always)]
            fn $f(self, rhs: $ty) -> Self::Output {
                let $s = rhs;
                Binary::new(Splat::new(self), $conv)
            }
        }
    };
}

/// A plain `f32` or `f64` on the left of any expression it is an [`Operand`] of: an
/// expression of the same float, or of packets or SIMD lanes of it (broadcast to every
/// lane), so `2.0 * &v` compiles wherever `&v * 2.0` does.
macro_rules! float_left {
    ([$($g:tt)*] $ty:ty => $ety:ty, |$s:ident| $conv:expr, $t:ty) => {
        float_left!(@one [$($g)*] $ty => $ety, |$s| $conv, $t, Add, add, AddOp);
        float_left!(@one [$($g)*] $ty => $ety, |$s| $conv, $t, Sub, sub, SubOp);
        float_left!(@one [$($g)*] $ty => $ety, |$s| $conv, $t, Mul, mul, MulOp);
        float_left!(@one [$($g)*] $ty => $ety, |$s| $conv, $t, Div, div, DivOp);
    };
    (@one [$($g:tt)*] $ty:ty => $ety:ty, |$s:ident| $conv:expr, $t:ty, $tr:ident, $f:ident, $op:ident) => {
        impl<$($g)*> $tr<$ty> for $t
        where
            $ety: Expr,
            $t: Operand<<$ety as Expr>::Scalar, <$ety as Expr>::Dim>,
        {
            type Output = Binary<
                <$t as Operand<<$ety as Expr>::Scalar, <$ety as Expr>::Dim>>::Expr,
                $ety,
                $op,
            >;
            #[inline(always)]
            fn $f(self, rhs: $ty) -> Self::Output {
                let $s = rhs;
                Binary::new(
                    <$t as Operand<<$ety as Expr>::Scalar, <$ety as Expr>::Dim>>::into_expr(self),
                    $conv,
                )
            }
        }
    };
}

macro_rules! packet_left {
    ([$($g:tt)*] $ty:ty => $ety:ty, |$s:ident| $conv:expr) => {
        packet_left!(@one [$($g)*] $ty => $ety, |$s| $conv, Add, add, AddOp);
        packet_left!(@one [$($g)*] $ty => $ety, |$s| $conv, Sub, sub, SubOp);
        packet_left!(@one [$($g)*] $ty => $ety, |$s| $conv, Mul, mul, MulOp);
        packet_left!(@one [$($g)*] $ty => $ety, |$s| $conv, Div, div, DivOp);
    };
    (@one [$($g:tt)*] $ty:ty => $ety:ty, |$s:ident| $conv:expr, $tr:ident, $f:ident, $op:ident) => {
        impl<$($g)* PT__: Real, PL__: ArrayLength> $tr<$ty> for Packet<PT__, PL__>
        where
            Packet<PT__, PL__>: Scalar,
            $ety: Expr<Scalar = Packet<PT__, PL__>>,
        {
            type Output = Binary<Splat<Packet<PT__, PL__>, <$ety as Expr>::Dim>, $ety, $op>;
            #[inline(always)]
            fn $f(self, rhs: $ty) -> Self::Output {
                let $s = rhs;
                Binary::new(Splat::new(self), $conv)
            }
        }
    };
}

binary_ops!(['a, T: Scalar, N: ArrayLength,] &'a Vector<T, N> => &'a Vector<T, N>, |s| s);
binary_ops!([T: Scalar, N: ArrayLength,] Vector<T, N> => Owned<T, N>, |s| Owned(s));
binary_ops!([T: Scalar, N: ArrayLength,] Owned<T, N> => Owned<T, N>, |s| s);
binary_ops!([T, N,] Splat<T, N> => Splat<T, N>, |s| s);
binary_ops!([L, R, O,] Binary<L, R, O> => Binary<L, R, O>, |s| s);
binary_ops!([E, O,] Unary<E, O> => Unary<E, O>, |s| s);
binary_ops!([A, B, C,] MulAdd<A, B, C> => MulAdd<A, B, C>, |s| s);
binary_ops!([M, A, B,] Select<M, A, B> => Select<M, A, B>, |s| s);
binary_ops!([E, F,] Map<E, F> => Map<E, F>, |s| s);
binary_ops!([E, T, N,] Conform<E, T, N> => Conform<E, T, N>, |s| s);

// ----- in-place updates: one loop, no temporary ---------------------------------------------

macro_rules! assign_op {
    ($tr:ident, $f:ident, $op:tt) => {
        /// In-place element-wise update with any operand (vector, expression or scalar).
        impl<T: Scalar, N: ArrayLength, Rhs: Operand<T, N>> $tr<Rhs> for Vector<T, N> {
            #[inline(always)]
            fn $f(&mut self, rhs: Rhs) {
                self.update(rhs, |a, b| a $op b);
            }
        }
    };
}
assign_op!(AddAssign, add_assign, +);
assign_op!(SubAssign, sub_assign, -);
assign_op!(MulAssign, mul_assign, *);
assign_op!(DivAssign, div_assign, /);

// `&Vec3A` builds lazy trees like `&Vector<f32, U3>` (by value its operators are eager,
// in `vec3a.rs`).
binary_ops!(@one ['a,] &'a crate::Vec3A => crate::Vec3A, |s| *s, Add, add, AddOp);
binary_ops!(@one ['a,] &'a crate::Vec3A => crate::Vec3A, |s| *s, Sub, sub, SubOp);
binary_ops!(@one ['a,] &'a crate::Vec3A => crate::Vec3A, |s| *s, Mul, mul, MulOp);
binary_ops!(@one ['a,] &'a crate::Vec3A => crate::Vec3A, |s| *s, Div, div, DivOp);
float_left!(['a,] &'a crate::Vec3A => crate::Vec3A, |s| *s, f32);

impl Neg for &crate::Vec3A {
    type Output = Unary<crate::Vec3A, NegOp>;
    #[inline(always)]
    fn neg(self) -> Self::Output {
        Unary::new(*self)
    }
}
