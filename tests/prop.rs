//! Property-test glue of the property tests (`mod prop;`): input strategies and a
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

/// How an element is drawn: a function of 64 random bits. Drawing through a plain
/// function (rather than a union of boxed strategies per element) keeps the generation of
/// 16 000-element inputs fast; shrinking moves the bits towards zero, which every decoder
/// maps to `+0.0`.
pub type Decode<E> = fn(u64) -> E;

/// The value part of the bits: the 53 bits above the low 11, as a fraction in [0, 1).
fn unit(bits: u64) -> f64 {
    (bits >> 11) as f64 / (1u64 << 53) as f64
}

/// A moderate real: magnitude in [0, 1000), sign from bit 4.
fn moderate_real<E: RefFloat>(bits: u64) -> E {
    let m = unit(bits) * 1.0e3;
    <E as Real>::from_f64(if bits & 0x10 == 0 { m } else { -m })
}

/// A small integer in [-8, 8] (collisions make comparisons see equal operands).
fn small_int<E: RefFloat>(bits: u64) -> E {
    <E as Real>::from_i32(((bits >> 11) % 17) as i32 - 8)
}

fn decode_elem<E: RefFloat>(bits: u64) -> E {
    match bits % 9 {
        0..=5 => moderate_real(bits),
        6 | 7 => small_int(bits),
        _ => {
            let specials = E::specials();
            specials[((bits >> 11) % specials.len() as u64) as usize]
        }
    }
}

fn decode_finite<E: RefFloat>(bits: u64) -> E {
    match bits % 8 {
        0..=5 => moderate_real(bits),
        _ => small_int(bits),
    }
}

fn decode_wide<E: RefFloat>(bits: u64) -> E {
    match bits % 4 {
        0 | 1 => {
            // Uniform over bit patterns: every exponent equally likely. The low two bits
            // are spent on the choice, so rotate fresh bits into place.
            let x = E::from_bits_u64(bits.rotate_right(2));
            if x.is_finite() {
                x
            } else {
                moderate_real(bits)
            }
        }
        2 => moderate_real(bits),
        _ => E::ZERO,
    }
}

fn decode_moderate<E: RefFloat>(bits: u64) -> E {
    let m = 0.25 + unit(bits) * 3.75;
    <E as Real>::from_f64(if bits & 0x10 == 0 { m } else { -m })
}

/// Any element, weighted towards ordinary values: moderate reals (6 in 9), small integers
/// (2 in 9), and the IEEE special values of [`RefFloat::specials`] (signed zeros,
/// infinities, NaN, subnormals, extremes).
pub fn elem<E: RefFloat>() -> Decode<E> {
    decode_elem::<E>
}

/// Finite elements of moderate size: squares and long sums stay far from overflow.
pub fn finite<E: RefFloat>() -> Decode<E> {
    decode_finite::<E>
}

/// Any finite element, from the whole exponent range: subnormals, tiny and huge
/// magnitudes alike (uniform over bit patterns), mixed with moderate values and zeros.
pub fn wide_finite<E: RefFloat>() -> Decode<E> {
    decode_wide::<E>
}

/// Magnitudes in [1/4, 4] with either sign: powers up to 16 neither overflow nor
/// underflow.
pub fn moderate<E: RefFloat>() -> Decode<E> {
    decode_moderate::<E>
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
/// with `decode`. All tests share this one strategy type, so the property-test machinery
/// is compiled once per lane type.
pub fn inputs<E: RefFloat>(
    len: usize,
    lanes: usize,
    decode: Decode<E>,
) -> SBoxedStrategy<Inputs<E>> {
    let elem = any::<u64>().prop_map(decode);
    let v = |n| proptest::collection::vec(elem.clone(), n);
    (
        v(len),
        v(len),
        v(len),
        v(len),
        v(len),
        v(lanes),
        elem.clone(),
        any::<usize>(),
    )
        .prop_map(|(a, b, c, d, e, s, x, idx)| Inputs {
            a,
            b,
            c,
            d,
            e,
            s,
            x,
            idx,
        })
        .sboxed()
}
