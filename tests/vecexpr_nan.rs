//! The NaN rule of minima, maxima and sums, property-tested for plain floats, packets and
//! the SIMD lane types: every minimum and maximum on vectors (element-wise `min`/`max`,
//! `min_element`, `max_element`, `Packet::reduce_min`/`reduce_max`) is NaN as soon as an
//! operand is NaN and orders `-0.0` below `+0.0` (IEEE 754-2019 `minimum`/`maximum`);
//! a sum is NaN when any term is. Inputs are dense in NaN, signed zeros and infinities.

use crate::prop;

use integration_tests::{naive, RefFloat};
use proptest::prelude::*;
use vecexpr::typenum::{U16, U3, U4, U8};
use vecexpr::{Expr, Packet, Real, Scalar, Vector};

/// An element: NaN one time in four, otherwise a signed zero, an infinity or a small
/// integer (so equal operands are frequent).
fn decode<E: RefFloat>(bits: u64) -> E {
    match bits % 8 {
        0 | 1 => E::NAN,
        2 => E::ZERO,
        3 => -E::ZERO,
        4 => {
            if bits & 0x100 == 0 {
                E::INFINITY
            } else {
                E::NEG_INFINITY
            }
        }
        _ => <E as Real>::from_i32(((bits >> 8) % 7) as i32 - 3),
    }
}

/// `len` elements (lane-major for packets: lane `l`, element `i` at `l * dim + i`).
fn data<E: RefFloat>(len: usize) -> impl Strategy<Value = (Vec<E>, Vec<E>)> + Send {
    let v = proptest::collection::vec(any::<u64>().prop_map(decode::<E>), len);
    (v.clone(), v)
}

/// Same bits, or both NaN (NaN payloads are unspecified).
fn same<E: RefFloat>(a: E, b: E) -> bool {
    a.bits() == b.bits() || (a.is_nan() && b.is_nan())
}

#[track_caller]
fn assert_same<E: RefFloat>(got: E, want: E, what: &str, data: &[E]) {
    assert!(same(got, want), "{what} of {data:?}: {got:?}, want {want:?}");
}

/// The rule on one plain-float vector of dimension `N` against the naive reference, and
/// its consequences stated directly.
fn check_plain<E: RefFloat, N: vecexpr::generic_array::ArrayLength>(a: &[E], b: &[E]) {
    let (va, vb) = (
        Vector::<E, N>::from_slice(a).unwrap(),
        Vector::<E, N>::from_slice(b).unwrap(),
    );
    let any_nan = a.iter().any(|x| x.is_nan());
    let mn = (&va).min_element();
    let mx = (&va).max_element();
    assert_eq!(mn.is_nan(), any_nan, "min_element of {a:?}: {mn:?}");
    assert_eq!(mx.is_nan(), any_nan, "max_element of {a:?}: {mx:?}");
    assert_same(mn, naive::min_element(a), "min_element", a);
    assert_same(mx, naive::max_element(a), "max_element", a);
    if any_nan {
        assert!((&va).sum().is_nan(), "sum of {a:?}");
    }
    if !any_nan {
        // The least element is below or equal to every element, and one of them.
        assert!(a.iter().all(|&x| mn <= x) && a.iter().any(|&x| x.bits() == mn.bits()));
        assert!(a.iter().all(|&x| mx >= x) && a.iter().any(|&x| x.bits() == mx.bits()));
    }
    let emin = (&va).min(&vb).eval();
    let emax = (&va).max(&vb).eval();
    for i in 0..a.len() {
        let nan = a[i].is_nan() || b[i].is_nan();
        assert_eq!(emin[i].is_nan(), nan, "min({:?}, {:?})", a[i], b[i]);
        assert_eq!(emax[i].is_nan(), nan, "max({:?}, {:?})", a[i], b[i]);
        assert_same(emin[i], naive::minimum(a[i], b[i]), "min", &[a[i], b[i]]);
        assert_same(emax[i], naive::maximum(a[i], b[i]), "max", &[a[i], b[i]]);
        // Commutative, signed zeros included.
        assert_same(emin[i], Scalar::minimum(b[i], a[i]), "min reversed", &[a[i], b[i]]);
        assert_same(emax[i], Scalar::maximum(b[i], a[i]), "max reversed", &[a[i], b[i]]);
    }
}

/// A packet vector gives, lane by lane, what the plain vector of that lane gives.
fn check_packet<E: RefFloat, L: vecexpr::generic_array::ArrayLength>(a: &[E], b: &[E])
where
    Packet<E, L>: Scalar<Elem = E>,
{
    const DIM: usize = 3;
    let lanes = L::USIZE;
    let build = |d: &[E]| {
        Vector::<Packet<E, L>, U3>::from_fn(|i| Packet::from_fn(|l| d[l * DIM + i]))
    };
    let (va, vb) = (build(a), build(b));
    let (mn, mx) = ((&va).min_element(), (&va).max_element());
    let (emin, emax) = ((&va).min(&vb).eval(), (&va).max(&vb).eval());
    for l in 0..lanes {
        let (la, lb) = (&a[l * DIM..][..DIM], &b[l * DIM..][..DIM]);
        assert_same(mn.lane(l), naive::min_element(la), "packet min_element", la);
        assert_same(mx.lane(l), naive::max_element(la), "packet max_element", la);
        for i in 0..DIM {
            let ab = [la[i], lb[i]];
            assert_same(emin[i].lane(l), naive::minimum(la[i], lb[i]), "packet min", &ab);
            assert_same(emax[i].lane(l), naive::maximum(la[i], lb[i]), "packet max", &ab);
        }
    }
    // A packet's own reductions over its lanes.
    let lanes0: Vec<E> = (0..lanes).map(|l| a[l * DIM]).collect();
    assert_same(va[0].reduce_min(), naive::min_element(&lanes0), "reduce_min", &lanes0);
    assert_same(va[0].reduce_max(), naive::max_element(&lanes0), "reduce_max", &lanes0);
}

#[test]
fn plain_floats() {
    prop::check(256, data::<f32>(3), |(a, b)| check_plain::<f32, U3>(&a, &b));
    prop::check(256, data::<f64>(3), |(a, b)| check_plain::<f64, U3>(&a, &b));
    prop::check(128, data::<f32>(16), |(a, b)| check_plain::<f32, U16>(&a, &b));
    prop::check(128, data::<f64>(16), |(a, b)| check_plain::<f64, U16>(&a, &b));
}

#[test]
fn packets() {
    prop::check(128, data::<f32>(3 * 8), |(a, b)| check_packet::<f32, U8>(&a, &b));
    prop::check(128, data::<f64>(3 * 4), |(a, b)| check_packet::<f64, U4>(&a, &b));
}

/// The SIMD lane types of every instruction set the CPU has give, lane by lane, what
/// `f32` gives.
#[cfg(target_arch = "x86_64")]
#[test]
fn simd_lanes() {
    use vecexpr::simd::{Isa, Kernel, SimdF32};

    struct Check<'a> {
        a: &'a [f32],
        b: &'a [f32],
    }
    impl Kernel for Check<'_> {
        type Output = ();
        #[inline(always)]
        fn run<S: SimdF32>(self) {
            let n = S::LANES;
            let build = |d: &[f32]| Vector::<S, U3>::from_fn(|i| S::load(&d[i * n..]));
            // Here the data is component-major: component `i`, lane `l` at `i * n + l`.
            let (va, vb) = (build(self.a), build(self.b));
            let (mn, mx) = ((&va).min_element(), (&va).max_element());
            let (emin, emax) = ((&va).min(&vb).eval(), (&va).max(&vb).eval());
            for l in 0..n {
                let la: Vec<f32> = (0..3).map(|i| self.a[i * n + l]).collect();
                let lb: Vec<f32> = (0..3).map(|i| self.b[i * n + l]).collect();
                assert_same(mn.lane(l), naive::min_element(&la), "lanes min_element", &la);
                assert_same(mx.lane(l), naive::max_element(&la), "lanes max_element", &la);
                for i in 0..3 {
                    let ab = [la[i], lb[i]];
                    assert_same(emin[i].lane(l), naive::minimum(la[i], lb[i]), "lanes min", &ab);
                    assert_same(emax[i].lane(l), naive::maximum(la[i], lb[i]), "lanes max", &ab);
                }
            }
        }
    }

    for isa in Isa::available() {
        let len = 3 * isa.lanes();
        prop::check(64, data::<f32>(len), move |(a, b)| {
            isa.dispatch(Check { a: &a, b: &b });
        });
    }
}
