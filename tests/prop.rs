//! Property-test glue shared by the test files (`mod prop;`): input strategies and a
//! runner that executes each property on a thread with a large stack, so that several
//! 1000-element vectors of 16-lane packets (64 KiB each) fit comfortably.
#![allow(dead_code)]

use integration_tests::RefFloat;
use proptest::prelude::*;
use proptest::strategy::{SBoxedStrategy, Strategy};
use proptest::test_runner::{Config, TestRunner};
use vecexpr::Real;

/// Stack size of the thread that runs a property.
const STACK: usize = 64 << 20;

/// Runs `test` on `cases` inputs drawn from `strategy`, shrinking and reporting the
/// smallest failing input if any case panics.
///
/// # Panics
/// If a case fails.
#[track_caller]
pub fn check<S>(cases: u32, strategy: S, test: impl Fn(S::Value) + Send + Sync + 'static)
where
    S: Strategy + Send + 'static,
{
    // One runner instantiation per strategy type, not per test closure: the property
    // is called through a trait object, which keeps the test binaries small.
    run(cases, strategy, Box::new(test));
}

fn run<S>(cases: u32, strategy: S, test: Box<dyn Fn(S::Value) + Send + Sync>)
where
    S: Strategy + Send + 'static,
{
    let handle = std::thread::Builder::new()
        .stack_size(STACK)
        .spawn(move || {
            let config = Config {
                cases,
                failure_persistence: None,
                max_shrink_iters: 512,
                ..Config::default()
            };
            let mut runner = TestRunner::new(config);
            if let Err(e) = runner.run(&strategy, |v| {
                test(v);
                Ok(())
            }) {
                panic!("{e}");
            }
        })
        .expect("spawn the property-test thread");
    if let Err(panic) = handle.join() {
        std::panic::resume_unwind(panic);
    }
}

/// Any element, weighted towards ordinary values: moderate reals, small integers (which
/// collide, so comparisons see equal operands), and the IEEE special values of
/// [`RefFloat::specials`] (signed zeros, infinities, NaN, subnormals, extremes).
pub fn elem<E: RefFloat>() -> SBoxedStrategy<E> {
    prop_oneof![
        6 => (-1.0e3f64..1.0e3).prop_map(<E as Real>::from_f64),
        2 => (-8i32..=8).prop_map(<E as Real>::from_i32),
        1 => proptest::sample::select(E::specials()),
    ]
    .sboxed()
}

/// Finite elements of moderate size: squares and long sums stay far from overflow.
pub fn finite<E: RefFloat>() -> SBoxedStrategy<E> {
    prop_oneof![
        6 => (-1.0e3f64..1.0e3).prop_map(<E as Real>::from_f64),
        2 => (-8i32..=8).prop_map(<E as Real>::from_i32),
    ]
    .sboxed()
}

/// Any finite element, from the whole exponent range: subnormals, tiny and huge
/// magnitudes alike (uniform over bit patterns), mixed with moderate values.
pub fn wide_finite<E: RefFloat>() -> SBoxedStrategy<E> {
    prop_oneof![
        2 => any::<u64>()
            .prop_map(E::from_bits_u64)
            .prop_filter("finite", |x| x.is_finite()),
        1 => (-1.0e3f64..1.0e3).prop_map(<E as Real>::from_f64),
        1 => Just(E::ZERO),
    ]
    .sboxed()
}

/// Magnitudes in [1/4, 4] with either sign: powers up to 16 neither overflow nor
/// underflow.
pub fn moderate<E: RefFloat>() -> SBoxedStrategy<E> {
    (0.25f64..4.0, any::<bool>())
        .prop_map(|(m, neg)| <E as Real>::from_f64(if neg { -m } else { m }))
        .sboxed()
}

/// The operands of one property-test case, in lane-major order (see
/// `integration_tests::build`): five vectors of `N * LANES` elements, a per-lane scalar,
/// one lane value and a free index.
#[derive(Clone, Debug)]
pub struct Inputs<E> {
    /// First vector operand.
    pub a: Vec<E>,
    /// Second vector operand.
    pub b: Vec<E>,
    /// Third vector operand.
    pub c: Vec<E>,
    /// Fourth vector operand.
    pub d: Vec<E>,
    /// Fifth vector operand.
    pub e: Vec<E>,
    /// A scalar of the vector's own type, one value per lane.
    pub s: Vec<E>,
    /// A plain lane value.
    pub x: E,
    /// An arbitrary index (reduce it modulo what is needed).
    pub idx: usize,
}

/// Inputs with vectors of `len` elements and `lanes` scalar lanes, every element drawn
/// from `elem`. All tests share this one strategy type, so the property-test machinery is
/// compiled once per lane type.
pub fn inputs<E: RefFloat>(len: usize, lanes: usize, elem: SBoxedStrategy<E>) -> SBoxedStrategy<Inputs<E>> {
    let v = || proptest::collection::vec(elem.clone(), len);
    (
        v(),
        v(),
        v(),
        v(),
        v(),
        proptest::collection::vec(elem.clone(), lanes),
        elem.clone(),
        any::<usize>(),
    )
        .prop_map(|(a, b, c, d, e, s, x, idx)| Inputs { a, b, c, d, e, s, x, idx })
        .sboxed()
}
