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

use crate::scalar::Scalar;
use core::mem::MaybeUninit;
use generic_array::{ArrayLength, GenericArray};

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

/// What the element-wise loops read: element `i` of a source. Every expression is a
/// source (the impl sits next to [`Expr`](crate::Expr)); the loops need nothing else of
/// it, and the calls inline as `Expr::coeff` itself does.
pub(crate) trait Source {
    /// The element type.
    type Item: Copy;
    /// Element `i`.
    fn at(&self, i: usize) -> Self::Item;
}

/// Writes `src` into `dst`, one element at a time, in one loop.
#[inline(always)]
pub(crate) fn assign_to<S: Source, N: ArrayLength>(dst: &mut GenericArray<S::Item, N>, src: &S) {
    let d = dst.as_mut_slice();
    for (i, x) in d.iter_mut().enumerate() {
        *x = src.at(i);
    }
}

/// Writes `f(dst[i], src[i])` into `dst`: the in-place update loop.
#[inline(always)]
pub(crate) fn update<S: Source, N: ArrayLength>(
    dst: &mut GenericArray<S::Item, N>,
    src: &S,
    f: impl Fn(S::Item, S::Item) -> S::Item,
) {
    let d = dst.as_mut_slice();
    for (i, x) in d.iter_mut().enumerate() {
        *x = f(*x, src.at(i));
    }
}

/// Evaluates `src` into a new array of `N` elements without first initialising it.
#[inline(always)]
pub(crate) fn eval<S: Source, N: ArrayLength>(src: &S) -> GenericArray<S::Item, N> {
    let mut out = MaybeUninit::<GenericArray<S::Item, N>>::uninit();
    let base = out.as_mut_ptr().cast::<S::Item>();
    for i in 0..N::USIZE {
        // SAFETY: a GenericArray<T, N> is laid out as [T; N], so `base.add(i)` for
        // i < N stays inside `out` and is suitably aligned for T.
        unsafe { base.add(i).write(src.at(i)) };
    }
    // SAFETY: the loop above wrote all N elements; the items are Copy, so an early
    // unwind from `at` would only leak uninitialised stack memory, never read or drop it.
    unsafe { out.assume_init() }
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
