//! Compile-time-generic vector math with lazy, fused expression templates.
//!
//! A [`Vector<T, N>`] stores `N` elements of a [`Scalar`] `T`; `N` is a typenum type, so
//! the dimension is part of the type and a mismatch is a compile error. `T` is `f32`,
//! `f64`, or a [`Packet`] of 4, 8 or 16 lanes, so one generic formula serves a single
//! vector and a structure-of-arrays packet of rays alike.
//!
//! # Expressions are data; evaluation is one loop
//! Operators on vectors do not compute: `&a * &b + &c * &d - &e` builds a tree of small
//! generic structs ([`Binary`], [`Unary`], [`Splat`], ...) holding references to the
//! leaves. The tree is computed only by [`Expr::eval`] or [`Vector::assign`], which run a
//! single loop asking the root for element `i` ([`Expr::coeff`]); each node asks its
//! children for element `i` and applies its operation. After inlining, the whole tree is
//! one fused loop body with no temporaries, whatever its depth.
//!
//! Reductions ([`Expr::dot`], [`Expr::sum`], [`Expr::length`], ...) consume an expression
//! and evaluate each child once. Operations that need a child more than once
//! ([`Expr::normalize`], [`Expr::cross`], [`Expr::reflect`], [`Expr::refract`]) first
//! evaluate it into a vector.
//!
//! ```
//! use vecexpr::{vec3, Expr};
//! let i = vec3(1.0f32, -1.0, 0.0);
//! let n = vec3(0.0f32, 1.0, 0.0);
//! // R = I - 2 N (N·I), written out; `reflect` computes the same.
//! let r = (&i - &n * (2.0 * n.dot(&i))).eval();
//! assert_eq!(r, i.reflect(&n));
//! ```
//!
//! A dimension mismatch does not compile:
//! ```compile_fail
//! use vecexpr::{Vector, Expr, typenum::{U3, U4}};
//! let a = Vector::<f32, U3>::splat(1.0);
//! let b = Vector::<f32, U4>::splat(1.0);
//! let c = (&a + &b).eval();
//! ```
//! nor does mixing scalar types:
//! ```compile_fail
//! use vecexpr::{vec3, Expr};
//! let c = (&vec3(1.0f32, 2.0, 3.0) + &vec3(1.0f64, 2.0, 3.0)).eval();
//! ```
//! and aliasing the destination of an assignment is refused by the borrow checker:
//! ```compile_fail
//! use vecexpr::vec3;
//! let mut a = vec3(1.0f32, 2.0, 3.0);
//! let b = vec3(1.0f32, 2.0, 3.0);
//! a.assign(&a + &b);
//! ```
//!
//! # Packets
//! ```
//! use vecexpr::{Packet, Vector, Expr, Scalar, typenum::{U3, U16}};
//! type P = Packet<f32, U16>;
//! // Sixteen incident directions and normals in SoA form.
//! let i = Vector::<P, U3>::from_fn(|c| P::from_fn(|l| if c == 1 { -1.0 } else { l as f32 }));
//! let n = Vector::<P, U3>::from_fn(|c| P::splat(if c == 1 { 1.0 } else { 0.0 }));
//! let r = i.reflect(&n); // the same source as for one f32 ray
//! assert_eq!(r[1], P::splat(1.0));
//! // A plain float scales every lane, on either side of the operator.
//! assert_eq!((2.0 * &r).eval(), (&r * 2.0).eval());
//! assert_eq!((0.5 * r).eval()[1], P::splat(0.5));
//! ```
//!
//! # Matrices
//! [`Matrix<T, R, C>`](Matrix) (column-major, [`Mat3`], [`Mat4`], ...) has the same lazy
//! element-wise operators through [`MatExpr`], and products whose inner dimensions are
//! checked at compile time:
//! ```
//! use vecexpr::{vec3, Mat3, MatExpr};
//! let scale = (Mat3::<f32>::identity() * 2.0).eval();
//! assert_eq!(&scale * &vec3(1.0, 2.0, 3.0), vec3(2.0, 4.0, 6.0));
//! ```
//!
//! # Fused multiply-add
//! Rust never contracts `a * b + c` into an FMA, so results are reproducible across
//! targets. Ask for it with [`Expr::mul_add`]; it changes the last bits.
//!
//! # Compile-time computation
//! [`powi`] unrolls integer powers through typenum; [`Vector::extend`] and
//! [`Vector::truncate`] compute dimensions `N ± 1` at compile time.

#![warn(missing_docs)]

pub use generic_array;
pub use typenum;

pub mod assign;
mod eval;
pub mod expr;
pub mod guide;
mod interop;
pub mod matrix;
mod meta;
pub mod op;
mod ops;
mod packet;
mod scalar;
pub mod simd;
mod vec3a;
mod vector;

pub use expr::{
    select, Binary, Compare, Conform, Dim3, Expr, ExprOf, Map, MaskAnd, MaskExpr, MaskNot, MaskOr,
    MulAdd, Operand, Owned, Refracted, SameDim, SameScalar, Select, Splat, Unary,
};
pub use matrix::{Mat2, Mat3, Mat4, MatExpr, Matrix};
pub use meta::{powi, Pow};
pub use packet::{Packet, PacketMask};
pub use scalar::{LaneBits, Mask, Real, Scalar};
pub use vec3a::Vec3A;
pub use vector::{approx_eq_scalar, vec2, vec3, vec4, LengthMismatch, Vector};

/// A 3-vector of `T`.
pub type Vec3<T> = Vector<T, typenum::U3>;
/// A 4-vector of `T`.
pub type Vec4<T> = Vector<T, typenum::U4>;
/// Four `f32` lanes in an array, one SSE register's worth (`Packet<f32, U4>`).
///
/// The array packets are named `Packet` + lane type + `x` + lanes; the explicit SIMD
/// registers of [`simd`] are `F32x4`, `F32x8` and `F32x16`, so both modules can be
/// glob-imported together.
pub type PacketF32x4 = Packet<f32, typenum::U4>;
/// Eight `f32` lanes in an array, one AVX2 register's worth (`Packet<f32, U8>`).
pub type PacketF32x8 = Packet<f32, typenum::U8>;
/// Sixteen `f32` lanes in an array, one AVX-512 register's worth (`Packet<f32, U16>`).
pub type PacketF32x16 = Packet<f32, typenum::U16>;
/// Four `f64` lanes in an array, one AVX2 register's worth (`Packet<f64, U4>`).
pub type PacketF64x4 = Packet<f64, typenum::U4>;
/// Eight `f64` lanes in an array, one AVX-512 register's worth (`Packet<f64, U8>`).
pub type PacketF64x8 = Packet<f64, typenum::U8>;

/// The names most code needs, for `use vecexpr::prelude::*`.
///
/// # Examples
/// ```
/// use vecexpr::prelude::*;
/// fn sum_of<T: Scalar, N: ArrayLength>(v: &Vector<T, N>) -> T {
///     v.sum()
/// }
/// assert_eq!(sum_of(&vec3(1.0f32, 2.0, 3.0)), 6.0);
/// let a = Vec3A::new(1.0, 0.0, 0.0);
/// assert_eq!(a.cross(Vec3A::Y), Vec3A::Z);
/// ```
pub mod prelude {
    pub use crate::generic_array::ArrayLength;
    pub use crate::typenum::{U2, U3, U4};
    pub use crate::{
        select, vec2, vec3, vec4, Expr, ExprOf, Mask, MaskExpr, Mat2, Mat3, Mat4, MatExpr, Matrix,
        Operand, Packet, Real, Scalar, Vec3, Vec3A, Vec4, Vector,
    };
}
