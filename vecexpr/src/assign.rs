//! The evaluation loops: the only place that decides how an expression is traversed.
//!
//! Element-wise evaluation is one loop `for i in 0..N { dst[i] = expr.coeff(i) }`. `N` is
//! a compile-time constant and every leaf is an array of exactly `N` elements, so bounds
//! checks vanish and LLVM vectorises the fused body (or, for small `N`, unrolls it
//! completely into straight-line SIMD code).
//!
//! Reductions choose their strategy from `N` at compile time: short reductions
//! (`N < SPLIT_THRESHOLD`) run left to right, exactly as the formula reads; long ones
//! keep `PARTIAL_SUMS` interleaved partial sums, which breaks the serial dependency
//! chain and lets the sum vectorise, at the price of a different (still deterministic)
//! rounding order.

use crate::expr::Expr;
use crate::scalar::Scalar;
use crate::vector::Vector;
use core::mem::MaybeUninit;
use generic_array::{ArrayLength, GenericArray};
use typenum::Unsigned;

/// Reductions at least this long use interleaved partial sums.
pub const SPLIT_THRESHOLD: usize = 64;
/// Number of interleaved partial sums for long reductions.
pub const PARTIAL_SUMS: usize = 32;

/// Which loop a reduction over `n` elements runs; exposed for tests of the strategy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReduceStrategy {
    /// One accumulator, left to right.
    Sequential,
    /// `PARTIAL_SUMS` accumulators combined pairwise at the end.
    Interleaved,
}

/// The strategy a reduction over `n` elements uses.
pub const fn reduce_strategy(n: usize) -> ReduceStrategy {
    if n >= SPLIT_THRESHOLD {
        ReduceStrategy::Interleaved
    } else {
        ReduceStrategy::Sequential
    }
}

/// Writes `e` into `dst`, one element at a time, in one loop.
#[inline(always)]
pub(crate) fn assign_to<E: Expr>(dst: &mut GenericArray<E::Scalar, E::Dim>, e: &E) {
    let d = dst.as_mut_slice();
    for (i, x) in d.iter_mut().enumerate() {
        *x = e.coeff(i);
    }
}

/// Writes `f(dst[i], e[i])` into `dst`: the in-place update loop.
#[inline(always)]
pub(crate) fn update<E: Expr>(
    dst: &mut GenericArray<E::Scalar, E::Dim>,
    e: &E,
    f: impl Fn(E::Scalar, E::Scalar) -> E::Scalar,
) {
    let d = dst.as_mut_slice();
    for (i, x) in d.iter_mut().enumerate() {
        *x = f(*x, e.coeff(i));
    }
}

/// Evaluates `e` into a new vector without first initialising it.
#[inline(always)]
pub(crate) fn eval<E: Expr>(e: &E) -> Vector<E::Scalar, E::Dim> {
    let mut out = MaybeUninit::<GenericArray<E::Scalar, E::Dim>>::uninit();
    let base = out.as_mut_ptr().cast::<E::Scalar>();
    for i in 0..E::Dim::USIZE {
        // SAFETY: a GenericArray<T, N> is laid out as [T; N], so `base.add(i)` for
        // i < N stays inside `out` and is suitably aligned for T.
        unsafe { base.add(i).write(e.coeff(i)) };
    }
    // SAFETY: the loop above wrote all N elements; scalars are Copy, so an early
    // unwind from `coeff` would only leak uninitialised stack memory, never read it.
    Vector::from_generic_array(unsafe { out.assume_init() })
}

/// Fills a new heap allocation with `f(i)` without building the value on the stack.
#[inline]
pub(crate) fn boxed_from_fn<T, N: ArrayLength>(mut f: impl FnMut(usize) -> T) -> Box<Vector<T, N>> {
    let mut b = Box::<Vector<T, N>>::new_uninit();
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

/// $\sum_{i<n} f(i)$ with the strategy of [`reduce_strategy`].
#[inline(always)]
pub(crate) fn sum<T: Scalar>(f: impl Fn(usize) -> T, n: usize) -> T {
    match reduce_strategy(n) {
        ReduceStrategy::Sequential => {
            if n == 0 {
                return T::zero();
            }
            let mut acc = f(0);
            for i in 1..n {
                acc += f(i);
            }
            acc
        }
        ReduceStrategy::Interleaved => {
            let mut acc = [T::zero(); PARTIAL_SUMS];
            let chunks = n / PARTIAL_SUMS;
            for c in 0..chunks {
                for (j, a) in acc.iter_mut().enumerate() {
                    *a += f(c * PARTIAL_SUMS + j);
                }
            }
            for (j, a) in acc.iter_mut().enumerate().take(n % PARTIAL_SUMS) {
                *a += f(chunks * PARTIAL_SUMS + j);
            }
            // Pairwise combination of the partial sums.
            let mut width = PARTIAL_SUMS;
            while width > 1 {
                width /= 2;
                for j in 0..width {
                    acc[j] += acc[j + width];
                }
            }
            acc[0]
        }
    }
}

/// Left fold of `f(0..n)` with `op`, starting from `f(0)`.
///
/// # Panics
/// If `n == 0`.
#[inline(always)]
pub(crate) fn fold1<T: Scalar>(f: impl Fn(usize) -> T, n: usize, op: impl Fn(T, T) -> T) -> T {
    assert!(n > 0, "min_element/max_element of an empty vector");
    let mut acc = f(0);
    for i in 1..n {
        acc = op(acc, f(i));
    }
    acc
}
