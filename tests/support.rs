//! Shared helpers for the integration tests: a naive eager reference implementation of
//! every vecexpr operation, lane bookkeeping for packets, bit-exact and tolerance
//! assertions, and the macros that instantiate a test body per scalar type and dimension.
//!
//! # How the property tests compare
//! A `Vector<T, N>` of a packet `T` with `L` lanes is `L` independent `N`-vectors of the
//! lane type `E` (`f32` or `f64`). The tests keep every operand as a plain `Vec<E>` of
//! `N * L` elements in *lane-major* order (lane `l`, element `i` at `l * N + i`; see
//! [`build`] and [`lanes`]), run the fused vecexpr expression on the vector, and run the
//! [`naive`] reference, plain loops over slices, on the `Vec<E>`s. Element-wise results
//! must agree bit for bit (any NaN matches any NaN, because Rust leaves NaN payloads
//! unspecified; the sign of zero must match). Reductions run per lane on slices of
//! length `N`.
//!
//! The property-test runner and input strategies live in `tests/prop.rs`, a module the
//! property tests include with `mod prop;` (they need `proptest`, a dev-dependency, which
//! this library cannot use).
//!
//! # Type rules that must not compile
//! vecexpr's own crate docs check `U3 + U4`, `f32 + f64` and `a.assign(&a + &b)`. The
//! cases below extend them. Each `compile_fail` block names the line that must fail; the
//! control block after them holds the same operations with matching types and shows that
//! the failing line is the only problem. The error codes are those rustc reports for the
//! marked line (stable rustdoc does not compare them; nightly does).
//!
//! A cross product is defined for 3-vectors only:
//! ```compile_fail,E0271
//! use vecexpr::{Vector, Expr, typenum::U4};
//! let a = Vector::<f32, U4>::splat(1.0);
//! let b = Vector::<f32, U4>::splat(2.0);
//! // MUST FAIL: `cross` requires `Dim = U3`.
//! let _ = a.cross(&b);
//! ```
//! A dimension mismatch fails for every binary operation, not only `+`:
//! ```compile_fail,E0271
//! use vecexpr::{Vector, Expr, typenum::{U3, U4}};
//! let a = Vector::<f64, U3>::splat(1.0);
//! let b = Vector::<f64, U4>::splat(1.0);
//! // MUST FAIL: a U4 operand for a U3 dot product.
//! let _ = a.dot(&b);
//! ```
//! ```compile_fail,E0271
//! use vecexpr::{Vector, Expr, typenum::{U3, U4}};
//! let a = Vector::<f32, U3>::splat(1.0);
//! let b = Vector::<f32, U4>::splat(1.0);
//! // MUST FAIL: element-wise min of a U3 and a U4 expression.
//! let _ = a.min(&b).eval();
//! ```
//! Assigning an expression of another dimension to a vector fails:
//! ```compile_fail,E0271
//! use vecexpr::{Vector, typenum::{U3, U4}};
//! let a = Vector::<f32, U4>::splat(1.0);
//! let mut out = Vector::<f32, U3>::zero();
//! // MUST FAIL: a U4 expression assigned into a U3 vector.
//! out.assign(&a * 2.0f32);
//! ```
//! Scalar types never mix: not an `f64` scalar with an `f32` vector,
//! ```compile_fail,E0277
//! use vecexpr::{vec3, Expr};
//! let a = vec3(1.0f32, 2.0, 3.0);
//! // MUST FAIL: an f64 scalar operand for an f32 expression.
//! let _ = (&a * 2.0f64).eval();
//! ```
//! not packets of different widths,
//! ```compile_fail,E0271
//! use vecexpr::{Vector, Expr, PacketF32x4, PacketF32x8, typenum::U3};
//! let a = Vector::<PacketF32x4, U3>::zero();
//! let b = Vector::<PacketF32x8, U3>::zero();
//! // MUST FAIL: 4-lane and 8-lane packets in one expression.
//! let _ = (&a + &b).eval();
//! ```
//! and not `f32` and `f64` in an in-place update:
//! ```compile_fail,E0271
//! use vecexpr::vec3;
//! let mut a = vec3(1.0f32, 2.0, 3.0);
//! let b = vec3(1.0f64, 2.0, 3.0);
//! // MUST FAIL: an f64 vector added in place to an f32 vector.
//! a += &b;
//! ```
//! The in-place forms refuse aliasing like `assign` does (use `a *= 2.0` instead):
//! ```compile_fail,E0502
//! use vecexpr::vec3;
//! let mut a = vec3(1.0f32, 2.0, 3.0);
//! // MUST FAIL: `a` is borrowed mutably and immutably at once.
//! a.update(&a, |x, y| x + y);
//! ```
//! ```compile_fail,E0502
//! use vecexpr::{vec3, Expr};
//! let mut a = vec3(1.0f32, 2.0, 3.0);
//! let b = vec3(1.0f32, 2.0, 3.0);
//! // MUST FAIL: the destination appears in its own (deeper) expression.
//! a.assign((&b * &a).sqrt() + 1.0f32);
//! ```
//! Compile-time dimension arithmetic is checked too:
//! ```compile_fail,E0271
//! use vecexpr::{vec3, Vector};
//! let a = vec3(1.0f32, 2.0, 3.0);
//! // MUST FAIL: `into_array` needs the array length to equal the dimension.
//! let _: [f32; 4] = a.into_array();
//! ```
//! ```compile_fail,E0271
//! use vecexpr::{vec3, typenum::U4};
//! let a = vec3(1.0f32, 2.0, 3.0);
//! // MUST FAIL: `resize_down` cannot grow a vector.
//! let _ = a.resize_down::<U4>();
//! ```
//! ```compile_fail,E0308
//! use vecexpr::{vec3, Vector, typenum::U3};
//! let a = vec3(1.0f32, 2.0, 3.0);
//! // MUST FAIL: `extend` gives a U4 vector, not a U3 one.
//! let _: Vector<f32, U3> = a.extend(4.0);
//! ```
//! The control: every operation above with matching types compiles and runs.
//! ```
//! use vecexpr::{vec3, Expr, Vector, PacketF32x4, typenum::{U2, U3, U4}};
//! let a = Vector::<f32, U3>::splat(1.0);
//! let b = Vector::<f32, U3>::splat(2.0);
//! assert_eq!(a.cross(&b), Vector::zero());
//! assert_eq!(a.dot(&b), 6.0);
//! assert_eq!(a.min(&b).eval(), a);
//! let mut out = Vector::<f32, U3>::zero();
//! out.assign(&a * 2.0f32);
//! assert_eq!(out, b);
//! let p = Vector::<PacketF32x4, U3>::zero();
//! assert_eq!((&p + &p).eval(), p);
//! let mut c = vec3(1.0f32, 2.0, 3.0);
//! let c0 = c;
//! c += &c0;
//! c.update(&c0, |x, y| x + y);
//! c.assign((&b * &c0).sqrt() + 1.0f32);
//! let _: [f32; 3] = c.into_array();
//! let _: Vector<f32, U2> = c.resize_down::<U2>();
//! let _: Vector<f32, U4> = c.extend(4.0);
//! ```

use vecexpr::generic_array::ArrayLength;
use vecexpr::{Expr, Mask, Packet, Real, Scalar, Vector};

pub use vecexpr;

// ----- scalar plumbing ------------------------------------------------------------------

/// A lane type (`f32` or `f64`) with the operations the reference implementation needs,
/// taken from `std` directly rather than from vecexpr's [`Scalar`] impls.
pub trait RefFloat: Real {
    /// The raw IEEE bits, widened to `u64`.
    fn bits(self) -> u64;
    /// From raw IEEE bits (the low 32 bits for `f32`).
    fn from_bits_u64(bits: u64) -> Self;
    /// `std`'s absolute value.
    fn std_abs(self) -> Self;
    /// `std`'s correctly rounded square root.
    fn std_sqrt(self) -> Self;
    /// `std`'s fused multiply-add `self * a + b`.
    fn std_mul_add(self, a: Self, b: Self) -> Self;
    /// Values that exercise the edges of IEEE arithmetic: signed zeros, infinities, NaN,
    /// the smallest subnormal and normal, the largest finite value, epsilon.
    fn specials() -> Vec<Self>;
}

macro_rules! ref_float {
    ($t:ident) => {
        impl RefFloat for $t {
            fn bits(self) -> u64 {
                u64::from(<$t>::to_bits(self))
            }
            fn from_bits_u64(bits: u64) -> Self {
                // Truncation to the lane width is intended.
                #[allow(clippy::cast_possible_truncation)]
                <$t>::from_bits(bits as _)
            }
            fn std_abs(self) -> Self {
                <$t>::abs(self)
            }
            fn std_sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            fn std_mul_add(self, a: Self, b: Self) -> Self {
                <$t>::mul_add(self, a, b)
            }
            fn specials() -> Vec<Self> {
                vec![
                    0.0,
                    -0.0,
                    1.0,
                    -1.0,
                    <$t>::INFINITY,
                    <$t>::NEG_INFINITY,
                    <$t>::NAN,
                    <$t>::MIN_POSITIVE,
                    -<$t>::MIN_POSITIVE,
                    <$t>::from_bits(1),
                    -<$t>::from_bits(1),
                    <$t>::MAX,
                    <$t>::MIN,
                    <$t>::EPSILON,
                ]
            }
        }
    };
}
ref_float!(f32);
ref_float!(f64);

/// A vecexpr [`Scalar`] the tests can build lane by lane: `f32`, `f64` or a [`Packet`].
pub trait TestScalar: Scalar<Elem: RefFloat> {
    /// Is this a multi-lane packet (affects only the expected `Debug` text)?
    const IS_PACKET: bool;
    /// The scalar whose lane `l` is `f(l)`.
    fn from_lanes(f: impl FnMut(usize) -> Self::Elem) -> Self;
}

impl TestScalar for f32 {
    const IS_PACKET: bool = false;
    fn from_lanes(mut f: impl FnMut(usize) -> f32) -> f32 {
        f(0)
    }
}

impl TestScalar for f64 {
    const IS_PACKET: bool = false;
    fn from_lanes(mut f: impl FnMut(usize) -> f64) -> f64 {
        f(0)
    }
}

impl<E: RefFloat, L: ArrayLength> TestScalar for Packet<E, L>
where
    Packet<E, L>: Scalar<Elem = E>,
{
    const IS_PACKET: bool = true;
    fn from_lanes(f: impl FnMut(usize) -> E) -> Self {
        Packet::from_fn(f)
    }
}

/// The lane type of a test scalar.
pub type ElemOf<T> = <T as Scalar>::Elem;

// ----- lane-major data ------------------------------------------------------------------

/// Builds a vector from lane-major data: element `i`, lane `l` is `data[l * N + i]`.
///
/// # Panics
/// If `data.len() != N * LANES`.
#[inline(never)]
pub fn build<T: TestScalar, N: ArrayLength>(data: &[T::Elem]) -> Vector<T, N> {
    let k = N::USIZE;
    assert_eq!(
        data.len(),
        k * T::LANES,
        "lane-major data of the wrong length"
    );
    Vector::from_fn(|i| T::from_lanes(|l| data[l * k + i]))
}

/// A boxed vector from lane-major data, built on the heap (for huge dimensions).
///
/// # Panics
/// If `data.len() != N * LANES`.
#[inline(never)]
pub fn build_boxed<T: TestScalar, N: ArrayLength>(data: &[T::Elem]) -> Box<Vector<T, N>> {
    let k = N::USIZE;
    assert_eq!(
        data.len(),
        k * T::LANES,
        "lane-major data of the wrong length"
    );
    Vector::boxed_from_fn(|i| T::from_lanes(|l| data[l * k + i]))
}

/// The elements of a vector in lane-major order (the inverse of [`build`]).
#[inline(never)]
pub fn lanes<T: TestScalar, N: ArrayLength>(v: &Vector<T, N>) -> Vec<T::Elem> {
    let k = N::USIZE;
    (0..k * T::LANES).map(|j| v[j % k].lane(j / k)).collect()
}

/// The lanes of one scalar, in order.
#[inline(never)]
pub fn scalar_lanes<T: Scalar>(s: T) -> Vec<T::Elem> {
    (0..T::LANES).map(|l| s.lane(l)).collect()
}

/// A mask vector in lane-major order.
#[inline(never)]
pub fn mask_lanes<M: Mask, N: ArrayLength>(v: &Vector<M, N>) -> Vec<bool> {
    let k = N::USIZE;
    (0..k * M::LANES).map(|j| v[j % k].test(j / k)).collect()
}

/// The lanes of one mask value, in order.
#[inline(never)]
pub fn mask_bits<M: Mask>(m: M) -> Vec<bool> {
    (0..M::LANES).map(|l| m.test(l)).collect()
}

/// Lane-major data for a per-lane scalar broadcast over `k` elements: lane `l` of the
/// scalar is repeated `k` times.
#[inline(never)]
pub fn broadcast<E: Copy>(per_lane: &[E], k: usize) -> Vec<E> {
    per_lane
        .iter()
        .flat_map(|&x| core::iter::repeat_n(x, k))
        .collect()
}

/// How many property-test cases to run for a vector of `k` elements of `lanes` lanes:
/// 64 for small inputs, fewer as the data grows so the suite stays fast.
pub const fn cases(k: usize, lanes: usize) -> u32 {
    let len = k * lanes;
    if len >= 4000 {
        8
    } else if len >= 1000 {
        16
    } else if len >= 64 {
        32
    } else {
        64
    }
}

// ----- comparisons ----------------------------------------------------------------------

/// Are `a` and `b` the same value bit for bit, treating every NaN as the same?
#[inline(never)]
pub fn same<E: RefFloat>(a: E, b: E) -> bool {
    a.bits() == b.bits() || (a.is_nan() && b.is_nan())
}

/// Asserts that `got` and `want` agree element by element in the sense of [`same`].
///
/// # Panics
/// On a length mismatch or the first differing element, naming `what` and the index.
#[track_caller]
#[inline(never)]
pub fn assert_same<E: RefFloat>(got: &[E], want: &[E], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: length");
    if let Some(j) = (0..got.len()).find(|&j| !same(got[j], want[j])) {
        panic!(
            "{what}: element {j} (lane-major) differs: got {:?} ({:#x}), reference {:?} ({:#x})",
            got[j],
            got[j].bits(),
            want[j],
            want[j].bits()
        );
    }
}

/// Asserts that a vector equals lane-major reference data bit for bit.
///
/// # Panics
/// On the first differing element.
#[track_caller]
#[inline(never)]
pub fn assert_vec_same<T: TestScalar, N: ArrayLength>(
    got: &Vector<T, N>,
    want: &[T::Elem],
    what: &str,
) {
    assert_same(&lanes(got), want, what);
}

/// Evaluates the expression `x` and asserts that the result equals lane-major reference
/// data bit for bit.
///
/// Each expression type gets its own small, separately optimised copy of this function,
/// which keeps the test binaries quick to build.
///
/// # Panics
/// On the first differing element.
#[inline(never)]
#[track_caller]
pub fn assert_expr<X>(x: X, want: &[ElemOf<X::Scalar>], what: &str)
where
    X: Expr,
    X::Scalar: TestScalar,
{
    assert_vec_same(&x.eval(), want, what);
}

/// Asserts that every lane of a scalar result equals the per-lane reference.
///
/// # Panics
/// On the first differing lane.
#[track_caller]
#[inline(never)]
pub fn assert_scalar_same<T: TestScalar>(got: T, want: &[T::Elem], what: &str) {
    assert_same(&scalar_lanes(got), want, what);
}

/// Asserts `|got - want| <= tol * max(1, |got|, |want|)` element by element (see
/// [`naive::approx_eq`]); NaN must meet NaN.
///
/// # Panics
/// On the first element outside the tolerance.
#[track_caller]
#[inline(never)]
pub fn assert_close<E: RefFloat>(got: &[E], want: &[E], tol: E, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: length");
    for (j, (&g, &w)) in got.iter().zip(want).enumerate() {
        let ok = (g.is_nan() && w.is_nan()) || naive::approx_eq(g, w, tol);
        assert!(
            ok,
            "{what}: element {j} (lane-major): got {g:?}, reference {w:?}, tolerance {tol:?}"
        );
    }
}

/// Applies `f` to each lane's slice of lane-major data (`k` elements per lane).
#[inline(never)]
pub fn per_lane<E: Copy, R>(data: &[E], k: usize, f: impl Fn(&[E]) -> R) -> Vec<R> {
    data.chunks(k).map(f).collect()
}

/// Applies `f` to each lane's slices of two lane-major operands.
#[inline(never)]
pub fn per_lane2<E: Copy, R>(a: &[E], b: &[E], k: usize, f: impl Fn(&[E], &[E]) -> R) -> Vec<R> {
    a.chunks(k).zip(b.chunks(k)).map(|(x, y)| f(x, y)).collect()
}

/// The `Debug` text a vector of lane-major `data` must print: `[e0, e1, ...]`, where a
/// packet element prints as its list of lanes.
#[inline(never)]
pub fn debug_reference<T: TestScalar>(data: &[T::Elem], k: usize) -> String {
    let elems: Vec<String> = (0..k)
        .map(|i| {
            if T::IS_PACKET {
                let l: Vec<String> = (0..T::LANES)
                    .map(|l| format!("{:?}", data[l * k + i]))
                    .collect();
                format!("[{}]", l.join(", "))
            } else {
                format!("{:?}", data[i])
            }
        })
        .collect();
    format!("[{}]", elems.join(", "))
}

// ----- the reference implementation -----------------------------------------------------

/// The naive eager reference: every operation as a plain loop over slices, each element
/// computed with the same operations in the same order as the formula reads, allocating
/// a fresh `Vec` per operation. Nothing here uses vecexpr's arithmetic.
pub mod naive {
    use super::RefFloat;
    use vecexpr::assign::{reduce_strategy, ReduceStrategy, PARTIAL_SUMS};

    /// `f(a[i])` for every `i`.
    #[inline(never)]
    pub fn map<E: Copy>(a: &[E], f: impl Fn(E) -> E) -> Vec<E> {
        a.iter().map(|&x| f(x)).collect()
    }

    /// `f(a[i], b[i])` for every `i`.
    ///
    /// # Panics
    /// If the lengths differ.
    #[inline(never)]
    pub fn zip<E: Copy>(a: &[E], b: &[E], f: impl Fn(E, E) -> E) -> Vec<E> {
        assert_eq!(a.len(), b.len());
        a.iter().zip(b).map(|(&x, &y)| f(x, y)).collect()
    }

    /// `f(a[i], b[i], c[i])` for every `i`.
    ///
    /// # Panics
    /// If the lengths differ.
    #[inline(never)]
    pub fn zip3<E: Copy>(a: &[E], b: &[E], c: &[E], f: impl Fn(E, E, E) -> E) -> Vec<E> {
        assert!(a.len() == b.len() && b.len() == c.len());
        (0..a.len()).map(|i| f(a[i], b[i], c[i])).collect()
    }

    /// `a + b`.
    #[inline(never)]
    pub fn add<E: RefFloat>(a: &[E], b: &[E]) -> Vec<E> {
        zip(a, b, |x, y| x + y)
    }
    /// `a - b`.
    #[inline(never)]
    pub fn sub<E: RefFloat>(a: &[E], b: &[E]) -> Vec<E> {
        zip(a, b, |x, y| x - y)
    }
    /// `a * b`.
    #[inline(never)]
    pub fn mul<E: RefFloat>(a: &[E], b: &[E]) -> Vec<E> {
        zip(a, b, |x, y| x * y)
    }
    /// `a / b`.
    #[inline(never)]
    pub fn div<E: RefFloat>(a: &[E], b: &[E]) -> Vec<E> {
        zip(a, b, |x, y| x / y)
    }
    /// `-a`.
    #[inline(never)]
    pub fn neg<E: RefFloat>(a: &[E]) -> Vec<E> {
        map(a, |x| -x)
    }
    /// `|a|`.
    #[inline(never)]
    pub fn abs<E: RefFloat>(a: &[E]) -> Vec<E> {
        map(a, E::std_abs)
    }
    /// `sqrt(a)`.
    #[inline(never)]
    pub fn sqrt<E: RefFloat>(a: &[E]) -> Vec<E> {
        map(a, E::std_sqrt)
    }
    /// `1 / a`.
    #[inline(never)]
    pub fn recip<E: RefFloat>(a: &[E]) -> Vec<E> {
        map(a, |x| E::ONE / x)
    }
    /// `a * b + c` with one rounding.
    #[inline(never)]
    pub fn mul_add<E: RefFloat>(a: &[E], b: &[E], c: &[E]) -> Vec<E> {
        zip3(a, b, c, E::std_mul_add)
    }

    /// The order key of IEEE 754-2019 `minimum`/`maximum` for non-NaN values: the value
    /// in `f64`, then `-0.0` before `+0.0`.
    fn order_key<E: RefFloat>(x: E) -> (f64, bool) {
        let w = x.to_f64();
        (w, !w.is_sign_negative())
    }
    /// IEEE 754-2019 `minimum`: NaN if either operand is NaN, else the smaller with
    /// `-0.0 < +0.0`.
    #[inline(never)]
    pub fn minimum<E: RefFloat>(a: E, b: E) -> E {
        if a.is_nan() || b.is_nan() {
            return E::NAN;
        }
        if order_key(a) <= order_key(b) {
            a
        } else {
            b
        }
    }
    /// IEEE 754-2019 `maximum`: NaN if either operand is NaN, else the larger with
    /// `+0.0 > -0.0`.
    #[inline(never)]
    pub fn maximum<E: RefFloat>(a: E, b: E) -> E {
        if a.is_nan() || b.is_nan() {
            return E::NAN;
        }
        if order_key(a) >= order_key(b) {
            a
        } else {
            b
        }
    }
    /// Element-wise [`minimum`].
    #[inline(never)]
    pub fn min<E: RefFloat>(a: &[E], b: &[E]) -> Vec<E> {
        zip(a, b, minimum)
    }
    /// Element-wise [`maximum`].
    #[inline(never)]
    pub fn max<E: RefFloat>(a: &[E], b: &[E]) -> Vec<E> {
        zip(a, b, maximum)
    }
    /// `if m[i] { a[i] } else { b[i] }`.
    #[inline(never)]
    pub fn select<E: Copy>(m: &[bool], a: &[E], b: &[E]) -> Vec<E> {
        (0..m.len())
            .map(|i| if m[i] { a[i] } else { b[i] })
            .collect()
    }
    /// `f(a[i], b[i])` as a mask.
    #[inline(never)]
    pub fn compare<E: Copy>(a: &[E], b: &[E], f: impl Fn(E, E) -> bool) -> Vec<bool> {
        a.iter().zip(b).map(|(&x, &y)| f(x, y)).collect()
    }

    /// Left-to-right sum starting from the first element (zero for an empty slice).
    #[inline(never)]
    pub fn sum_sequential<E: RefFloat>(x: &[E]) -> E {
        let Some((&first, rest)) = x.split_first() else {
            return E::ZERO;
        };
        let mut acc = first;
        for &v in rest {
            acc += v;
        }
        acc
    }

    /// The documented long-reduction order: element `i` goes to partial sum
    /// `i % PARTIAL_SUMS` (each starting at zero), then the partial sums are halved
    /// pairwise (`p[j] + p[j + width / 2]`) down to one.
    ///
    /// # Panics
    /// If `PARTIAL_SUMS` is not a power of two.
    #[inline(never)]
    pub fn sum_interleaved<E: RefFloat>(x: &[E]) -> E {
        assert!(PARTIAL_SUMS.is_power_of_two());
        let mut acc = vec![E::ZERO; PARTIAL_SUMS];
        for (i, &v) in x.iter().enumerate() {
            acc[i % PARTIAL_SUMS] += v;
        }
        while acc.len() > 1 {
            let h = acc.len() / 2;
            acc = (0..h).map(|j| acc[j] + acc[j + h]).collect();
        }
        acc[0]
    }

    /// The sum in the order vecexpr documents for a reduction of this length
    /// (`vecexpr::assign::reduce_strategy`).
    #[inline(never)]
    pub fn sum<E: RefFloat>(x: &[E]) -> E {
        match reduce_strategy(x.len()) {
            ReduceStrategy::Sequential => sum_sequential(x),
            ReduceStrategy::Interleaved => sum_interleaved(x),
        }
    }

    /// $\sum_i a_i b_i$ in the documented order.
    #[inline(never)]
    pub fn dot<E: RefFloat>(a: &[E], b: &[E]) -> E {
        sum(&mul(a, b))
    }
    /// $\sum_i a_i^2$ in the documented order.
    #[inline(never)]
    pub fn length_squared<E: RefFloat>(a: &[E]) -> E {
        sum(&mul(a, a))
    }
    /// $\sqrt{\sum_i a_i^2}$.
    #[inline(never)]
    pub fn length<E: RefFloat>(a: &[E]) -> E {
        length_squared(a).std_sqrt()
    }
    /// The least element: NaN if any is NaN, `-0.0` before `+0.0`.
    ///
    /// # Panics
    /// If `a` is empty.
    #[inline(never)]
    pub fn min_element<E: RefFloat>(a: &[E]) -> E {
        a[1..].iter().fold(a[0], |acc, &x| minimum(acc, x))
    }
    /// The greatest element: NaN if any is NaN, `+0.0` after `-0.0`.
    ///
    /// # Panics
    /// If `a` is empty.
    #[inline(never)]
    pub fn max_element<E: RefFloat>(a: &[E]) -> E {
        a[1..].iter().fold(a[0], |acc, &x| maximum(acc, x))
    }

    /// `a / |a|`, and the zero vector for a zero vector.
    #[inline(never)]
    pub fn normalize<E: RefFloat>(a: &[E]) -> Vec<E> {
        let l2 = length_squared(a);
        if l2 == E::ZERO {
            return vec![E::ZERO; a.len()];
        }
        let len = l2.std_sqrt();
        map(a, |x| x / len)
    }

    /// $a \times b$ of 3-vectors.
    ///
    /// # Panics
    /// If either slice is not of length 3.
    #[inline(never)]
    pub fn cross<E: RefFloat>(a: &[E], b: &[E]) -> Vec<E> {
        assert!(a.len() == 3 && b.len() == 3);
        vec![
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    /// $R = I - 2 (N \cdot I) N$.
    #[inline(never)]
    pub fn reflect<E: RefFloat>(i: &[E], n: &[E]) -> Vec<E> {
        let two_d = <E as super::Real>::from_f64(2.0) * dot(n, i);
        zip(i, n, |x, y| x - y * two_d)
    }

    /// Snell refraction: $k = 1 - \eta^2 (1 - (N \cdot I)^2)$, `None` if `k < 0` (or NaN),
    /// else $T = \eta I - (\eta (N \cdot I) + \sqrt{k}) N$.
    #[inline(never)]
    pub fn refract<E: RefFloat>(i: &[E], n: &[E], eta: E) -> Option<Vec<E>> {
        let ni = dot(n, i);
        let k = E::ONE - eta * eta * (E::ONE - ni * ni);
        if k < E::ZERO || k.is_nan() {
            return None;
        }
        let b = eta * ni + k.std_sqrt();
        Some(zip(i, n, |x, y| eta * x - b * y))
    }

    /// $x^e$ by binary exponentiation from the most significant bit:
    /// $x^e = (x^{\lfloor e/2 \rfloor})^2 \cdot x^{e \bmod 2}$, with no multiplication by one.
    #[inline(never)]
    pub fn pow_binary<E: RefFloat>(x: E, e: u32) -> E {
        if e == 0 {
            return E::ONE;
        }
        let half = e / 2;
        let odd = e % 2 == 1;
        if half == 0 {
            return x; // e == 1
        }
        let p = pow_binary(x, half);
        let sq = p * p;
        if odd {
            sq * x
        } else {
            sq
        }
    }

    /// $x^e$ as `x * x * ... * x`, left to right (one for `e == 0`).
    #[inline(never)]
    pub fn pow_repeated<E: RefFloat>(x: E, e: u32) -> E {
        if e == 0 {
            return E::ONE;
        }
        let mut acc = x;
        for _ in 1..e {
            acc *= x;
        }
        acc
    }

    /// `|a - b| <= tol * max(1, |a|, |b|)`; equal values (infinities included) are close,
    /// NaN and unequal infinities are not.
    #[inline(never)]
    pub fn approx_eq<E: RefFloat>(a: E, b: E, tol: E) -> bool {
        if a == b {
            return true;
        }
        if !a.is_finite() || !b.is_finite() {
            return false;
        }
        let mut scale = E::ONE;
        for m in [a.std_abs(), b.std_abs()] {
            if m > scale {
                scale = m;
            }
        }
        (a - b).std_abs() <= tol * scale
    }
}

// ----- instantiation macros -------------------------------------------------------------

/// Invokes `$body!(module, T, E, N, n, kind)` for every scalar type `T` (`f32`, `f64`,
/// `Packet<f32, U4 | U8 | U16>`, `Packet<f64, U4 | U8>`, lane type `E`) and every
/// dimension `N` in {1, 2, 3, 4, 7, 16, 1000} (`n` is `N` as a literal), inside one
/// module per scalar type (`f32`, `f64`, `f32x4`, ...). `kind` is the identifier `scalar`
/// for `f32`/`f64` and `packet` for packets, for code that only one of them supports.
///
/// The generated modules `use super::*`, so `$body` sees the caller's imports.
#[macro_export]
macro_rules! for_each_case {
    ($body:ident) => {
        $crate::for_each_case!(@dims $body, f32, f32, f32, scalar);
        $crate::for_each_case!(@dims $body, f64, f64, f64, scalar);
        $crate::for_each_case!(@dims $body, f32x4,
            $crate::vecexpr::Packet<f32, $crate::vecexpr::typenum::U4>, f32, packet);
        $crate::for_each_case!(@dims $body, f32x8,
            $crate::vecexpr::Packet<f32, $crate::vecexpr::typenum::U8>, f32, packet);
        $crate::for_each_case!(@dims $body, f32x16,
            $crate::vecexpr::Packet<f32, $crate::vecexpr::typenum::U16>, f32, packet);
        $crate::for_each_case!(@dims $body, f64x4,
            $crate::vecexpr::Packet<f64, $crate::vecexpr::typenum::U4>, f64, packet);
        $crate::for_each_case!(@dims $body, f64x8,
            $crate::vecexpr::Packet<f64, $crate::vecexpr::typenum::U8>, f64, packet);
    };
    (@dims $body:ident, $name:ident, $t:ty, $e:ty, $kind:ident) => {
        mod $name {
            #[allow(unused_imports)]
            use super::*;
            $body!(n1, $t, $e, $crate::vecexpr::typenum::U1, 1, $kind);
            $body!(n2, $t, $e, $crate::vecexpr::typenum::U2, 2, $kind);
            $body!(n3, $t, $e, $crate::vecexpr::typenum::U3, 3, $kind);
            $body!(n4, $t, $e, $crate::vecexpr::typenum::U4, 4, $kind);
            $body!(n7, $t, $e, $crate::vecexpr::typenum::U7, 7, $kind);
            $body!(n16, $t, $e, $crate::vecexpr::typenum::U16, 16, $kind);
            $body!(n1000, $t, $e, $crate::vecexpr::typenum::U1000, 1000, $kind);
        }
    };
}

/// Invokes `$body!(module, T, E, kind)` for every scalar type of [`for_each_case!`].
#[macro_export]
macro_rules! for_each_scalar {
    ($body:ident) => {
        $body!(f32, f32, f32, scalar);
        $body!(f64, f64, f64, scalar);
        $body!(f32x4, $crate::vecexpr::Packet<f32, $crate::vecexpr::typenum::U4>, f32, packet);
        $body!(f32x8, $crate::vecexpr::Packet<f32, $crate::vecexpr::typenum::U8>, f32, packet);
        $body!(f32x16, $crate::vecexpr::Packet<f32, $crate::vecexpr::typenum::U16>, f32, packet);
        $body!(f64x4, $crate::vecexpr::Packet<f64, $crate::vecexpr::typenum::U4>, f64, packet);
        $body!(f64x8, $crate::vecexpr::Packet<f64, $crate::vecexpr::typenum::U8>, f64, packet);
    };
}

/// Expands its body only for `scalar` (plain `f32`/`f64`) cases of [`for_each_case!`]:
/// `only_scalar!(kind, { ... })`.
#[macro_export]
macro_rules! only_scalar {
    (scalar, { $($body:tt)* }) => { $($body)* };
    (packet, { $($body:tt)* }) => {};
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interleaved_matches_sequential_on_exact_data() {
        // Small integers sum exactly in any order, so both orders must agree.
        let x: Vec<f64> = (0..1000).map(|i| f64::from(i % 17) - 8.0).collect();
        assert_eq!(naive::sum_interleaved(&x), naive::sum_sequential(&x));
        assert_eq!(naive::sum(&x), x.iter().sum::<f64>());
    }

    #[test]
    fn pow_orders() {
        assert_eq!(naive::pow_binary(3.0f64, 13), 1_594_323.0);
        assert_eq!(naive::pow_repeated(3.0f64, 13), 1_594_323.0);
        assert_eq!(naive::pow_binary(2.0f32, 0), 1.0);
    }

    #[test]
    fn lane_major_round_trip() {
        use vecexpr::typenum::{U3, U4};
        let data: Vec<f32> = (0..12).map(|i| i as f32).collect();
        let v = build::<Packet<f32, U4>, U3>(&data);
        assert_eq!(v[1].lane(2), data[2 * 3 + 1]);
        assert_eq!(lanes(&v), data);
        assert_eq!(broadcast(&[1.0f32, 2.0], 2), vec![1.0, 1.0, 2.0, 2.0]);
    }
}
