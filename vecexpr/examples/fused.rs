//! Fused versus eager evaluation of `a*b + c*d - e` over one million `f32` elements.
//!
//! * fused: vecexpr builds the expression tree and assigns it into a preallocated boxed
//!   vector in one loop, with no temporary;
//! * eager: a plain vector type whose every operator allocates and fills a new `Vec`
//!   (four temporaries for this expression, the last one being the result);
//! * hand-written: the loop one would write by hand over slices.
//!
//! Each version runs several times; the example prints the median time per evaluation,
//! the time per element and the speedup of fused over eager, and checks that all three
//! agree bit for bit (they perform the same operations in the same order).
//!
//! Run with `cargo run --release -p vecexpr --example fused`.

use std::hint::black_box;
use std::ops::{Add, Mul, Sub};
use std::time::{Duration, Instant};
use vecexpr::typenum::{Prod, U1000};
use vecexpr::Vector;

/// One million, as a type: the dimension of the vectors.
type Million = Prod<U1000, U1000>;
type Big = Vector<f32, Million>;
const LEN: usize = 1_000_000;
const RUNS: usize = 15;

/// The eager alternative: every operator returns a freshly allocated vector.
struct Eager(Vec<f32>);

impl Eager {
    fn zip_with(&self, rhs: &Eager, f: impl Fn(f32, f32) -> f32) -> Eager {
        Eager(self.0.iter().zip(&rhs.0).map(|(&x, &y)| f(x, y)).collect())
    }
}

impl Add for &Eager {
    type Output = Eager;
    fn add(self, rhs: &Eager) -> Eager {
        self.zip_with(rhs, |x, y| x + y)
    }
}

impl Sub for &Eager {
    type Output = Eager;
    fn sub(self, rhs: &Eager) -> Eager {
        self.zip_with(rhs, |x, y| x - y)
    }
}

impl Mul for &Eager {
    type Output = Eager;
    fn mul(self, rhs: &Eager) -> Eager {
        self.zip_with(rhs, |x, y| x * y)
    }
}

/// Deterministic inputs in [-8, 8) from a 64-bit linear congruential generator (Knuth's
/// MMIX constants).
fn input(seed: u64) -> Vec<f32> {
    let mut s = seed;
    (0..LEN)
        .map(|_| {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((s >> 40) as f32 / (1u64 << 24) as f32) * 16.0 - 8.0
        })
        .collect()
}

/// Runs `f` `RUNS` times after one warm-up run and returns the median duration.
fn median_time(mut f: impl FnMut()) -> Duration {
    f();
    let mut times: Vec<Duration> = (0..RUNS)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed()
        })
        .collect();
    times.sort();
    times[RUNS / 2]
}

fn main() {
    let [a, b, c, d, e] = [1, 2, 3, 4, 5].map(input);

    // vecexpr: boxed vectors (4 MB each, too big for the stack), result preallocated.
    let boxed = |x: &[f32]| -> Box<Big> { Vector::boxed_from_fn(|i| x[i]) };
    let (va, vb, vc, vd, ve) = (boxed(&a), boxed(&b), boxed(&c), boxed(&d), boxed(&e));
    let mut fused_out: Box<Big> = Vector::boxed_splat(0.0);
    let fused = median_time(|| {
        let (a, b, c, d, e) = black_box((&*va, &*vb, &*vc, &*vd, &*ve));
        fused_out.assign(a * b + c * d - e);
        black_box(&mut *fused_out);
    });

    // Eager: a*b, c*d, their sum and the difference each allocate a new vector.
    let [ea, eb, ec, ed, ee] = [&a, &b, &c, &d, &e].map(|x| Eager(x.clone()));
    let mut eager_out = Eager(Vec::new());
    let eager = median_time(|| {
        let (a, b, c, d, e) = black_box((&ea, &eb, &ec, &ed, &ee));
        eager_out = &(&(a * b) + &(c * d)) - e;
        black_box(&eager_out);
    });

    // Hand-written loop over slices into a preallocated buffer.
    let mut hand_out = vec![0.0f32; LEN];
    let hand = median_time(|| {
        let (a, b, c, d, e) = black_box((&a, &b, &c, &d, &e));
        let inputs = a.iter().zip(b).zip(c.iter().zip(d)).zip(e);
        for (o, (((&a, &b), (&c, &d)), &e)) in hand_out.iter_mut().zip(inputs) {
            *o = a * b + c * d - e;
        }
        black_box(&mut hand_out);
    });

    // Same operations in the same order: the results must agree bit for bit.
    let same = |x: &[f32], y: &[f32]| {
        x.len() == y.len() && x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits())
    };
    assert!(
        same(fused_out.as_slice(), &eager_out.0),
        "fused and eager differ"
    );
    assert!(
        same(fused_out.as_slice(), &hand_out),
        "fused and hand-written differ"
    );

    let report = |name: &str, t: Duration| {
        let ms = t.as_secs_f64() * 1e3;
        let ns = t.as_secs_f64() * 1e9 / LEN as f64;
        println!("{name:<14} {ms:>9.3} ms {ns:>9.3} ns/element");
    };
    println!("a*b + c*d - e over {LEN} f32 elements, median of {RUNS} runs");
    report("fused", fused);
    report("eager", eager);
    report("hand-written", hand);
    println!(
        "speedup fused vs eager: {:.2}x; fused vs hand-written: {:.2}x the time",
        eager.as_secs_f64() / fused.as_secs_f64(),
        fused.as_secs_f64() / hand.as_secs_f64()
    );
    println!("results agree bit for bit");
}
