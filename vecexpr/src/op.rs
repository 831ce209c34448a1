//! Operation functors: what a node computes, separate from the node that stores operands.
//!
//! Each functor is a zero-sized type with a lane-wise scalar function. Nodes
//! ([`crate::expr`]) are generic over the functor, so one `Binary` node type serves
//! `+ - * / min max`.

use crate::scalar::Scalar;

/// A lane-wise binary operation.
pub trait BinaryOp: Copy + Default {
    /// Relative cost in simple arithmetic operations (documentation and strategy hints).
    const COST: usize;
    /// The operation on one element.
    fn apply<T: Scalar>(a: T, b: T) -> T;
}

/// A lane-wise unary operation.
pub trait UnaryOp: Copy + Default {
    /// Relative cost in simple arithmetic operations.
    const COST: usize;
    /// The operation on one element.
    fn apply<T: Scalar>(a: T) -> T;
}

/// A lane-wise comparison producing a mask.
pub trait CompareOp: Copy + Default {
    /// The comparison on one element.
    fn apply<T: Scalar>(a: T, b: T) -> T::Mask;
}

macro_rules! binary_op {
    ($(#[$m:meta])* $name:ident, $cost:expr, |$a:ident, $b:ident| $body:expr) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub struct $name;
        impl BinaryOp for $name {
            const COST: usize = $cost;
            #[inline(always)]
            fn apply<T: Scalar>($a: T, $b: T) -> T {
                $body
            }
        }
    };
}

macro_rules! unary_op {
    ($(#[$m:meta])* $name:ident, $cost:expr, |$a:ident| $body:expr) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub struct $name;
        impl UnaryOp for $name {
            const COST: usize = $cost;
            #[inline(always)]
            fn apply<T: Scalar>($a: T) -> T {
                $body
            }
        }
    };
}

macro_rules! compare_op {
    ($(#[$m:meta])* $name:ident, |$a:ident, $b:ident| $body:expr) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub struct $name;
        impl CompareOp for $name {
            #[inline(always)]
            fn apply<T: Scalar>($a: T, $b: T) -> T::Mask {
                $body
            }
        }
    };
}

binary_op!(/// $a + b$.
    AddOp, 1, |a, b| a + b);
binary_op!(/// $a - b$.
    SubOp, 1, |a, b| a - b);
binary_op!(/// $a \cdot b$.
    MulOp, 1, |a, b| a * b);
binary_op!(/// $a / b$.
    DivOp, 8, |a, b| a / b);
binary_op!(/// The NaN-propagating minimum [`Scalar::minimum`].
    MinOp, 1, |a, b| Scalar::minimum(a, b));
binary_op!(/// The NaN-propagating maximum [`Scalar::maximum`].
    MaxOp, 1, |a, b| Scalar::maximum(a, b));

unary_op!(/// $-a$.
    NegOp, 1, |a| -a);
unary_op!(/// $|a|$.
    AbsOp, 1, |a| a.abs());
unary_op!(/// $\sqrt{a}$.
    SqrtOp, 12, |a| a.sqrt());
unary_op!(/// $1 / a$.
    RecipOp, 8, |a| a.recip());

compare_op!(/// $a < b$.
    LtOp, |a, b| a.lt(b));
compare_op!(/// $a \le b$.
    LeOp, |a, b| a.le(b));
compare_op!(/// $a > b$.
    GtOp, |a, b| a.gt(b));
compare_op!(/// $a \ge b$.
    GeOp, |a, b| a.ge(b));
compare_op!(/// $a = b$ (IEEE equality).
    EqOp, |a, b| a.eq_mask(b));
