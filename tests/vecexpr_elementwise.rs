//! Property tests of every element-wise vecexpr operation against the naive eager
//! reference, bit for bit, for every scalar type and dimension (see
//! `integration_tests::for_each_case!`).

mod prop;

use integration_tests::{
    assert_expr, assert_same, assert_vec_same, broadcast, build, cases, lanes, mask_lanes, naive, ElemOf,
    TestScalar,
};
use prop::{check, elem, moderate, vec_of};
use vecexpr::typenum::{U0, U1, U13, U16, U2, U3, U4, U5, U7, U8};
use vecexpr::{powi, select, Expr, MaskExpr, Real, Scalar, Vector};

macro_rules! elementwise {
    ($m:ident, $t:ty, $e:ty, $n:ty, $k:literal) => {
        mod $m {
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

            /// `+ - * /` and unary `-` with vectors, owned vectors, expressions and
            /// scalars on either side; `min`, `max`, `abs`, `sqrt`, `recip`, `mul_add`,
            /// `scale`, `map`.
            #[test]
            fn arithmetic() {
                let s = (
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), L),
                    elem::<E>(),
                );
                check(CASES, s, |(a, b, c, s, x)| {
                    let (va, vb, vc) = (v(&a), v(&b), v(&c));
                    let st = packet(&s);
                    let sb = broadcast(&s, K);
                    let xb = vec![x; LEN];

                    assert_expr((&va + &vb), &naive::add(&a, &b), "a + b");
                    assert_expr((&va - &vb), &naive::sub(&a, &b), "a - b");
                    assert_expr((&va * &vb), &naive::mul(&a, &b), "a * b");
                    assert_expr((&va / &vb), &naive::div(&a, &b), "a / b");
                    // Owned leaves (moved copies) and mixed owned/borrowed.
                    assert_expr((va + vb), &naive::add(&a, &b), "owned a + b");
                    assert_expr((va - &vb), &naive::sub(&a, &b), "owned a - &b");
                    assert_expr((va * vb), &naive::mul(&a, &b), "owned a * b");
                    assert_expr((va / &vb), &naive::div(&a, &b), "owned a / &b");

                    // Scalar of the vector's own type on the right...
                    assert_expr((&va + st), &naive::add(&a, &sb), "a + s");
                    assert_expr((&va - st), &naive::sub(&a, &sb), "a - s");
                    assert_expr((&va * st), &naive::mul(&a, &sb), "a * s");
                    assert_expr((&va / st), &naive::div(&a, &sb), "a / s");
                    // ... and on the left.
                    assert_expr((st + &va), &naive::add(&sb, &a), "s + a");
                    assert_expr((st - &va), &naive::sub(&sb, &a), "s - a");
                    assert_expr((st * &va), &naive::mul(&sb, &a), "s * a");
                    assert_expr((st / &va), &naive::div(&sb, &a), "s / a");
                    assert_expr((st - (&va + &vb)), &naive::sub(&sb, &naive::add(&a, &b)), "s - (a + b)");
                    // A plain lane value broadcast to every lane (packets) or element.
                    assert_expr((&va + x), &naive::add(&a, &xb), "a + x");
                    assert_expr((&va - x), &naive::sub(&a, &xb), "a - x");
                    assert_expr((&va * x), &naive::mul(&a, &xb), "a * x");
                    assert_expr((&va / x), &naive::div(&a, &xb), "a / x");
                    assert_expr((&va).scale(st), &naive::mul(&a, &sb), "a.scale(s)");

                    // Unary.
                    assert_expr((-&va), &naive::neg(&a), "-a");
                    assert_expr((-va), &naive::neg(&a), "-owned a");
                    assert_expr((-(&va * &vb)), &naive::neg(&naive::mul(&a, &b)), "-(a * b)");
                    assert_expr((&va).abs(), &naive::abs(&a), "abs");
                    assert_expr((&va).sqrt(), &naive::sqrt(&a), "sqrt");
                    assert_expr((&va).recip(), &naive::recip(&a), "recip");
                    assert_expr((&va - &vb).abs().sqrt(), &naive::sqrt(&naive::abs(&naive::sub(&a, &b))), "sqrt(abs(a - b))");

                    // min / max with the minps rule.
                    assert_expr(va.min(&vb), &naive::min(&a, &b), "min");
                    assert_expr(va.max(&vb), &naive::max(&a, &b), "max");
                    assert_expr(va.min(st), &naive::min(&a, &sb), "min(a, s)");
                    assert_expr(va.max(x), &naive::max(&a, &xb), "max(a, x)");
                    assert_expr((&va + &vc).min(&vb - &vc), &naive::min(&naive::add(&a, &c), &naive::sub(&b, &c)), "min of expressions");

                    // mul_add with vectors, expressions and scalars.
                    assert_expr(va.mul_add(&vb, &vc), &naive::mul_add(&a, &b, &c), "mul_add");
                    assert_expr(va.mul_add(st, x), &naive::mul_add(&a, &sb, &xb), "mul_add(s, x)");
                    assert_expr((&va * &vb).mul_add(&vc, &va), &naive::mul_add(&naive::mul(&a, &b), &c, &a), "mul_add of expression");

                    // map with a closure; the reference applies the same closure per lane.
                    let f = |y: T| y * y - y;
                    let g = |y: E| y * y - y;
                    assert_expr((&va).map(f), &naive::map(&a, g), "map");
                    assert_expr((&va + &vb).map(f), &naive::map(&naive::add(&a, &b), g), "map of expression");
                    assert_expr(((&va).map(f) * &vc), &naive::mul(&naive::map(&a, g), &c), "map in a tree");
                });
            }

            /// Comparisons, mask combinations and `select`.
            #[test]
            fn select_and_masks() {
                let s = (
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), LEN),
                    elem::<E>(),
                );
                check(CASES, s, |(a, b, c, x)| {
                    let (va, vb, vc) = (v(&a), v(&b), v(&c));
                    let xb = vec![x; LEN];
                    let lt = naive::compare(&a, &b, |p, q| p < q);
                    let le = naive::compare(&a, &b, |p, q| p <= q);
                    let gt = naive::compare(&a, &b, |p, q| p > q);
                    let ge = naive::compare(&a, &b, |p, q| p >= q);
                    let eq = naive::compare(&a, &b, |p, q| p == q);
                    let ltc = naive::compare(&b, &c, |p, q| p < q);

                    assert_eq!(mask_lanes(&va.lt(&vb).eval()), lt, "lt");
                    assert_eq!(mask_lanes(&va.le(&vb).eval()), le, "le");
                    assert_eq!(mask_lanes(&va.gt(&vb).eval()), gt, "gt");
                    assert_eq!(mask_lanes(&va.ge(&vb).eval()), ge, "ge");
                    assert_eq!(mask_lanes(&va.eq_mask(&vb).eval()), eq, "eq_mask");
                    let gtx = naive::compare(&a, &xb, |p, q| p > q);
                    assert_eq!(mask_lanes(&va.gt(x).eval()), gtx, "gt scalar");

                    let and: Vec<bool> = lt.iter().zip(&ltc).map(|(&p, &q)| p && q).collect();
                    let or: Vec<bool> = eq.iter().zip(&ltc).map(|(&p, &q)| p || q).collect();
                    let not: Vec<bool> = le.iter().map(|&p| !p).collect();
                    assert_eq!(mask_lanes(&va.lt(&vb).and(vb.lt(&vc)).eval()), and, "and");
                    assert_eq!(mask_lanes(&va.eq_mask(&vb).or(vb.lt(&vc)).eval()), or, "or");
                    assert_eq!(mask_lanes(&va.le(&vb).not().eval()), not, "not");
                    assert_eq!(va.lt(&vb).all(), lt.iter().all(|&p| p), "all");
                    assert_eq!(va.lt(&vb).any(), lt.iter().any(|&p| p), "any");

                    assert_expr(select(va.lt(&vb), &va, &vb), &naive::select(&lt, &a, &b), "select lt");
                    assert_expr(select(va.le(&vb), &vc, &va), &naive::select(&le, &c, &a), "select le");
                    assert_expr(select(va.gt(&vb), &va, &vc), &naive::select(&gt, &a, &c), "select gt");
                    assert_expr(select(va.ge(&vb), &vb, &vc), &naive::select(&ge, &b, &c), "select ge");
                    assert_expr(select(va.eq_mask(&vb), &vc, &vb), &naive::select(&eq, &c, &b), "select eq");
                    let and_sel = naive::select(&and, &naive::add(&a, &b), &xb);
                    assert_expr(select(va.lt(&vb).and(vb.lt(&vc)), &va + &vb, x), &and_sel, "select and, expression branch");
                    let or_sel = naive::select(&or, &xb, &naive::abs(&c));
                    assert_expr(select(va.eq_mask(&vb).or(vb.lt(&vc)), x, (&vc).abs()), &or_sel, "select or");
                    let not_sel = naive::select(&not, &a, &naive::neg(&b));
                    assert_expr(select(va.le(&vb).not(), &va, -&vb), &not_sel, "select not");
                    // A mask evaluated into a vector is itself a mask expression.
                    let mv = va.lt(&vb).eval();
                    assert_expr(select(&mv, &vc, &va), &naive::select(&lt, &c, &a), "select stored mask");
                    // Select inside a larger tree: ReLU-like clamp times a vector.
                    let relu = naive::mul(&naive::select(&gtx, &a, &xb), &b);
                    assert_expr((select(va.gt(x), &va, x) * &vb), &relu, "select in a tree");
                });
            }

            /// `eval` vs `eval_boxed` vs `assign` vs the in-place operators vs `update`.
            #[test]
            fn assignment_forms() {
                let s = (
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), L),
                    elem::<E>(),
                );
                check(CASES, s, |(a, b, c, s, x)| {
                    let (va, vb, vc) = (v(&a), v(&b), v(&c));
                    let st = packet(&s);
                    let sb = broadcast(&s, K);
                    let xb = vec![x; LEN];
                    let want = naive::add(&naive::mul(&a, &b), &c);

                    let e = (&va * &vb + &vc).eval();
                    assert_vec_same(&e, &want, "eval");
                    let boxed = (&va * &vb + &vc).eval_boxed();
                    assert_vec_same(&boxed, &want, "eval_boxed");
                    // assign overwrites every element, whatever was there.
                    let mut out = Vector::<T, N>::splat(T::splat(<E as Real>::NAN));
                    out.assign(&va * &vb + &vc);
                    assert_vec_same(&out, &want, "assign");
                    out.assign(&vb);
                    assert_vec_same(&out, &b, "assign a vector");
                    out.assign(st);
                    assert_vec_same(&out, &sb, "assign a scalar");
                    out.assign(va);
                    assert_vec_same(&out, &a, "assign an owned vector");

                    // In-place operators, each checked against the reference state.
                    let mut w = va;
                    let mut r = a.clone();
                    w += &vb;
                    r = naive::add(&r, &b);
                    assert_vec_same(&w, &r, "+= vector");
                    w -= &vc * st;
                    r = naive::sub(&r, &naive::mul(&c, &sb));
                    assert_vec_same(&w, &r, "-= expression");
                    w *= x;
                    r = naive::mul(&r, &xb);
                    assert_vec_same(&w, &r, "*= lane scalar");
                    w /= (&vb).abs();
                    r = naive::div(&r, &naive::abs(&b));
                    assert_vec_same(&w, &r, "/= expression");
                    w += st;
                    r = naive::add(&r, &sb);
                    assert_vec_same(&w, &r, "+= scalar");
                    w -= vc;
                    r = naive::sub(&r, &c);
                    assert_vec_same(&w, &r, "-= owned");
                    w *= &va - &vb;
                    r = naive::mul(&r, &naive::sub(&a, &b));
                    assert_vec_same(&w, &r, "*= expression");
                    w /= st;
                    r = naive::div(&r, &sb);
                    assert_vec_same(&w, &r, "/= scalar");

                    // The same sequence spelt with update().
                    let mut u = va;
                    u.update(&vb, |o, n| o + n);
                    u.update(&vc * st, |o, n| o - n);
                    u.update(x, |o, n| o * n);
                    u.update((&vb).abs(), |o, n| o / n);
                    let mut r2 = naive::add(&a, &b);
                    r2 = naive::sub(&r2, &naive::mul(&c, &sb));
                    r2 = naive::mul(&r2, &xb);
                    r2 = naive::div(&r2, &naive::abs(&b));
                    assert_vec_same(&u, &r2, "update sequence");
                    // A non-arithmetic update function.
                    let mut m = va;
                    m.update(&vb, |o, n| o * n - o);
                    assert_vec_same(&m, &naive::zip(&a, &b, |p, q| p * q - p), "update closure");
                    // In-place map.
                    let mut ap = va;
                    ap.apply(|y| y + y);
                    assert_vec_same(&ap, &naive::map(&a, |y| y + y), "apply");
                });
            }

            /// Deep fused trees: `a*b + c*d - e` and a nine-level nesting of every kind of
            /// node, against the same formula per element.
            #[test]
            fn deep_trees() {
                let s = (
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), LEN),
                    vec_of(elem::<E>(), L),
                );
                check(CASES, s, |(a, b, c, d, e, s)| {
                    let (va, vb, vc, vd, ve) = (v(&a), v(&b), v(&c), v(&d), v(&e));
                    let st = packet(&s);
                    let sb = broadcast(&s, K);

                    let want = naive::sub(&naive::add(&naive::mul(&a, &b), &naive::mul(&c, &d)), &e);
                    assert_expr((&va * &vb + &vc * &vd - &ve), &want, "a*b + c*d - e");
                    assert_expr((va * vb + vc * vd - ve), &want, "owned a*b + c*d - e");
                    let mut out = Vector::<T, N>::zero();
                    out.assign(&va * &vb + &vc * &vd - &ve);
                    assert_vec_same(&out, &want, "assign a*b + c*d - e");

                    let one: E = 1.0;
                    // Levels: + * - / max sqrt mul_add - min (abs, -, * inside).
                    let tree = ((((&va + &vb) * &vc - (&vd).abs()) / (&ve * &ve + one))
                        .max(-&va)
                        .sqrt()
                        .mul_add(&vb, &vc)
                        - st)
                        .min(&vd);
                    let want: Vec<E> = (0..LEN)
                        .map(|j| {
                            let mut y = ((a[j] + b[j]) * c[j] - d[j].abs()) / (e[j] * e[j] + one);
                            y = naive::max_rule(y, -a[j]);
                            y = y.sqrt();
                            y = y.mul_add(b[j], c[j]);
                            y = y - sb[j];
                            naive::min_rule(y, d[j])
                        })
                        .collect();
                    assert_expr(tree, &want, "nested tree");
                    let mut out2 = Vector::<T, N>::zero();
                    out2.assign(tree);
                    assert_vec_same(&out2, &want, "assign nested tree");

                    // Six levels of alternating scalar-left and scalar-right operations.
                    let six = st - (((((&va * st + &vb) / st - &vc) * st + &vd) / st) - &ve);
                    let want6: Vec<E> = (0..LEN)
                        .map(|j| {
                            let q = sb[j];
                            q - (((((a[j] * q + b[j]) / q - c[j]) * q + d[j]) / q) - e[j])
                        })
                        .collect();
                    assert_expr(six, &want6, "six levels with scalars");
                });
            }

            /// `powi::<U..>` against binary exponentiation (bit for bit) and repeated
            /// multiplication (bit for bit up to the cube, within the rounding bound
            /// beyond).
            #[test]
            fn powi_vs_multiplication() {
                let s = (vec_of(elem::<E>(), LEN), vec_of(moderate::<E>(), LEN));
                check(CASES, s, |(a, m)| {
                    let (va, vm) = (v(&a), v(&m));
                    macro_rules! pow_case {
                        ($u:ty, $p:literal) => {{
                            let got = (&va).map(powi::<$u, T>).eval();
                            let want = naive::map(&a, |y| naive::pow_binary(y, $p));
                            assert_vec_same(&got, &want, concat!("powi ", $p));
                            let got = lanes(&(&vm).map(powi::<$u, T>).eval());
                            let rep = naive::map(&m, |y| naive::pow_repeated(y, $p));
                            if $p <= 3 {
                                assert_same(&got, &rep, concat!("powi vs repeated ", $p));
                            } else {
                                let tol = <E as Real>::EPSILON * (2.0 * $p as E);
                                for (j, (&g, &r)) in got.iter().zip(&rep).enumerate() {
                                    assert!(
                                        (g - r).abs() <= tol * r.abs(),
                                        "powi {} element {j}: {g:?} vs repeated {r:?}",
                                        $p
                                    );
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
                    // powi on a packet scalar directly, lane by lane.
                    let p = (&va).sum();
                    let lanes_p = integration_tests::scalar_lanes(p);
                    integration_tests::assert_scalar_same(
                        powi::<U5, T>(p),
                        &naive::map(&lanes_p, |y: ElemOf<T>| naive::pow_binary(y, 5)),
                        "powi of a scalar",
                    );
                });
            }
        }
    };
}

elementwise!(n3, f32, f32, vecexpr::typenum::U3, 3);

