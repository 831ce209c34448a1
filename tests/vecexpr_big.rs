//! One million elements: vectors live in boxes (4 MB each would overflow the stack), the
//! fused `a*b + c*d - e` is assigned into a preallocated box, and the result equals the
//! naive per-element loop bit for bit.

use integration_tests::naive;
use vecexpr::typenum::{Prod, U1000};
use vecexpr::{Expr, Vector};

type Million = Prod<U1000, U1000>;
type Big = Vector<f32, Million>;
const LEN: usize = 1_000_000;

/// Deterministic, varied inputs: a 64-bit linear congruential generator (Knuth's MMIX
/// constants) mapped to [-8, 8), with every 97th element a small integer so that
/// cancellation and exact zeros occur too.
fn data(seed: u64) -> Vec<f32> {
    let mut s = seed;
    (0..LEN)
        .map(|i| {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            if i % 97 == 0 {
                ((s >> 60) as f32) - 8.0
            } else {
                ((s >> 40) as f32 / (1u64 << 24) as f32) * 16.0 - 8.0
            }
        })
        .collect()
}

#[test]
fn million_element_fused_tree_matches_the_loop() {
    assert_eq!(Big::DIM, LEN);
    let [a, b, c, d, e] = [1, 2, 3, 4, 5].map(data);
    let boxed = |x: &[f32]| -> Box<Big> { Vector::boxed_from_fn(|i| x[i]) };
    let (va, vb, vc, vd, ve) = (boxed(&a), boxed(&b), boxed(&c), boxed(&d), boxed(&e));

    let want: Vec<f32> = (0..LEN).map(|i| a[i] * b[i] + c[i] * d[i] - e[i]).collect();
    let mut out: Box<Big> = Vector::boxed_splat(f32::NAN);
    out.assign(&*va * &*vb + &*vc * &*vd - &*ve);
    integration_tests::assert_same(out.as_slice(), &want, "assign a*b + c*d - e");

    // eval_boxed builds the same result directly on the heap.
    let evaluated = (&*va * &*vb + &*vc * &*vd - &*ve).eval_boxed();
    integration_tests::assert_same(evaluated.as_slice(), &want, "eval_boxed");

    // In place, with no temporary: out = out * 2 - a.
    *out *= 2.0;
    *out -= &*va;
    let want2: Vec<f32> = want.iter().zip(&a).map(|(&w, &x)| w * 2.0 - x).collect();
    integration_tests::assert_same(out.as_slice(), &want2, "in-place update");

    // A reduction over a million elements: the documented interleaved order exactly,
    // and the rounding bound of the sequential sum.
    let dot = va.dot(&*vb);
    assert_eq!(dot.to_bits(), naive::dot(&a, &b).to_bits());
    let products = naive::mul(&a, &b);
    let seq = naive::sum_sequential(&products);
    let abs_sum: f64 = products.iter().map(|&p| f64::from(p.abs())).sum();
    let bound = 2.0 * LEN as f64 * f64::from(f32::EPSILON) * abs_sum;
    assert!(
        f64::from((dot - seq).abs()) <= bound,
        "dot {dot} vs sequential {seq}"
    );
    // Each of the 32 partial sums adds LEN / 32 terms and the pairwise combination five
    // more levels, so against the exact sum (f64 is exact enough here) the error is at
    // most (LEN / 32 + 5) eps sum|p|, 32 times tighter than the sequential bound.
    let exact: f64 = products.iter().map(|&p| f64::from(p)).sum();
    let tight = (LEN / 32 + 6) as f64 * f64::from(f32::EPSILON) * abs_sum;
    assert!(
        (f64::from(dot) - exact).abs() <= tight,
        "dot {dot} vs exact {exact}"
    );
}
