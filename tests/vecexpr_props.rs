//! Property tests of every vecexpr operation against the naive eager reference
//! (`integration_tests::naive`), for every scalar type (`f32`, `f64`, packets of 4, 8 and
//! 16 `f32` lanes, of 4 and 8 `f64` lanes) and every dimension in {1, 2, 3, 4, 7, 16,
//! 1000}.
//!
//! Element-wise results must match the reference bit for bit. Reductions must match the
//! documented summation order bit for bit (left to right below 64 elements, interleaved
//! partial sums from 64 up), and from 64 elements up also stay within the rounding bound
//! of the plain left-to-right sum. Geometric operations that divide by a length are
//! checked within a few units of rounding.
//!
//! Each distinct expression type costs compile time in every one of the 49 cases, so the
//! variants of an operator (owned operands, lane scalars, expression operands) are
//! covered by a few deep trees rather than one expression each.

use crate::prop;

use integration_tests::{
    assert_close, assert_expr, assert_same, assert_scalar_same, assert_vec_same, broadcast, build,
    cases, debug_reference, lanes, mask_bits, mask_lanes, naive, per_lane, per_lane2, scalar_lanes,
    TestScalar,
};
use prop::{check, elem, finite, inputs, moderate, wide_finite, Inputs};
use vecexpr::assign::{reduce_strategy, ReduceStrategy};
use vecexpr::generic_array::ArrayLength;
use vecexpr::typenum::{U0, U1, U13, U16, U2, U3, U4, U5, U7, U8};
use vecexpr::{powi, select, Expr, LengthMismatch, MaskExpr, Real, Scalar, Vector};

/// The lane-major data of a vector and, per lane, whether normalising it must give NaN
/// (a non-finite component), zero (all components zero) or a unit vector.
#[inline(never)]
fn check_normalize<T: TestScalar, N: ArrayLength>(data: &[T::Elem]) {
    let k = N::USIZE;
    let v = build::<T, N>(data);
    let got = lanes(&(&v).normalize());
    let mut in_place = v;
    in_place.normalize_mut();
    assert_vec_same(&in_place, &got, "normalize_mut vs normalize");

    let eps = <T::Elem as Real>::EPSILON;
    let min = <T::Elem as Real>::MIN_POSITIVE;
    let max = <T::Elem as Real>::MAX;
    let l2s = per_lane(data, k, naive::length_squared);
    // Every lane in the normal range: the fast path x * (1 / |x|) runs for the whole
    // packet and differs from x / |x| by rounding only. Otherwise every lane is rescaled
    // by its largest magnitude first, which changes the summation.
    let fast = l2s.iter().all(|&l2| l2 >= min && l2 <= max);
    let tol_close = if fast {
        eps * <T::Elem as Real>::from_f64(4.0)
    } else {
        eps * <T::Elem as Real>::from_f64(8.0 + (k / 8) as f64)
    };
    for (l, (x, r)) in data.chunks(k).zip(got.chunks(k)).enumerate() {
        if x.iter().any(|y| !y.is_finite()) {
            assert!(
                r.iter().all(|y| y.is_nan()),
                "normalize lane {l}: non-finite input must give NaN, got {r:?}"
            );
        } else if x.iter().all(|&y| y == <T::Elem as Real>::ZERO) {
            assert!(
                r.iter().all(|&y| y == <T::Elem as Real>::ZERO),
                "normalize lane {l}: zero must give zero, got {r:?}"
            );
        } else {
            assert!(
                r.iter().all(|y| y.is_finite()),
                "normalize lane {l}: finite non-zero input {x:?} gave {r:?}"
            );
            let len2: f64 = r.iter().map(|y| y.to_f64() * y.to_f64()).sum();
            let bound = (3 * k + 16) as f64 * eps.to_f64();
            assert!(
                (len2 - 1.0).abs() <= bound,
                "normalize lane {l}: squared length {len2} (input {x:?})"
            );
            if l2s[l] >= min && l2s[l] <= max {
                assert_close(r, &naive::normalize(x), tol_close, "normalize vs x / |x|");
            }
        }
    }
}

/// Reflection (bit for bit, any input) and refraction of unit vectors built from the
/// data (bit for bit, with the total-internal-reflection lanes zero), for `etas` per
/// lane.
#[inline(never)]
fn check_reflect_refract<T: TestScalar, N: ArrayLength>(
    a: &[T::Elem],
    b: &[T::Elem],
    etas: &[T::Elem],
) {
    let k = N::USIZE;
    let (va, vb) = (build::<T, N>(a), build::<T, N>(b));
    let want: Vec<T::Elem> = per_lane2(a, b, k, naive::reflect).concat();
    assert_vec_same(&va.reflect(&vb), &want, "reflect");
    assert_vec_same(
        &(&va + &vb).reflect(&vb),
        &per_lane2(&naive::add(a, b), b, k, naive::reflect).concat(),
        "reflect of an expression",
    );

    // Unit incident direction i and unit normal n facing it (n . i <= 0), per lane.
    let i: Vec<T::Elem> = per_lane(a, k, naive::normalize).concat();
    let n: Vec<T::Elem> = per_lane2(b, &i, k, |bl, il| {
        let nl = naive::normalize(bl);
        if naive::dot(&nl, il) > <T::Elem as Real>::ZERO {
            naive::neg(&nl)
        } else {
            nl
        }
    })
    .concat();
    let (vi, vn) = (build::<T, N>(&i), build::<T, N>(&n));
    let eta = T::from_lanes(|l| etas[l]);
    let (t, ok) = vi.refract_masked(&vn, eta);
    let t = lanes(&t);
    let refs: Vec<Option<Vec<T::Elem>>> = (0..T::LANES)
        .map(|l| naive::refract(&i[l * k..(l + 1) * k], &n[l * k..(l + 1) * k], etas[l]))
        .collect();
    assert_eq!(
        mask_bits(ok),
        refs.iter().map(Option::is_some).collect::<Vec<_>>(),
        "refract mask"
    );
    for (l, r) in refs.iter().enumerate() {
        let tl = &t[l * k..(l + 1) * k];
        match r {
            Some(r) => assert_same(tl, r, "refract"),
            None => {
                let finite = i[l * k..(l + 1) * k]
                    .iter()
                    .chain(&n[l * k..(l + 1) * k])
                    .all(|y| y.is_finite());
                if finite {
                    assert!(
                        tl.iter().all(|&y| y == <T::Elem as Real>::ZERO),
                        "refract: TIR lane {l} must be zero, got {tl:?}"
                    );
                }
            }
        }
    }
}

/// Exact reductions in the documented order, and for long vectors of finite data also
/// the rounding bound against the plain left-to-right sum.
#[inline(never)]
fn check_reductions<T: TestScalar, N: ArrayLength>(t: &Inputs<T::Elem>, finite_data: bool) {
    let k = N::USIZE;
    let (a, b, c) = (&t.a, &t.b, &t.c);
    let (va, vb, vc) = (build::<T, N>(a), build::<T, N>(b), build::<T, N>(c));

    assert_scalar_same((&va).sum(), &per_lane(a, k, naive::sum), "sum");
    assert_scalar_same(va.dot(&vb), &per_lane2(a, b, k, naive::dot), "dot");
    assert_scalar_same(
        (&va).length_squared(),
        &per_lane(a, k, naive::length_squared),
        "length_squared",
    );
    assert_scalar_same((&va).length(), &per_lane(a, k, naive::length), "length");
    assert_scalar_same(
        (&va).min_element(),
        &per_lane(a, k, naive::min_element),
        "min_element",
    );
    assert_scalar_same(
        (&va).max_element(),
        &per_lane(a, k, naive::max_element),
        "max_element",
    );
    // Reductions of expressions evaluate the tree once per element.
    let amb = naive::sub(a, b);
    assert_scalar_same(
        (&va - &vb).dot(&vc),
        &per_lane2(&amb, c, k, naive::dot),
        "dot of expressions",
    );
    assert_scalar_same(
        (&va * &vb).sum(),
        &per_lane(&naive::mul(a, b), k, naive::sum),
        "sum of a product",
    );
    assert_scalar_same(
        (&va).abs().max_element(),
        &per_lane(&naive::abs(a), k, naive::max_element),
        "max_element of abs",
    );

    if finite_data {
        // |interleaved - sequential| <= 2 n eps sum|terms|: each order is within
        // (n - 1) eps sum|terms| of the exact sum (Higham, Accuracy and Stability of
        // Numerical Algorithms, 2nd ed., section 4.2).
        let eps = <T::Elem as Real>::EPSILON;
        let bound = |terms: &[T::Elem]| {
            let abs_sum = naive::sum_sequential(&naive::abs(terms));
            eps * <T::Elem as Real>::from_f64(2.0 * k as f64) * abs_sum
        };
        let close = |got: T, terms: &[T::Elem], what: &str| {
            for (l, (g, tl)) in scalar_lanes(got)
                .into_iter()
                .zip(terms.chunks(k))
                .enumerate()
            {
                let seq = naive::sum_sequential(tl);
                if k < 64 {
                    assert_same(&[g], &[seq], what);
                } else {
                    assert!(
                        (g - seq).abs() <= bound(tl),
                        "{what} lane {l}: {g:?} vs sequential {seq:?}"
                    );
                }
            }
        };
        close((&va).sum(), a, "sum vs sequential");
        close(va.dot(&vb), &naive::mul(a, b), "dot vs sequential");
        close(
            (&va).length_squared(),
            &naive::mul(a, a),
            "length_squared vs sequential",
        );
    }
}

macro_rules! props {
    ($m:ident, $t:ty, $e:ty, $n:ty, $k:literal, $kind:ident) => {
        mod $m {
            // `i % K` is written for every dimension, including K = 1.
            #![allow(clippy::modulo_one)]
            use super::*;

            type T = $t;
            type E = $e;
            type N = $n;
            const K: usize = $k;
            const L: usize = <T as Scalar>::LANES;
            const LEN: usize = K * L;
            const CASES: u32 = cases(K, L);

            fn v(data: &[E]) -> Vector<T, N> {
                build::<T, N>(data)
            }

            fn packet(per_lane: &[E]) -> T {
                T::from_lanes(|l| per_lane[l])
            }

            /// Every element-wise operator and function in isolation, then their
            /// operand variants in two deep trees.
            #[test]
            fn elementwise() {
                check(CASES, inputs(LEN, L, elem::<E>()), |t| {
                    let (a, b, c) = (&t.a, &t.b, &t.c);
                    let (va, vb, vc) = (v(a), v(b), v(c));
                    let st = packet(&t.s);
                    let sb = broadcast(&t.s, K);
                    let x = t.x;
                    let xb = vec![x; LEN];

                    assert_expr(&va + &vb, &naive::add(a, b), "a + b");
                    assert_expr(&va - &vb, &naive::sub(a, b), "a - b");
                    assert_expr(&va * &vb, &naive::mul(a, b), "a * b");
                    assert_expr(&va / &vb, &naive::div(a, b), "a / b");
                    assert_expr(&va + st, &naive::add(a, &sb), "a + s");
                    assert_expr(&va - st, &naive::sub(a, &sb), "a - s");
                    assert_expr(&va * st, &naive::mul(a, &sb), "a * s");
                    assert_expr(&va / st, &naive::div(a, &sb), "a / s");
                    assert_expr(st + &va, &naive::add(&sb, a), "s + a");
                    assert_expr(st - &va, &naive::sub(&sb, a), "s - a");
                    assert_expr(st * &va, &naive::mul(&sb, a), "s * a");
                    assert_expr(st / &va, &naive::div(&sb, a), "s / a");
                    assert_expr(-&va, &naive::neg(a), "-a");
                    assert_expr(va.min(&vb), &naive::min(a, b), "min");
                    assert_expr(va.max(&vb), &naive::max(a, b), "max");
                    assert_expr((&va).abs(), &naive::abs(a), "abs");
                    assert_expr((&va).sqrt(), &naive::sqrt(a), "sqrt");
                    assert_expr((&va).recip(), &naive::recip(a), "recip");
                    assert_expr(va.mul_add(&vb, &vc), &naive::mul_add(a, b, c), "mul_add");
                    assert_expr((&va).scale(st), &naive::mul(a, &sb), "scale");
                    let f = |y: T| y * y - y;
                    let g = |y: E| y * y - y;
                    assert_expr((&va).map(f), &naive::map(a, g), "map");

                    // Owned vectors, lane scalars and expressions as operands of every
                    // binary operator, scalars on both sides of expressions.
                    let tree = (((va + x) * (&vb - x)).min(st) / (&vc * x + vb)).max(x)
                        - st / (&va - &vc);
                    let want: Vec<E> = (0..LEN)
                        .map(|j| {
                            let p = naive::minimum((a[j] + x) * (b[j] - x), sb[j]);
                            naive::maximum(p / (c[j] * x + b[j]), x) - sb[j] / (a[j] - c[j])
                        })
                        .collect();
                    assert_expr(tree, &want, "operand variants");
                    // Unary nodes and mul_add/map of expressions, with scalar operands.
                    let tree = (-(&va / x)).abs().sqrt().recip().mul_add(st, x).map(f)
                        + (&vb).scale(st);
                    let want = naive::add(
                        &naive::map(
                            &naive::mul_add(
                                &naive::recip(&naive::sqrt(&naive::abs(&naive::neg(&naive::div(a, &xb))))),
                                &sb,
                                &xb,
                            ),
                            g,
                        ),
                        &naive::mul(b, &sb),
                    );
                    assert_expr(tree, &want, "unary chain");
                });
            }

            /// Comparisons, their combinations and `select`.
            #[test]
            fn select_and_masks() {
                check(CASES, inputs(LEN, L, elem::<E>()), |t| {
                    let (a, b, c) = (&t.a, &t.b, &t.c);
                    let (va, vb, vc) = (v(a), v(b), v(c));
                    let st = packet(&t.s);
                    let sb = broadcast(&t.s, K);
                    let x = t.x;
                    let xb = vec![x; LEN];
                    let lt = naive::compare(a, b, |p, q| p < q);
                    let le = naive::compare(b, c, |p, q| p <= q);
                    let gt = naive::compare(a, &xb, |p, q| p > q);
                    let ge = naive::compare(a, c, |p, q| p >= q);
                    let eq = naive::compare(a, b, |p, q| p == q);

                    assert_expr(select(va.lt(&vb), &va, &vb), &naive::select(&lt, a, b), "select lt");
                    assert_expr(select(vb.le(&vc), &vc, &va), &naive::select(&le, c, a), "select le");
                    assert_expr(select(va.gt(x), &va, x), &naive::select(&gt, a, &xb), "select gt scalar");
                    assert_expr(select(va.ge(&vc), &vb, &vc), &naive::select(&ge, b, c), "select ge");
                    assert_expr(select(va.eq_mask(&vb), st, &vb), &naive::select(&eq, &sb, b), "select eq");

                    let and: Vec<bool> = lt.iter().zip(&le).map(|(&p, &q)| p && q).collect();
                    let or: Vec<bool> = eq.iter().zip(&gt).map(|(&p, &q)| p || q).collect();
                    let not: Vec<bool> = ge.iter().map(|&p| !p).collect();
                    assert_expr(select(va.lt(&vb).and(vb.le(&vc)), &vb - &va, x), &naive::select(&and, &naive::sub(b, a), &xb), "select and");
                    assert_expr(select(va.eq_mask(&vb).or(va.gt(x)), st, (&vc).abs()), &naive::select(&or, &sb, &naive::abs(c)), "select or");
                    assert_expr(select(va.ge(&vc).not(), &va, -&vb), &naive::select(&not, a, &naive::neg(b)), "select not");

                    let mv = va.lt(&vb).and(vb.le(&vc)).eval();
                    assert_eq!(mask_lanes(&mv), and, "mask eval");
                    assert_expr(select(&mv, &vc, &va), &naive::select(&and, c, a), "select stored mask");
                    assert_eq!(va.lt(&vb).all(), lt.iter().all(|&p| p), "all");
                    assert_eq!(va.lt(&vb).any(), lt.iter().any(|&p| p), "any");
                    // select as an operand inside a larger tree
                    let relu = naive::mul(&naive::select(&gt, a, &xb), b);
                    assert_expr(select(va.gt(x), &va, x) * &vb, &relu, "select in a tree");
                });
            }

            /// `eval`, `eval_boxed`, `assign`, the in-place operators, `update`, `apply`,
            /// deep trees and `powi` through `map`.
            #[test]
            fn assignment_and_trees() {
                check(CASES, inputs(LEN, L, elem::<E>()), |t| {
                    let (a, b, c, d, e) = (&t.a, &t.b, &t.c, &t.d, &t.e);
                    let (va, vb, vc, vd, ve) = (v(a), v(b), v(c), v(d), v(e));
                    let st = packet(&t.s);
                    let sb = broadcast(&t.s, K);
                    let x = t.x;
                    let xb = vec![x; LEN];

                    // a*b + c*d - e: eval, eval_boxed and assign of one tree.
                    let want = naive::sub(&naive::add(&naive::mul(a, b), &naive::mul(c, d)), e);
                    assert_expr(&va * &vb + &vc * &vd - &ve, &want, "a*b + c*d - e");
                    assert_vec_same(&(&va * &vb + &vc * &vd - &ve).eval_boxed(), &want, "eval_boxed");
                    let mut out = Vector::<T, N>::splat(T::splat(<E as Real>::NAN));
                    out.assign(&va * &vb + &vc * &vd - &ve);
                    assert_vec_same(&out, &want, "assign");
                    out.assign(&vb);
                    assert_vec_same(&out, b, "assign a vector");
                    out.assign(st);
                    assert_vec_same(&out, &sb, "assign a scalar");

                    // In-place operators, tracked by the reference.
                    let mut w = va;
                    w += &vb;
                    let mut r = naive::add(a, b);
                    assert_vec_same(&w, &r, "+= vector");
                    w -= &vc * st;
                    r = naive::sub(&r, &naive::mul(c, &sb));
                    assert_vec_same(&w, &r, "-= expression");
                    w *= x;
                    r = naive::mul(&r, &xb);
                    assert_vec_same(&w, &r, "*= lane scalar");
                    w /= st;
                    r = naive::div(&r, &sb);
                    assert_vec_same(&w, &r, "/= scalar");
                    // update with the same operands as the operators above.
                    let mut u = va;
                    u.update(&vb, |o, n| o + n);
                    u.update(&vc * st, |o, n| o - n);
                    u.update(x, |o, n| o * n);
                    u.update(st, |o, n| o / n);
                    assert_vec_same(&u, &r, "update sequence");
                    let mut m = va;
                    m.update(&vb, |o, n| o * n - o);
                    assert_vec_same(&m, &naive::zip(a, b, |p, q| p * q - p), "update closure");
                    m.apply(|y| y + y);
                    assert_vec_same(&m, &naive::map(&naive::zip(a, b, |p, q| p * q - p), |y| y + y), "apply");

                    // Nine nested levels: + * - / max sqrt mul_add - min (abs, -, * inside).
                    let one: E = 1.0;
                    let tree = ((((&va + &vb) * &vc - (&vd).abs()) / (&ve * &ve + one))
                        .max(-&va)
                        .sqrt()
                        .mul_add(&vb, &vc)
                        - st)
                        .min(&vd);
                    let want: Vec<E> = (0..LEN)
                        .map(|j| {
                            let mut y = ((a[j] + b[j]) * c[j] - d[j].abs()) / (e[j] * e[j] + one);
                            y = naive::maximum(y, -a[j]).sqrt();
                            y = y.mul_add(b[j], c[j]) - sb[j];
                            naive::minimum(y, d[j])
                        })
                        .collect();
                    let mut out = Vector::<T, N>::zero();
                    out.assign(tree);
                    assert_vec_same(&out, &want, "nested tree");

                    // powi through map, against binary exponentiation.
                    assert_expr((&va).map(powi::<U5, T>), &naive::map(a, |y| naive::pow_binary(y, 5)), "powi 5");
                    assert_expr((&va).map(powi::<U16, T>), &naive::map(a, |y| naive::pow_binary(y, 16)), "powi 16");
                });
            }

            /// Reductions: bit for bit in the documented order; within the rounding
            /// bound of the sequential sum for long vectors.
            #[test]
            fn reductions() {
                let expected = if K >= 64 { ReduceStrategy::Interleaved } else { ReduceStrategy::Sequential };
                assert_eq!(reduce_strategy(K), expected);
                check(CASES, inputs(LEN, L, elem::<E>()), |t| check_reductions::<T, N>(&t, false));
                check(CASES, inputs(LEN, L, finite::<E>()), |t| check_reductions::<T, N>(&t, true));
            }

            /// `normalize`, `normalize_mut`, `reflect`, `refract`, `refract_masked` on
            /// moderate, whole-exponent-range and special inputs.
            #[test]
            fn geometry() {
                fn body(t: &Inputs<E>) {
                    check_normalize::<T, N>(&t.a);
                    check_normalize::<T, N>(&t.b);
                    const ETAS: [f64; 6] = [0.5, 1.0 / 1.5, 1.0, 1.33, 1.5, 2.0];
                    let etas: Vec<E> = (0..L).map(|l| ETAS[(t.idx % 6 + l) % 6] as E).collect();
                    check_reflect_refract::<T, N>(&t.a, &t.b, &etas);
                    integration_tests::only_scalar!($kind, {
                        // The Option form agrees with the masked form's reference.
                        let i = v(&naive::normalize(&t.a));
                        let nl = naive::normalize(&t.b);
                        let nl = if naive::dot(&nl, &lanes(&i)) > 0.0 { naive::neg(&nl) } else { nl };
                        let got = i.refract(&v(&nl), etas[0]).map(|r| lanes(&r));
                        let want = naive::refract(&lanes(&i), &nl, etas[0]);
                        match (&got, &want) {
                            (Some(g), Some(r)) => assert_same(g, r, "refract (Option)"),
                            (None, None) => {}
                            _ => panic!("refract (Option): got {got:?}, reference {want:?}"),
                        }
                    });
                }
                check(CASES, inputs(LEN, L, finite::<E>()), |t| body(&t));
                check(CASES, inputs(LEN, L, wide_finite::<E>()), |t| body(&t));
                check(CASES, inputs(LEN, L, elem::<E>()), |t| body(&t));
            }

            /// Construction, conversion, access, iteration, `Debug`, `PartialEq` and
            /// `approx_eq`.
            #[test]
            fn vector_api() {
                check(CASES, inputs(LEN, L, elem::<E>()), |t| {
                    let (a, b) = (&t.a, &t.b);
                    let (va, vb) = (v(a), v(b));
                    let st = packet(&t.s);
                    let sb = broadcast(&t.s, K);
                    let j = t.idx % K;
                    let elems: Vec<T> = va.iter().copied().collect();

                    // from_slice, boxed_from_fn, From<[T; K]>, into_array, generic arrays.
                    assert_vec_same(&Vector::<T, N>::from_slice(&elems).unwrap(), a, "from_slice");
                    let short = Vector::<T, N>::from_slice(&elems[..K - 1]).unwrap_err();
                    assert_eq!(short, LengthMismatch { expected: K, found: K - 1 });
                    assert_eq!(short.to_string(), format!("slice of length {} cannot fill a vector of dimension {K}", K - 1));
                    let mut long = elems.clone();
                    long.push(st);
                    assert_eq!(Vector::<T, N>::from_slice(&long).unwrap_err(), LengthMismatch { expected: K, found: K + 1 });
                    assert_eq!(Vector::<T, N>::from_slice(&[]).unwrap_err().found, 0);
                    let boxed: Box<Vector<T, N>> = Vector::boxed_from_fn(|i| elems[i]);
                    assert_vec_same(&boxed, a, "boxed_from_fn");
                    let arr: [T; K] = core::array::from_fn(|i| elems[i]);
                    let from_arr: Vector<T, N> = Vector::from(arr);
                    assert_vec_same(&from_arr, a, "From<[T; K]>");
                    let back: [T; K] = from_arr.into_array();
                    assert_vec_same(&Vector::<T, N>::from(back), a, "into_array");
                    assert_vec_same(&Vector::from_generic_array(va.into_generic_array()), a, "generic array round trip");

                    // Constructors.
                    assert_eq!(Vector::<T, N>::DIM, K);
                    assert_vec_same(&Vector::<T, N>::splat(st), &sb, "splat");
                    assert_vec_same(&Vector::<T, N>::zero(), &vec![0.0; LEN], "zero");
                    assert_vec_same(&Vector::<T, N>::default(), &vec![0.0; LEN], "default");
                    let unit: Vec<E> = (0..LEN).map(|q| if q % K == j { 1.0 } else { 0.0 }).collect();
                    assert_vec_same(&Vector::<T, N>::unit(j), &unit, "unit");

                    // Indexing.
                    for i in 0..K {
                        for l in 0..L {
                            assert_same(&[va[i].lane(l)], &[a[l * K + i]], "index");
                        }
                    }
                    let mut w = va;
                    w[j] = st;
                    let mut want = a.clone();
                    for l in 0..L {
                        want[l * K + j] = t.s[l];
                    }
                    assert_vec_same(&w, &want, "index_mut");

                    // Iteration, slices.
                    assert_eq!(va.iter().len(), K);
                    assert_vec_same(&Vector::<T, N>::from_slice(&va.iter().copied().collect::<Vec<_>>()).unwrap(), a, "iter");
                    let by_ref: Vec<T> = (&va).into_iter().copied().collect();
                    assert_vec_same(&Vector::<T, N>::from_slice(&by_ref).unwrap(), a, "into_iter by reference");
                    let rev: Vec<T> = va.into_iter().rev().collect();
                    let rev_want: Vec<E> = (0..LEN).map(|q| a[(q / K) * K + (K - 1 - q % K)]).collect();
                    assert_vec_same(&Vector::<T, N>::from_slice(&rev).unwrap(), &rev_want, "into_iter by value, reversed");
                    let mut w = va;
                    for y in w.iter_mut() {
                        *y += st;
                    }
                    for y in &mut w {
                        *y *= st;
                    }
                    w.as_mut_slice()[j] = st;
                    let mut want = naive::mul(&naive::add(a, &sb), &sb);
                    for l in 0..L {
                        want[l * K + j] = t.s[l];
                    }
                    assert_vec_same(&w, &want, "iter_mut, as_mut_slice");
                    assert_eq!(va.as_slice().len(), K);
                    assert_eq!(AsRef::<[T]>::as_ref(&va).len(), K);

                    // extend / truncate / resize_down.
                    let ext = va.extend(st);
                    let ext_want: Vec<E> = (0..L).flat_map(|l| {
                        a[l * K..(l + 1) * K].iter().copied().chain([t.s[l]])
                    }).collect();
                    assert_same(&lanes(&ext), &ext_want, "extend");
                    assert_vec_same(&ext.truncate(), a, "extend then truncate");
                    let tr = va.truncate();
                    let tr_want: Vec<E> = (0..L).flat_map(|l| a[l * K..l * K + K - 1].iter().copied()).collect();
                    assert_same(&lanes(&tr), &tr_want, "truncate");
                    let first = va.resize_down::<U1>();
                    let first_want: Vec<E> = (0..L).map(|l| a[l * K]).collect();
                    assert_same(&lanes(&first), &first_want, "resize_down");

                    // Debug.
                    assert_eq!(format!("{va:?}"), debug_reference::<T>(a, K), "Debug");

                    // PartialEq: IEEE equality of every element and lane.
                    let all_eq = |p: &[E], q: &[E]| p.iter().zip(q).all(|(y, z)| y == z);
                    assert_eq!(va == vb, all_eq(a, b), "==");
                    let copy = va;
                    assert_eq!(va == copy, all_eq(a, a), "== copy (false only with NaN)");
                    let mut w = va;
                    w[j] = vb[j];
                    assert_eq!(va == w, all_eq(a, &lanes(&w)), "== after one change");
                    assert_eq!(va != w, !all_eq(a, &lanes(&w)), "!=");

                    // approx_eq: a relative perturbation of about 1e-7 * |b| per element.
                    let tol: E = [1e-6, 1e-3, 1e-1][t.idx % 3];
                    let rel: E = 1e-7;
                    let pert = naive::zip(a, b, |p, q| p + p * (q * rel));
                    let vp = v(&pert);
                    let want = a.iter().zip(&pert).all(|(&p, &q)| naive::approx_eq(p, q, tol));
                    assert_eq!(va.approx_eq(&vp, tol), want, "approx_eq");
                    let want_self = a.iter().all(|&p| naive::approx_eq(p, p, tol));
                    assert_eq!(va.approx_eq(&va, tol), want_self, "approx_eq with itself");
                    let sum_ab = naive::add(a, b);
                    let want_expr = a.iter().zip(&sum_ab).all(|(&p, &q)| naive::approx_eq(p, q, tol));
                    assert_eq!(va.approx_eq(&va + &vb, tol), want_expr, "approx_eq with an expression");
                });
            }
        }
    };
}

integration_tests::for_each_case!(props);

macro_rules! scalar_props {
    ($m:ident, $t:ty, $e:ty, $kind:ident) => {
        mod $m {
            use super::*;

            type T = $t;
            type E = $e;
            const L: usize = <T as Scalar>::LANES;

            /// `powi::<U..>` against binary exponentiation (bit for bit), and against
            /// repeated multiplication: bit for bit up to the cube, within the rounding
            /// bound `2 e eps |x^e|` beyond.
            #[test]
            fn powi_vs_multiplication() {
                fn body(t: &Inputs<E>, exact_only: bool) {
                    let p = T::from_lanes(|l| t.a[l]);
                    macro_rules! pow_case {
                        ($u:ty, $p:literal) => {{
                            let got = scalar_lanes(powi::<$u, T>(p));
                            let bin = naive::map(&t.a, |y| naive::pow_binary(y, $p));
                            assert_same(&got, &bin, concat!("powi vs binary exponentiation ", $p));
                            let rep = naive::map(&t.a, |y| naive::pow_repeated(y, $p));
                            if $p <= 3 {
                                assert_same(&got, &rep, concat!("powi vs repeated multiplication ", $p));
                            } else if !exact_only {
                                let tol = <E as Real>::EPSILON * (2 * $p) as E;
                                for (g, r) in got.iter().zip(&rep) {
                                    assert!((g - r).abs() <= tol * r.abs(), "powi {}: {g:?} vs repeated {r:?}", $p);
                                }
                            }
                        }};
                    }
                    pow_case!(U0, 0);
                    pow_case!(U1, 1);
                    pow_case!(U2, 2);
                    pow_case!(U3, 3);
                    pow_case!(U4, 4);
                    pow_case!(U5, 5);
                    pow_case!(U7, 7);
                    pow_case!(U8, 8);
                    pow_case!(U13, 13);
                    pow_case!(U16, 16);
                }
                check(64, inputs(L, L, moderate::<E>()), |t| body(&t, false));
                check(64, inputs(L, L, elem::<E>()), |t| body(&t, true));
            }

            /// The cross product of 3-vectors: bit for bit against the formula, exactly
            /// anti-commutative, and orthogonal to its operands within rounding.
            #[test]
            fn cross() {
                fn body(t: &Inputs<E>, finite_data: bool) {
                    let (a, b, c) = (&t.a, &t.b, &t.c);
                    let (va, vb, vc) = (build::<T, U3>(a), build::<T, U3>(b), build::<T, U3>(c));
                    let want: Vec<E> = per_lane2(a, b, 3, naive::cross).concat();
                    let ab = va.cross(&vb);
                    assert_vec_same(&ab, &want, "cross");
                    // Anti-commutative: b x a = -(a x b), up to the sign of exact zeros.
                    let ba = lanes(&(-vb.cross(&va)).eval());
                    for (j, (&p, &q)) in ba.iter().zip(&want).enumerate() {
                        assert!(p == q || (p.is_nan() && q.is_nan()), "-(b x a) element {j}: {p:?} vs {q:?}");
                    }
                    let apb = naive::add(a, b);
                    assert_vec_same(&(&va + &vb).cross(vc), &per_lane2(&apb, c, 3, naive::cross).concat(), "cross of expressions");
                    if finite_data {
                        let eps = <E as Real>::EPSILON;
                        for l in 0..L {
                            let (al, bl, cl) = (&a[l * 3..l * 3 + 3], &b[l * 3..l * 3 + 3], &want[l * 3..l * 3 + 3]);
                            let bound = 16.0 * eps * naive::length_squared(al) * naive::length(bl);
                            let d = naive::dot(cl, al);
                            assert!(d.abs() <= bound, "(a x b) . a = {d:?}, bound {bound:?}");
                        }
                    }
                }
                check(64, inputs(3 * L, L, elem::<E>()), |t| body(&t, false));
                check(64, inputs(3 * L, L, finite::<E>()), |t| body(&t, true));
            }
        }
    };
}

mod per_scalar {
    use super::*;
    integration_tests::for_each_scalar!(scalar_props);
}
