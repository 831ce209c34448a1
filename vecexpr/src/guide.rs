//! # Writing generic code with vecexpr
//!
//! This page is documentation only: how to write functions generic over the scalar type
//! `T`, the dimension `N`, any expression, and the SIMD lane types, with the fewest
//! bounds. Every example here is compiled and run as a test.
//!
//! ## The bounds, one per parameter
//!
//! | you take | bound | gives |
//! |---|---|---|
//! | a scalar `T` (`f32`, `f64`, a [`Packet`](crate::Packet), a [`simd`](crate::simd) lane type) | `T: Scalar` | `+ - * /`, `min`, `max`, `sqrt`, `select`, [`Scalar::splat_f64`] |
//! | a plain float (`f32` or `f64` only) | `T: Real` | the above plus `<`, `PI`, `from_f64`, `to_f64` |
//! | a dimension `N` (`U3`, `U1000`, ...) | `N: ArrayLength` | `Vector<T, N>`; re-exported as [`crate::generic_array::ArrayLength`] |
//! | any vector expression of scalar `T` | `E: ExprOf<T>` | every [`Expr`] method, use as an operand, operators after [`Expr::ops`] |
//! | a lane type of an instruction set | `S: SimdF32` | `Scalar` of `f32` lanes plus `load`/`store` |
//!
//! A `Vector<T, N>` needs nothing more than `T: Scalar, N: ArrayLength` for all its
//! arithmetic: the operators of `&Vector<T, N>` are implemented for every such `T` and
//! `N`.
//!
//! ```
//! use vecexpr::generic_array::ArrayLength;
//! use vecexpr::{vec3, Expr, Scalar, Vector};
//!
//! /// $a + t (b - a)$ for any scalar and dimension.
//! fn lerp<T: Scalar, N: ArrayLength>(a: &Vector<T, N>, b: &Vector<T, N>, t: T) -> Vector<T, N> {
//!     (a + (b - a) * t).eval()
//! }
//!
//! let m = lerp(&vec3(0.0f32, 2.0, 4.0), &vec3(2.0, 2.0, 0.0), 0.5);
//! assert_eq!(m, vec3(1.0, 2.0, 2.0));
//! // The same function on f64 and on a 5-vector:
//! let a = Vector::<f64, vecexpr::typenum::U5>::splat(1.0);
//! assert_eq!(lerp(&a, &Vector::zero(), 0.25), Vector::splat(0.75));
//! ```
//!
//! ## Float constants in generic code
//!
//! A literal such as `0.5` is an `f32` or an `f64`, never a `T`; `v * 0.5` does not compile
//! in a function generic over `T` (the error says so). Write the constant through the
//! scalar type, which also works for packets (every lane set):
//!
//! - `T::splat_f64(0.5)`: any [`Scalar`], rounded to the lane type;
//! - `T::one()`, `T::zero()`;
//! - `T::from_f64(0.5)`, `T::PI`, `T::EPSILON`: plain floats ([`Real`]).
//!
//! ```
//! use vecexpr::generic_array::ArrayLength;
//! use vecexpr::{vec3, Expr, Packet, Scalar, Vector};
//! use vecexpr::typenum::{U3, U8};
//!
//! /// The midpoint of two points.
//! fn midpoint<T: Scalar, N: ArrayLength>(a: &Vector<T, N>, b: &Vector<T, N>) -> Vector<T, N> {
//!     ((a + b) * T::splat_f64(0.5)).eval()
//! }
//!
//! assert_eq!(midpoint(&vec3(0.0f32, 0.0, 0.0), &vec3(2.0, 4.0, 6.0)), vec3(1.0, 2.0, 3.0));
//! // Eight points at once: the same function on a packet scalar.
//! type P = Packet<f32, U8>;
//! let a = Vector::<P, U3>::splat(P::splat(2.0));
//! assert_eq!(midpoint(&a, &Vector::zero()), Vector::splat(P::splat(1.0)));
//! ```
//!
//! ## Any expression: `ExprOf<T>`
//!
//! A function that should accept a vector, a borrowed vector or a whole lazy tree takes
//! `E: ExprOf<T>`. The operators of a generic `E` are reached through [`Expr::ops`]
//! (which wraps it in a node that has them; it costs nothing), and `E` can stand on the
//! right of any operator:
//!
//! ```
//! use vecexpr::{vec3, Expr, ExprOf, Scalar, Vector};
//!
//! /// $\sum_i (2 x_i + y_i)$, for any two expressions of the same scalar and dimension.
//! fn weighted<T: Scalar, A: ExprOf<T>, B: ExprOf<T> + Expr<Dim = A::Dim>>(a: A, b: B) -> T {
//!     (a.ops() * T::splat_f64(2.0) + b).sum()
//! }
//!
//! let (x, y) = (vec3(1.0f32, 2.0, 3.0), vec3(1.0f32, 1.0, 1.0));
//! assert_eq!(weighted(&x, &y), 15.0);
//! // A lazy tree is an expression too: nothing is evaluated before `sum`.
//! assert_eq!(weighted(&x - &y, &y), 9.0);
//! ```
//!
//! An expression is consumed by each use. To use one twice, evaluate it once
//! ([`Expr::eval`]) and borrow the vector, as `normalize` and `reflect` do internally:
//!
//! ```
//! use vecexpr::{vec3, Expr, ExprOf, Real, Vector};
//!
//! /// The component of `v` along the unit vector `n`: $(v \cdot n)\, n$.
//! fn project<T: Real, E: ExprOf<T>>(v: E, n: &Vector<T, E::Dim>) -> Vector<T, E::Dim> {
//!     let v = v.eval();
//!     (n * (&v).dot(n)).eval()
//! }
//!
//! let p = project(&vec3(3.0f64, 4.0, 0.0), &vec3(1.0, 0.0, 0.0));
//! assert_eq!(p, vec3(3.0, 0.0, 0.0));
//! ```
//!
//! ## Lane types: one kernel for every instruction set
//!
//! Code generic over [`SimdF32`](crate::simd::SimdF32) runs on SSE2, AVX2 and AVX-512
//! registers; [`Isa::dispatch`](crate::simd::Isa::dispatch) picks the widest the CPU has
//! and compiles the kernel for it (x86-64 only).
//!
//! ```
//! # #[cfg(target_arch = "x86_64")] {
//! use vecexpr::simd::{Isa, Kernel, SimdF32};
//! use vecexpr::typenum::U3;
//! use vecexpr::{Expr, Scalar, Vector};
//!
//! /// Lengths of 3-vectors stored as three arrays (x, y, z), `S::LANES` at a time.
//! struct Lengths<'a> {
//!     xyz: [&'a [f32]; 3],
//!     out: &'a mut [f32],
//! }
//!
//! impl Kernel for Lengths<'_> {
//!     type Output = ();
//!     #[inline(always)]
//!     fn run<S: SimdF32>(self) {
//!         let n = self.out.len();
//!         for i in (0..n).step_by(S::LANES) {
//!             let v = Vector::<S, U3>::from_fn(|c| S::load(&self.xyz[c][i..]));
//!             v.length().store(&mut self.out[i..]);
//!         }
//!     }
//! }
//!
//! let (x, y, z) = ([3.0f32; 16], [4.0f32; 16], [0.0f32; 16]);
//! let mut out = [0.0f32; 16];
//! let isa = Isa::detect().expect("x86-64 has at least SSE2");
//! isa.dispatch(Lengths { xyz: [&x, &y, &z], out: &mut out });
//! assert_eq!(out, [5.0; 16]);
//! # }
//! ```
//!
//! ## Lanes of a packet from a function generic over `T`
//!
//! [`Scalar::lane`] and [`Scalar::LANES`] read any scalar lane by lane, so one
//! function can report per-ray results for a plain float (one lane) and a packet alike:
//!
//! ```
//! use vecexpr::{vec3, Expr, Packet, Scalar, Vector};
//! use vecexpr::typenum::{U3, U4};
//!
//! fn lengths<T: Scalar>(v: &Vector<T, U3>) -> Vec<T::Elem> {
//!     let l = v.length();
//!     (0..T::LANES).map(|i| l.lane(i)).collect()
//! }
//!
//! assert_eq!(lengths(&vec3(3.0f32, 4.0, 0.0)), vec![5.0]);
//! type P = Packet<f32, U4>;
//! let v = Vector::<P, U3>::from_fn(|c| P::from_fn(|l| if c == 0 { l as f32 } else { 0.0 }));
//! assert_eq!(lengths(&v), vec![0.0, 1.0, 2.0, 3.0]);
//! ```

#[allow(unused_imports)]
use crate::{Expr, ExprOf, Real, Scalar};
