//! The storage type: a fixed-size vector whose dimension is a typenum type.

use crate::scalar::{Real, Scalar};
use core::fmt;
use core::ops::{Index, IndexMut};
use generic_array::sequence::GenericSequence;
use generic_array::{ArrayLength, ConstArrayLength, GenericArray, IntoArrayLength};
use typenum::{Const, U2, U3, U4};

/// A vector of `N` elements of type `T`, `N` a typenum unsigned (`U3`, `U1000`, ...).
///
/// Storage is a [`GenericArray`], inline, with the layout of `[T; N]`. Arithmetic on
/// vectors builds lazy expressions ([`Expr`](crate::Expr)); nothing is computed until
/// [`Expr::eval`](crate::Expr::eval) or [`Vector::assign`].
///
/// # Examples
/// ```
/// use vecexpr::{Vector, Expr, typenum::U4};
/// let a = Vector::<f32, U4>::from_fn(|i| i as f32);
/// let b = Vector::<f32, U4>::splat(2.0);
/// let c = (&a * &b + 1.0).eval();
/// assert_eq!(c.as_slice(), &[1.0, 3.0, 5.0, 7.0]);
/// ```
#[repr(transparent)]
pub struct Vector<T, N: ArrayLength> {
    data: GenericArray<T, N>,
}

/// Error returned by [`Vector::from_slice`] when the slice length differs from `N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LengthMismatch {
    /// The dimension of the vector.
    pub expected: usize,
    /// The length of the slice given.
    pub found: usize,
}

impl fmt::Display for LengthMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "slice of length {} cannot fill a vector of dimension {}",
            self.found, self.expected
        )
    }
}

impl std::error::Error for LengthMismatch {}

impl<T, N: ArrayLength> Vector<T, N> {
    /// The dimension `N` as a number.
    pub const DIM: usize = N::USIZE;

    /// Wraps a generic array.
    #[inline(always)]
    pub const fn from_generic_array(data: GenericArray<T, N>) -> Self {
        Self { data }
    }

    /// The underlying generic array.
    #[inline(always)]
    pub fn into_generic_array(self) -> GenericArray<T, N> {
        self.data
    }

    /// The underlying generic array, borrowed.
    #[inline(always)]
    pub fn as_generic_array(&self) -> &GenericArray<T, N> {
        &self.data
    }

    /// The underlying generic array, mutably borrowed.
    #[inline(always)]
    pub fn as_mut_generic_array(&mut self) -> &mut GenericArray<T, N> {
        &mut self.data
    }

    /// A vector whose element `i` is `f(i)`.
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> T) -> Self {
        Self {
            data: GenericArray::generate(f),
        }
    }

    /// A boxed vector whose element `i` is `f(i)`, built directly on the heap: use it for
    /// dimensions too large for the stack (a million elements).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{Vector, typenum::{U1000, U1000000}};
    /// type Big = Vector<f32, vecexpr::typenum::Prod<U1000, U1000>>;
    /// let v: Box<Big> = Vector::boxed_from_fn(|i| i as f32);
    /// assert_eq!(v[999_999], 999_999.0);
    /// # let _ = core::marker::PhantomData::<U1000000>;
    /// ```
    #[inline]
    pub fn boxed_from_fn(mut f: impl FnMut(usize) -> T) -> Box<Self> {
        let mut b = Box::<Self>::new_uninit();
        let base = b.as_mut_ptr().cast::<T>();
        let mut guard = PartialInit { base, len: 0 };
        for i in 0..N::USIZE {
            // SAFETY: Vector<T, N> is repr(transparent) over GenericArray<T, N>, laid out as
            // [T; N]; i < N keeps the write inside the allocation, and the slot is unwritten.
            unsafe { base.add(i).write(f(i)) };
            guard.len = i + 1;
        }
        core::mem::forget(guard);
        // SAFETY: all N elements were written above.
        unsafe { b.assume_init() }
    }

    /// Copies a slice of exactly `N` elements.
    ///
    /// # Errors
    /// [`LengthMismatch`] if `slice.len() != N`.
    ///
    /// # Examples
    /// ```
    /// use vecexpr::{vec3, LengthMismatch, Vec3};
    /// let data = [1.0f32, 2.0, 3.0, 4.0];
    /// assert_eq!(Vec3::from_slice(&data[1..]), Ok(vec3(2.0, 3.0, 4.0)));
    /// let err = Vec3::<f32>::from_slice(&data).unwrap_err();
    /// assert_eq!(err, LengthMismatch { expected: 3, found: 4 });
    /// assert_eq!(err.to_string(), "slice of length 4 cannot fill a vector of dimension 3");
    /// ```
    #[inline]
    pub fn from_slice(slice: &[T]) -> Result<Self, LengthMismatch>
    where
        T: Clone,
    {
        if slice.len() != N::USIZE {
            return Err(LengthMismatch {
                expected: N::USIZE,
                found: slice.len(),
            });
        }
        Ok(Self::from_fn(|i| slice[i].clone()))
    }

    /// The elements as a slice of length `N`.
    #[inline(always)]
    pub fn as_slice(&self) -> &[T] {
        self.data.as_slice()
    }

    /// The elements as a mutable slice of length `N`.
    #[inline(always)]
    pub fn as_mut_slice(&mut self) -> &mut [T] {
        self.data.as_mut_slice()
    }

    /// Iterates over the elements.
    #[inline]
    pub fn iter(&self) -> core::slice::Iter<'_, T> {
        self.data.iter()
    }

    /// Iterates mutably over the elements.
    #[inline]
    pub fn iter_mut(&mut self) -> core::slice::IterMut<'_, T> {
        self.data.iter_mut()
    }

    /// Converts to a plain array `[T; K]` (`K` must equal `N`, checked at compile time).
    #[inline(always)]
    pub fn into_array<const K: usize>(self) -> [T; K]
    where
        Const<K>: IntoArrayLength<ArrayLength = N>,
    {
        self.data.into_array()
    }
}

/// Drops the elements written so far if `f` panics half-way through a boxed fill.
struct PartialInit<T> {
    base: *mut T,
    len: usize,
}

impl<T> Drop for PartialInit<T> {
    fn drop(&mut self) {
        // SAFETY: exactly the first `len` elements were initialised and are dropped once;
        // the allocation itself is freed by the Box of MaybeUninit that owns it.
        unsafe {
            core::ptr::drop_in_place(core::ptr::slice_from_raw_parts_mut(self.base, self.len))
        };
    }
}

impl<T: Copy, N: ArrayLength> Vector<T, N> {
    /// Every element set to `x`.
    #[inline(always)]
    pub fn splat(x: T) -> Self {
        Self::from_fn(|_| x)
    }

    /// A boxed vector with every element set to `x`, built on the heap.
    #[inline]
    pub fn boxed_splat(x: T) -> Box<Self> {
        Self::boxed_from_fn(|_| x)
    }
}

impl<T: Scalar, N: ArrayLength> Vector<T, N> {
    /// The zero vector.
    #[inline(always)]
    pub fn zero() -> Self {
        Self::splat(T::zero())
    }

    /// The `i`-th unit vector.
    ///
    /// # Panics
    /// If `i >= N`.
    #[inline]
    pub fn unit(i: usize) -> Self {
        assert!(
            i < N::USIZE,
            "unit vector {i} out of range for dimension {}",
            N::USIZE
        );
        Self::from_fn(|j| if i == j { T::one() } else { T::zero() })
    }

    /// In-place map: `self[i] = f(self[i])`.
    #[inline(always)]
    pub fn apply(&mut self, f: impl Fn(T) -> T) {
        for x in self.data.iter_mut() {
            *x = f(*x);
        }
    }
}

/// `|a - b| <= tol * max(1, |a|, |b|)`, with equal values (including infinities) always
/// close and NaN never.
pub fn approx_eq_scalar<T: Real>(a: T, b: T, tol: T) -> bool {
    if a == b {
        return true;
    }
    if a.is_nan() || b.is_nan() || !a.is_finite() || !b.is_finite() {
        return false;
    }
    let scale = T::ONE.max_num(a.abs()).max_num(b.abs());
    (a - b).abs() <= tol * scale
}

/// Asserts that two vectors (or anything with `approx_eq`) are close, printing both on
/// failure.
///
/// # Examples
/// ```
/// use vecexpr::{assert_approx_eq, vec3};
/// assert_approx_eq!(vec3(1.0f32, 2.0, 3.0), vec3(1.0, 2.0, 3.000001), 1e-6);
/// ```
#[macro_export]
macro_rules! assert_approx_eq {
    ($a:expr, $b:expr, $tol:expr $(,)?) => {{
        let (a, b) = (&$a, &$b);
        assert!(
            a.approx_eq(b, $tol),
            "assertion failed: {:?} ≈ {:?} (tolerance {})",
            a,
            b,
            $tol
        );
    }};
}

impl<T: Copy, N: ArrayLength> Vector<T, N> {
    /// Appends `last`, giving a vector of dimension `N + 1` (for example a point's
    /// homogeneous form).
    ///
    /// # Examples
    /// ```
    /// use vecexpr::vec3;
    /// let h = vec3(1.0f32, 2.0, 3.0).extend(1.0);
    /// assert_eq!(h.as_slice(), &[1.0, 2.0, 3.0, 1.0]);
    /// assert_eq!(h.truncate(), vec3(1.0, 2.0, 3.0));
    /// ```
    #[inline(always)]
    pub fn extend(self, last: T) -> Vector<T, typenum::Add1<N>>
    where
        N: core::ops::Add<typenum::B1>,
        typenum::Add1<N>: ArrayLength,
    {
        Vector::from_fn(|i| if i < N::USIZE { self.data[i] } else { last })
    }

    /// Drops the last element, giving a vector of dimension `N - 1`.
    #[inline(always)]
    pub fn truncate(self) -> Vector<T, typenum::Sub1<N>>
    where
        N: core::ops::Sub<typenum::B1>,
        typenum::Sub1<N>: ArrayLength,
    {
        Vector::from_fn(|i| self.data[i])
    }

    /// Any dimension `M <= N`: the first `M` elements (`M > N` fails to compile).
    #[inline(always)]
    pub fn resize_down<M>(self) -> Vector<T, M>
    where
        M: ArrayLength + typenum::IsLessOrEqual<N, Output = typenum::True>,
    {
        Vector::from_fn(|i| self.data[i])
    }
}

/// A 2-vector.
#[inline(always)]
pub fn vec2<T>(x: T, y: T) -> Vector<T, U2> {
    Vector::from_generic_array(GenericArray::from_array([x, y]))
}

/// A 3-vector.
///
/// # Examples
/// ```
/// let v = vecexpr::vec3(1.0f32, 2.0, 3.0);
/// assert_eq!(v[2], 3.0);
/// ```
#[inline(always)]
pub fn vec3<T>(x: T, y: T, z: T) -> Vector<T, U3> {
    Vector::from_generic_array(GenericArray::from_array([x, y, z]))
}

/// A 4-vector.
#[inline(always)]
pub fn vec4<T>(x: T, y: T, z: T, w: T) -> Vector<T, U4> {
    Vector::from_generic_array(GenericArray::from_array([x, y, z, w]))
}

impl<T: Copy> Vector<T, U3> {
    /// Element 0.
    #[inline(always)]
    pub fn x(&self) -> T {
        self.data[0]
    }
    /// Element 1.
    #[inline(always)]
    pub fn y(&self) -> T {
        self.data[1]
    }
    /// Element 2.
    #[inline(always)]
    pub fn z(&self) -> T {
        self.data[2]
    }
}

impl<T: Clone, N: ArrayLength> Clone for Vector<T, N> {
    #[inline(always)]
    fn clone(&self) -> Self {
        Self {
            data: self.data.clone(),
        }
    }
}

impl<T: Copy, N: ArrayLength> Copy for Vector<T, N> where GenericArray<T, N>: Copy {}

impl<T: Default, N: ArrayLength> Default for Vector<T, N> {
    #[inline(always)]
    fn default() -> Self {
        Self {
            data: GenericArray::default(),
        }
    }
}

impl<T: PartialEq, N: ArrayLength> PartialEq for Vector<T, N> {
    #[inline]
    fn eq(&self, other: &Self) -> bool {
        self.data == other.data
    }
}

impl<T: Eq, N: ArrayLength> Eq for Vector<T, N> {}

impl<T: fmt::Debug, N: ArrayLength> fmt::Debug for Vector<T, N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.data.iter()).finish()
    }
}

impl<T: fmt::Display, N: ArrayLength> fmt::Display for Vector<T, N> {
    /// `[x, y, z]`, every element formatted with the formatter's options (`{:.2}` gives
    /// two decimals each).
    ///
    /// # Examples
    /// ```
    /// let v = vecexpr::vec3(1.0f32, 0.5, -2.0);
    /// assert_eq!(format!("{v}"), "[1, 0.5, -2]");
    /// assert_eq!(format!("{v:.2}"), "[1.00, 0.50, -2.00]");
    /// ```
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("[")?;
        for (i, x) in self.data.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            fmt::Display::fmt(x, f)?;
        }
        f.write_str("]")
    }
}

impl<T, N: ArrayLength> Index<usize> for Vector<T, N> {
    type Output = T;
    #[inline(always)]
    fn index(&self, i: usize) -> &T {
        &self.data[i]
    }
}

impl<T, N: ArrayLength> IndexMut<usize> for Vector<T, N> {
    #[inline(always)]
    fn index_mut(&mut self, i: usize) -> &mut T {
        &mut self.data[i]
    }
}

impl<'a, T, N: ArrayLength> IntoIterator for &'a Vector<T, N> {
    type Item = &'a T;
    type IntoIter = core::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.data.iter()
    }
}

impl<'a, T, N: ArrayLength> IntoIterator for &'a mut Vector<T, N> {
    type Item = &'a mut T;
    type IntoIter = core::slice::IterMut<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.data.iter_mut()
    }
}

impl<T, N: ArrayLength> IntoIterator for Vector<T, N> {
    type Item = T;
    type IntoIter = generic_array::GenericArrayIter<T, N>;
    fn into_iter(self) -> Self::IntoIter {
        self.data.into_iter()
    }
}

impl<T, const K: usize> From<[T; K]> for Vector<T, ConstArrayLength<K>>
where
    Const<K>: IntoArrayLength,
{
    #[inline(always)]
    fn from(a: [T; K]) -> Self {
        Self {
            data: GenericArray::from_array(a),
        }
    }
}

impl<T, N: ArrayLength> From<GenericArray<T, N>> for Vector<T, N> {
    #[inline(always)]
    fn from(data: GenericArray<T, N>) -> Self {
        Self { data }
    }
}

impl<T, N: ArrayLength> AsRef<[T]> for Vector<T, N> {
    fn as_ref(&self) -> &[T] {
        &self.data
    }
}

impl<T, N: ArrayLength> AsMut<[T]> for Vector<T, N> {
    fn as_mut(&mut self) -> &mut [T] {
        &mut self.data
    }
}
