//! Matrices on the vector machinery: `Matrix<T, R, C>` has `R` rows and `C` columns
//! (typenum numbers), stored column-major as `C` columns of type [`Vector<T, R>`].
//!
//! - **Element-wise operations are lazy**, like those of vectors: `&a + &b`, `&a - &b`,
//!   `-&a`, `&a * 2.0`, `2.0 * &a` and `&a / 2.0` build nodes ([`MatBinary`],
//!   [`MatUnary`], [`MatScale`]) implementing [`MatExpr`]; [`MatExpr::eval`] computes
//!   them in one pass over the elements, column by column.
//! - **Products are computed at once**: `&m * &v` (a [`Vector`], or any vector expression)
//!   gives a `Vector<T, R>`, and `&a * &b` a `Matrix<T, R, P>`; the left operand may be
//!   any matrix expression. Element `r` of `m * v` is $\sum_k m_{rk} v_k$, summed left to
//!   right (`k = 0, 1, ...`) whatever the size. A lazy right vector or matrix is
//!   evaluated first (each of its elements is used `R` times); a lazy left operand is
//!   read once per element for `m * v` and evaluated first for `a * b`.
//! - **Dimensions are checked at compile time**: adding a 2×3 to a 3×2 matrix, or
//!   multiplying a matrix with `C` columns by something with other than `C` rows, does
//!   not compile, and the error says so in words.
//!
//! # Examples
//! ```
//! use vecexpr::{vec2, vec3, Expr, MatExpr, Matrix};
//! // A 2×3 matrix from its rows.
//! let m = Matrix::from_rows([vec3(1.0f32, 2.0, 3.0), vec3(4.0, 5.0, 6.0)]);
//! assert_eq!(m[(1, 0)], 4.0);
//! assert_eq!(&m * &vec3(1.0, 0.0, -1.0), vec2(-2.0, -2.0));
//! // Lazy element-wise arithmetic, evaluated in one pass.
//! let n = (&m * 2.0 - &m).eval();
//! assert_eq!(n, m);
//! // (2×3)·(3×2) is 2×2.
//! let p = &m * &m.transpose();
//! assert_eq!(p, Matrix::from_rows([vec2(14.0, 32.0), vec2(32.0, 77.0)]));
//! assert_eq!(format!("{p}"), "[[14, 32], [32, 77]]");
//! ```
//!
//! A product whose inner dimensions differ does not compile:
//! ```compile_fail
//! use vecexpr::{vec2, Matrix, typenum::U3};
//! let m = Matrix::<f32, U3, U3>::identity();
//! let _ = &m * &vec2(1.0f32, 2.0);
//! ```

use crate::expr::{
    Binary, Conform, Expr, Map, MulAdd, Owned, SameDim, SameScalar, Select, Splat, Unary,
};
use crate::op::{AddOp, BinaryOp, DivOp, MulOp, NegOp, SubOp, UnaryOp};
use crate::scalar::Scalar;
use crate::vector::Vector;
use core::fmt;
use core::marker::PhantomData;
use core::ops::{Add, Div, Index, IndexMut, Mul, Neg, Sub};
use generic_array::sequence::GenericSequence;
use generic_array::{ArrayLength, GenericArray, IntoArrayLength};
use typenum::{Const, Unsigned, U2, U3, U4};

/// A matrix of `R` rows and `C` columns of `T`, stored column-major.
///
/// The storage is `C` columns of [`Vector<T, R>`] in a [`GenericArray`], inline, with the
/// layout of `[[T; R]; C]` (the layout of glam's and nalgebra's matrices and of OpenGL):
/// element `(r, c)` is at offset `c * R + r`. Index with `m[(row, col)]`.
///
/// See the [module documentation](crate::matrix) for the operators.
///
/// # Examples
/// ```
/// use vecexpr::{vec3, Expr, Mat3, MatExpr};
/// let rot = Mat3::from_cols([vec3(0.0f64, 1.0, 0.0), vec3(-1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0)]);
/// // A quarter turn about z, four times, is the identity.
/// let r2 = &rot * &rot;
/// assert_eq!(&r2 * &r2, Mat3::identity());
/// assert_eq!(&rot * &vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0));
/// assert_eq!(rot.transpose(), (-&rot + &rot * 2.0).eval().transpose());
/// ```
#[repr(transparent)]
pub struct Matrix<T, R: ArrayLength, C: ArrayLength> {
    cols: GenericArray<Vector<T, R>, C>,
}

/// A 2×2 matrix of `T`.
pub type Mat2<T> = Matrix<T, U2, U2>;
/// A 3×3 matrix of `T`.
pub type Mat3<T> = Matrix<T, U3, U3>;
/// A 4×4 matrix of `T`.
pub type Mat4<T> = Matrix<T, U4, U4>;

impl<T, R: ArrayLength, C: ArrayLength> Matrix<T, R, C> {
    /// Number of rows.
    pub const ROWS: usize = R::USIZE;
    /// Number of columns.
    pub const COLS: usize = C::USIZE;

    /// The matrix with element `(r, c)` equal to `f(r, c)` (called column by column).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{Matrix, typenum::{U2, U3}};
    /// let m = Matrix::<f32, U2, U3>::from_fn(|r, c| (10 * r + c) as f32);
    /// assert_eq!(m[(1, 2)], 12.0);
    /// ```
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize, usize) -> T) -> Self {
        Self {
            cols: GenericArray::generate(|c| Vector::from_fn(|r| f(r, c))),
        }
    }

    /// The matrix with the given columns.
    #[inline(always)]
    pub fn from_cols<const K: usize>(cols: [Vector<T, R>; K]) -> Self
    where
        Const<K>: IntoArrayLength<ArrayLength = C>,
    {
        Self {
            cols: GenericArray::from_array(cols),
        }
    }

    /// The matrix with the given columns, as a generic array.
    #[inline(always)]
    pub const fn from_col_array(cols: GenericArray<Vector<T, R>, C>) -> Self {
        Self { cols }
    }

    /// The columns.
    #[inline(always)]
    pub fn into_cols(self) -> GenericArray<Vector<T, R>, C> {
        self.cols
    }

    /// The columns, borrowed as a generic array.
    #[inline(always)]
    pub fn col_array(&self) -> &GenericArray<Vector<T, R>, C> {
        &self.cols
    }

    /// Column `c`.
    ///
    /// # Panics
    /// If `c >= C`.
    #[inline(always)]
    pub fn col(&self, c: usize) -> &Vector<T, R> {
        &self.cols[c]
    }

    /// Column `c`, mutably.
    ///
    /// # Panics
    /// If `c >= C`.
    #[inline(always)]
    pub fn col_mut(&mut self, c: usize) -> &mut Vector<T, R> {
        &mut self.cols[c]
    }

    /// The columns as a slice.
    #[inline(always)]
    pub fn cols(&self) -> &[Vector<T, R>] {
        &self.cols
    }
}

impl<T: Clone, R: ArrayLength, C: ArrayLength> Matrix<T, R, C> {
    /// The matrix with the given rows.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec2, Matrix};
    /// let m = Matrix::from_rows([vec2(1.0f32, 2.0), vec2(3.0, 4.0), vec2(5.0, 6.0)]);
    /// assert_eq!((m[(2, 0)], m[(0, 1)]), (5.0, 2.0));
    /// assert_eq!(m.row(1), vec2(3.0, 4.0));
    /// ```
    #[inline(always)]
    pub fn from_rows<const K: usize>(rows: [Vector<T, C>; K]) -> Self
    where
        Const<K>: IntoArrayLength<ArrayLength = R>,
    {
        Self::from_fn(|r, c| rows[r][c].clone())
    }

    /// Row `r`, copied into a vector.
    ///
    /// # Panics
    /// If `r >= R`.
    #[inline(always)]
    pub fn row(&self, r: usize) -> Vector<T, C> {
        assert!(r < R::USIZE, "row {r} out of range for {} rows", R::USIZE);
        Vector::from_fn(|c| self.cols[c][r].clone())
    }

    /// The transpose: element `(c, r)` of the result is element `(r, c)` of `self`.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, Matrix};
    /// let m = Matrix::from_rows([vec3(1.0f32, 2.0, 3.0)]);
    /// assert_eq!(m.transpose(), Matrix::from_cols([vec3(1.0, 2.0, 3.0)]));
    /// ```
    #[inline(always)]
    pub fn transpose(&self) -> Matrix<T, C, R> {
        Matrix::from_fn(|r, c| self.cols[r][c].clone())
    }
}

impl<T: Scalar, R: ArrayLength, C: ArrayLength> Matrix<T, R, C> {
    /// The zero matrix.
    #[inline(always)]
    pub fn zero() -> Self {
        Self::from_fn(|_, _| T::zero())
    }

    /// Is every element (every lane) within `tol` of the other's, as
    /// [`Vector::approx_eq`] defines it?
    pub fn approx_eq<E: MatOperand<T, R, C>>(&self, other: E, tol: T::Elem) -> bool {
        let e = other.into_mat_expr();
        (0..C::USIZE).all(|c| {
            (0..R::USIZE).all(|r| {
                let (a, b) = (self.cols[c][r], e.coeff(r, c));
                (0..T::LANES).all(|l| crate::approx_eq_scalar(a.lane(l), b.lane(l), tol))
            })
        })
    }
}

impl<T: Scalar, N: ArrayLength> Matrix<T, N, N> {
    /// The identity matrix: ones on the diagonal, zeros elsewhere.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec4, Mat4};
    /// let v = vec4(1.0f32, 2.0, 3.0, 4.0);
    /// assert_eq!(&Mat4::identity() * &v, v);
    /// ```
    #[inline(always)]
    pub fn identity() -> Self {
        Self::from_fn(|r, c| if r == c { T::one() } else { T::zero() })
    }
}

impl<T: Clone, R: ArrayLength, C: ArrayLength> Clone for Matrix<T, R, C> {
    #[inline(always)]
    fn clone(&self) -> Self {
        Self {
            cols: self.cols.clone(),
        }
    }
}

impl<T: Copy, R: ArrayLength, C: ArrayLength> Copy for Matrix<T, R, C> where
    GenericArray<Vector<T, R>, C>: Copy
{
}

impl<T: Default, R: ArrayLength, C: ArrayLength> Default for Matrix<T, R, C> {
    /// Every element `T::default()` (zero for the scalar types).
    #[inline(always)]
    fn default() -> Self {
        Self::from_fn(|_, _| T::default())
    }
}

impl<T: PartialEq, R: ArrayLength, C: ArrayLength> PartialEq for Matrix<T, R, C> {
    #[inline]
    fn eq(&self, other: &Self) -> bool {
        self.cols == other.cols
    }
}

impl<T, R: ArrayLength, C: ArrayLength> Index<(usize, usize)> for Matrix<T, R, C> {
    type Output = T;
    /// Element `(row, col)`.
    #[inline(always)]
    fn index(&self, (r, c): (usize, usize)) -> &T {
        &self.cols[c][r]
    }
}

impl<T, R: ArrayLength, C: ArrayLength> IndexMut<(usize, usize)> for Matrix<T, R, C> {
    #[inline(always)]
    fn index_mut(&mut self, (r, c): (usize, usize)) -> &mut T {
        &mut self.cols[c][r]
    }
}

impl<T: fmt::Display, R: ArrayLength, C: ArrayLength> fmt::Display for Matrix<T, R, C> {
    /// Row by row, `[[a, b], [c, d]]`, every element formatted with the formatter's
    /// options (`{:.2}` gives two decimals each); `{:#}` puts each row on its own line.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec2, Matrix};
    /// let m = Matrix::from_rows([vec2(1.0f32, 0.5), vec2(-2.0, 0.0)]);
    /// assert_eq!(format!("{m}"), "[[1, 0.5], [-2, 0]]");
    /// assert_eq!(format!("{m:.1}"), "[[1.0, 0.5], [-2.0, 0.0]]");
    /// assert_eq!(format!("{m:#}"), "[[1, 0.5],\n [-2, 0]]");
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("[")?;
        for r in 0..R::USIZE {
            if r > 0 {
                f.write_str(if f.alternate() { ",\n " } else { ", " })?;
            }
            f.write_str("[")?;
            for c in 0..C::USIZE {
                if c > 0 {
                    f.write_str(", ")?;
                }
                fmt::Display::fmt(&self.cols[c][r], f)?;
            }
            f.write_str("]")?;
        }
        f.write_str("]")
    }
}

impl<T: fmt::Debug, R: ArrayLength, C: ArrayLength> fmt::Debug for Matrix<T, R, C> {
    /// The rows, as a list of lists.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        struct Row<'a, T, R: ArrayLength, C: ArrayLength>(&'a Matrix<T, R, C>, usize);
        impl<T: fmt::Debug, R: ArrayLength, C: ArrayLength> fmt::Debug for Row<'_, T, R, C> {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.debug_list()
                    .entries((0..C::USIZE).map(|c| &self.0.cols[c][self.1]))
                    .finish()
            }
        }
        f.debug_list()
            .entries((0..R::USIZE).map(|r| Row(self, r)))
            .finish()
    }
}

// ----- lazy element-wise expressions -------------------------------------------------------

/// A lazy matrix-valued expression: `Rows` × `Cols` elements of `Scalar`.
///
/// Implemented by `&Matrix` and by the element-wise nodes; element `(r, c)` is
/// `coeff(r, c)`, and [`MatExpr::eval`] computes all of them in one pass.
pub trait MatExpr: Sized {
    /// The element type.
    type Scalar: Scalar;
    /// The number of rows, a typenum unsigned integer.
    type Rows: ArrayLength;
    /// The number of columns.
    type Cols: ArrayLength;

    /// Element `(r, c)` of the result (`r < Rows`, `c < Cols`).
    fn coeff(&self, r: usize, c: usize) -> Self::Scalar;

    /// Computes the expression into a new matrix, in one pass, column by column.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{MatExpr, Mat2};
    /// let i = Mat2::<f64>::identity();
    /// let m = (&i * 3.0 - &i).eval();
    /// assert_eq!(m, Mat2::from_fn(|r, c| if r == c { 2.0 } else { 0.0 }));
    /// ```
    #[inline(always)]
    fn eval(self) -> Matrix<Self::Scalar, Self::Rows, Self::Cols> {
        Matrix::from_fn(|r, c| self.coeff(r, c))
    }
}

/// Something that can stand as the right operand of `+` or `-` on a matrix expression of
/// scalar `T` with `R` rows and `C` columns: a borrowed or owned [`Matrix`] or a matrix
/// expression. Its own scalar and dimensions are checked by [`SameScalar`] and
/// [`SameDim`], whose errors say which differs.
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not a matrix or matrix expression of `{T}`",
    label = "not a matrix operand",
    note = "`+` and `-` on matrices take a matrix of the same scalar and dimensions; multiply by a scalar with `*`"
)]
pub trait MatOperand<T: Scalar, R: ArrayLength, C: ArrayLength> {
    /// The expression this operand becomes.
    type Expr: MatExpr<Scalar = T, Rows = R, Cols = C>;
    /// Converts into the expression.
    fn into_mat_expr(self) -> Self::Expr;
}

/// An owned matrix used as a leaf (`a + b` with `a` and `b` moved in).
#[must_use = "expressions are lazy: call .eval() to compute"]
#[derive(Clone, Debug)]
pub struct MatOwned<T, R: ArrayLength, C: ArrayLength>(pub Matrix<T, R, C>);

/// A checked operand: reads `inner` as an expression of scalar `T`, `R` rows and `C`
/// columns, which [`SameScalar`] and [`SameDim`] proved it is.
#[must_use = "expressions are lazy: call .eval() to compute"]
#[derive(Clone, Copy, Debug)]
pub struct MatConform<E, T, R, C> {
    inner: E,
    ty: PhantomData<(T, R, C)>,
}

/// Element-wise `O(lhs, rhs)` of two matrix expressions (`+`, `-`).
#[must_use = "expressions are lazy: call .eval() to compute"]
#[derive(Clone, Copy, Debug)]
pub struct MatBinary<L, R, O> {
    lhs: L,
    rhs: R,
    op: PhantomData<O>,
}

/// Element-wise `O(inner)` (`-`).
#[must_use = "expressions are lazy: call .eval() to compute"]
#[derive(Clone, Copy, Debug)]
pub struct MatUnary<E, O> {
    inner: E,
    op: PhantomData<O>,
}

/// Every element of `inner` combined with one scalar: `O(inner, scalar)` (`*`, `/`).
#[must_use = "expressions are lazy: call .eval() to compute"]
#[derive(Clone, Copy, Debug)]
pub struct MatScale<E, T, O> {
    inner: E,
    scalar: T,
    op: PhantomData<O>,
}

impl<T: Scalar, R: ArrayLength, C: ArrayLength> MatExpr for &Matrix<T, R, C> {
    type Scalar = T;
    type Rows = R;
    type Cols = C;
    #[inline(always)]
    fn coeff(&self, r: usize, c: usize) -> T {
        self.cols[c].as_slice()[r]
    }
}

impl<T: Scalar, R: ArrayLength, C: ArrayLength> MatExpr for MatOwned<T, R, C> {
    type Scalar = T;
    type Rows = R;
    type Cols = C;
    #[inline(always)]
    fn coeff(&self, r: usize, c: usize) -> T {
        self.0.cols[c].as_slice()[r]
    }
}

impl<E, T, R, C> MatExpr for MatConform<E, T, R, C>
where
    E: MatExpr,
    T: Scalar,
    R: ArrayLength,
    C: ArrayLength,
    E::Scalar: SameScalar<T>,
    E::Rows: SameDim<R>,
    E::Cols: SameDim<C>,
{
    type Scalar = T;
    type Rows = R;
    type Cols = C;
    #[inline(always)]
    fn coeff(&self, r: usize, c: usize) -> T {
        self.inner.coeff(r, c).same()
    }
}

impl<L, R, O> MatExpr for MatBinary<L, R, O>
where
    L: MatExpr,
    R: MatExpr<Scalar = L::Scalar, Rows = L::Rows, Cols = L::Cols>,
    O: BinaryOp,
{
    type Scalar = L::Scalar;
    type Rows = L::Rows;
    type Cols = L::Cols;
    #[inline(always)]
    fn coeff(&self, r: usize, c: usize) -> L::Scalar {
        O::apply(self.lhs.coeff(r, c), self.rhs.coeff(r, c))
    }
}

impl<E: MatExpr, O: UnaryOp> MatExpr for MatUnary<E, O> {
    type Scalar = E::Scalar;
    type Rows = E::Rows;
    type Cols = E::Cols;
    #[inline(always)]
    fn coeff(&self, r: usize, c: usize) -> E::Scalar {
        O::apply(self.inner.coeff(r, c))
    }
}

impl<E: MatExpr<Scalar = T>, T: Scalar, O: BinaryOp> MatExpr for MatScale<E, T, O> {
    type Scalar = T;
    type Rows = E::Rows;
    type Cols = E::Cols;
    #[inline(always)]
    fn coeff(&self, r: usize, c: usize) -> T {
        O::apply(self.inner.coeff(r, c), self.scalar)
    }
}

/// Every matrix leaf and node is an operand of any scalar and dimensions at the impl
/// level; the where-clauses then require its own to be the same, so a mismatch is
/// reported by the plain-word errors of [`SameScalar`] and [`SameDim`].
macro_rules! mat_operand {
    ([$($g:tt)*] $ty:ty, |$s:ident| $conv:expr) => {
        impl<$($g)* T__: Scalar, R__: ArrayLength, C__: ArrayLength> MatOperand<T__, R__, C__>
            for $ty
        where
            $ty: MatLeaf,
            <$ty as MatLeaf>::Expr: MatExpr,
            <<$ty as MatLeaf>::Expr as MatExpr>::Scalar: SameScalar<T__>,
            <<$ty as MatLeaf>::Expr as MatExpr>::Rows: SameDim<R__>,
            <<$ty as MatLeaf>::Expr as MatExpr>::Cols: SameDim<C__>,
        {
            type Expr = MatConform<<$ty as MatLeaf>::Expr, T__, R__, C__>;
            #[inline(always)]
            fn into_mat_expr(self) -> Self::Expr {
                let $s = self;
                MatConform {
                    inner: $conv,
                    ty: PhantomData,
                }
            }
        }
    };
}

/// What a matrix value becomes inside an expression: itself for nodes and borrowed
/// matrices, a [`MatOwned`] leaf for an owned matrix.
pub trait MatLeaf {
    /// The expression type.
    type Expr;
    /// Converts into the expression.
    fn into_leaf(self) -> Self::Expr;
}

macro_rules! mat_leaf {
    ([$($g:tt)*] $ty:ty => $ety:ty, |$s:ident| $conv:expr) => {
        impl<$($g)*> MatLeaf for $ty {
            type Expr = $ety;
            #[inline(always)]
            fn into_leaf(self) -> $ety {
                let $s = self;
                $conv
            }
        }
        mat_operand!([$($g)*] $ty, |s| s.into_leaf());
    };
}

mat_leaf!(['a, T, R: ArrayLength, C: ArrayLength,] &'a Matrix<T, R, C> => &'a Matrix<T, R, C>, |s| s);
mat_leaf!([T, R: ArrayLength, C: ArrayLength,] Matrix<T, R, C> => MatOwned<T, R, C>, |s| MatOwned(s));
mat_leaf!([T, R: ArrayLength, C: ArrayLength,] MatOwned<T, R, C> => MatOwned<T, R, C>, |s| s);
mat_leaf!([E, T, R, C,] MatConform<E, T, R, C> => MatConform<E, T, R, C>, |s| s);
mat_leaf!([L, R, O,] MatBinary<L, R, O> => MatBinary<L, R, O>, |s| s);
mat_leaf!([E, O,] MatUnary<E, O> => MatUnary<E, O>, |s| s);
mat_leaf!([E, T, O,] MatScale<E, T, O> => MatScale<E, T, O>, |s| s);

// ----- products ---------------------------------------------------------------------------

/// Proof that the rows `Self` of the right operand of a matrix product equal the columns
/// `C` of the matrix on the left: implemented only for `C` itself.
#[diagnostic::on_unimplemented(
    message = "matrix product dimension mismatch: the matrix on the left has `{C}` columns, the operand on the right `{Self}` rows; `A * x` needs as many rows in `x` as `A` has columns",
    label = "the inner dimensions of this product differ",
    note = "the dimensions are typenum numbers: `UInt<UInt<UTerm, B1>, B0>` is U2, `UInt<UInt<UTerm, B1>, B1>` is U3, `UInt<UInt<UInt<UTerm, B1>, B0>, B0>` is U4",
    note = "to multiply by the transpose, write `a.transpose()`; to drop or add a row of a vector, `truncate()` or `extend(..)`"
)]
pub trait InnerDim<C> {}

impl<N: ArrayLength> InnerDim<N> for N {}

/// The right operand of `*` on a matrix expression `L` of scalar `T`: a `T` (lazy
/// scaling), a vector or vector expression (the product `L x`, a vector), or a matrix or
/// matrix expression (the product `L B`, a matrix).
#[diagnostic::on_unimplemented(
    message = "`{Self}` cannot multiply a matrix: the right operand of `*` on a matrix is a scalar of the matrix's type, a vector or a matrix",
    label = "not a scalar, vector or matrix of the matrix's scalar type",
    note = "with concrete types, a literal must have the matrix's scalar type: `&m * 2.0f32` for `f32` matrices"
)]
pub trait MatMulRhs<T, L> {
    /// The product type.
    type Output;
    /// `lhs * self`.
    fn mul_by(self, lhs: L) -> Self::Output;
}

/// `lhs * v` for an evaluated vector `v` with as many elements as `lhs` has columns
/// (`K` = `L::Cols`, proved by [`InnerDim`] at the caller): each element summed left to
/// right over the columns, as a linear combination of the columns. Index loops over the
/// compile-time dimensions, so after inlining there is no loop, bounds check or call.
#[inline(always)]
#[allow(clippy::needless_range_loop)]
fn mat_vec<L: MatExpr, K: ArrayLength>(
    lhs: &L,
    v: &Vector<L::Scalar, K>,
) -> Vector<L::Scalar, L::Rows> {
    assert!(K::USIZE == L::Cols::USIZE && K::USIZE > 0);
    let x0 = v[0];
    let mut y = Vector::from_fn(|r| lhs.coeff(r, 0) * x0);
    for k in 1..K::USIZE {
        let x = v[k];
        for r in 0..L::Rows::USIZE {
            y[r] += lhs.coeff(r, k) * x;
        }
    }
    y
}

/// A scalar of the matrix's own type scales every element, lazily.
impl<T: Scalar, L: MatExpr<Scalar = T>> MatMulRhs<T, L> for T {
    type Output = MatScale<L, T, MulOp>;
    #[inline(always)]
    fn mul_by(self, lhs: L) -> Self::Output {
        MatScale {
            inner: lhs,
            scalar: self,
            op: PhantomData,
        }
    }
}

/// Vectors and vector expressions: the product is a vector, computed at once.
macro_rules! vec_rhs {
    ([$($g:tt)*] $ty:ty) => {
        impl<$($g)* L__: MatExpr> MatMulRhs<L__::Scalar, L__> for $ty
        where
            $ty: Expr<Scalar = L__::Scalar>,
            <$ty as Expr>::Dim: InnerDim<L__::Cols>,
        {
            type Output = Vector<L__::Scalar, L__::Rows>;
            #[inline(always)]
            fn mul_by(self, lhs: L__) -> Self::Output {
                mat_vec(&lhs, &self.eval())
            }
        }
    };
}
vec_rhs!(['a, T, N: ArrayLength,] &'a Vector<T, N>);
vec_rhs!([T, N: ArrayLength,] Owned<T, N>);
vec_rhs!([T, N,] Splat<T, N>);
vec_rhs!([L, R, O,] Binary<L, R, O>);
vec_rhs!([E, O,] Unary<E, O>);
vec_rhs!([A, B, C,] MulAdd<A, B, C>);
vec_rhs!([M, A, B,] Select<M, A, B>);
vec_rhs!([E, F,] Map<E, F>);
vec_rhs!([E, T, N,] Conform<E, T, N>);

/// An owned vector.
impl<T: Scalar, N: ArrayLength, L: MatExpr<Scalar = T>> MatMulRhs<T, L> for Vector<T, N>
where
    N: InnerDim<L::Cols>,
{
    type Output = Vector<T, L::Rows>;
    #[inline(always)]
    fn mul_by(self, lhs: L) -> Self::Output {
        mat_vec(&lhs, &self)
    }
}

/// Matrices and matrix expressions: the product is a matrix, computed at once (the left
/// operand is evaluated first, since each of its elements is used `P` times).
macro_rules! mat_rhs {
    ([$($g:tt)*] $ty:ty) => {
        impl<$($g)* L__: MatExpr> MatMulRhs<L__::Scalar, L__> for $ty
        where
            $ty: MatLeaf,
            <$ty as MatLeaf>::Expr: MatExpr<Scalar = L__::Scalar>,
            <<$ty as MatLeaf>::Expr as MatExpr>::Rows: InnerDim<L__::Cols>,
        {
            type Output =
                Matrix<L__::Scalar, L__::Rows, <<$ty as MatLeaf>::Expr as MatExpr>::Cols>;
            #[inline(always)]
            fn mul_by(self, lhs: L__) -> Self::Output {
                let a = lhs.eval();
                let b = self.into_leaf().eval();
                Matrix {
                    cols: GenericArray::generate(|p| mat_vec(&&a, &b.cols[p])),
                }
            }
        }
    };
}
mat_rhs!(['a, T, R: ArrayLength, C: ArrayLength,] &'a Matrix<T, R, C>);
mat_rhs!([T, R: ArrayLength, C: ArrayLength,] Matrix<T, R, C>);
mat_rhs!([T, R: ArrayLength, C: ArrayLength,] MatOwned<T, R, C>);
mat_rhs!([E, T, R, C,] MatConform<E, T, R, C>);
mat_rhs!([L, R, O,] MatBinary<L, R, O>);
mat_rhs!([E, O,] MatUnary<E, O>);
mat_rhs!([E, T, O,] MatScale<E, T, O>);

// ----- operators ----------------------------------------------------------------------------

macro_rules! mat_ops {
    ([$($g:tt)*] $ty:ty) => {
        mat_ops!(@elementwise [$($g)*] $ty, Add, add, AddOp);
        mat_ops!(@elementwise [$($g)*] $ty, Sub, sub, SubOp);
        impl<$($g)* Rhs__> Mul<Rhs__> for $ty
        where
            $ty: MatLeaf,
            <$ty as MatLeaf>::Expr: MatExpr,
            Rhs__: MatMulRhs<
                <<$ty as MatLeaf>::Expr as MatExpr>::Scalar,
                <$ty as MatLeaf>::Expr,
            >,
        {
            type Output = Rhs__::Output;
            #[inline(always)]
            fn mul(self, rhs: Rhs__) -> Self::Output {
                rhs.mul_by(self.into_leaf())
            }
        }
        impl<$($g)* S__: Scalar> Div<S__> for $ty
        where
            $ty: MatLeaf,
            <$ty as MatLeaf>::Expr: MatExpr<Scalar = S__>,
        {
            type Output = MatScale<<$ty as MatLeaf>::Expr, S__, DivOp>;
            #[inline(always)]
            fn div(self, rhs: S__) -> Self::Output {
                MatScale { inner: self.into_leaf(), scalar: rhs, op: PhantomData }
            }
        }
        impl<$($g)*> Neg for $ty
        where
            $ty: MatLeaf,
            <$ty as MatLeaf>::Expr: MatExpr,
        {
            type Output = MatUnary<<$ty as MatLeaf>::Expr, NegOp>;
            #[inline(always)]
            fn neg(self) -> Self::Output {
                MatUnary { inner: self.into_leaf(), op: PhantomData }
            }
        }
        mat_ops!(@left [$($g)*] $ty, f32);
        mat_ops!(@left [$($g)*] $ty, f64);
    };
    // `matrix ± operand`: the element-wise sum or difference, lazily.
    (@elementwise [$($g:tt)*] $ty:ty, $trait:ident, $method:ident, $op:ty) => {
        impl<$($g)* Rhs__> $trait<Rhs__> for $ty
        where
            $ty: MatLeaf,
            <$ty as MatLeaf>::Expr: MatExpr,
            Rhs__: MatOperand<
                <<$ty as MatLeaf>::Expr as MatExpr>::Scalar,
                <<$ty as MatLeaf>::Expr as MatExpr>::Rows,
                <<$ty as MatLeaf>::Expr as MatExpr>::Cols,
            >,
        {
            type Output = MatBinary<<$ty as MatLeaf>::Expr, Rhs__::Expr, $op>;
            #[inline(always)]
            fn $method(self, rhs: Rhs__) -> Self::Output {
                MatBinary { lhs: self.into_leaf(), rhs: rhs.into_mat_expr(), op: PhantomData }
            }
        }
    };
    (@left [$($g:tt)*] $ty:ty, $t:ty) => {
        /// A plain float on the left scales every element, like on the right.
        impl<$($g)*> Mul<$ty> for $t
        where
            $ty: MatLeaf,
            <$ty as MatLeaf>::Expr: MatExpr<Scalar = $t>,
        {
            type Output = MatScale<<$ty as MatLeaf>::Expr, $t, MulOp>;
            #[inline(always)]
            fn mul(self, rhs: $ty) -> Self::Output {
                // IEEE multiplication is commutative: `s * x` is `x * s`, bit for bit.
                MatScale { inner: rhs.into_leaf(), scalar: self, op: PhantomData }
            }
        }
    };
}

mat_ops!(['a, T, R: ArrayLength, C: ArrayLength,] &'a Matrix<T, R, C>);
mat_ops!([T, R: ArrayLength, C: ArrayLength,] Matrix<T, R, C>);
mat_ops!([T, R: ArrayLength, C: ArrayLength,] MatOwned<T, R, C>);
mat_ops!([E, T, R, C,] MatConform<E, T, R, C>);
mat_ops!([L, R, O,] MatBinary<L, R, O>);
mat_ops!([E, O,] MatUnary<E, O>);
mat_ops!([E, T, O,] MatScale<E, T, O>);
