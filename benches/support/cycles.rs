//! The tracer's cycle counter ([`tracer::cycles`]) as a criterion [`Measurement`]: an
//! iteration batch is timed from a serialised `rdtsc` to a serialised `rdtscp`, in TSC
//! ticks (reference cycles at the nominal frequency), or in nanoseconds where the
//! processor has no invariant TSC.

use criterion::measurement::{Measurement, ValueFormatter};
use criterion::Throughput;

/// Criterion measurement in cycle-counter ticks.
#[derive(Clone, Copy, Debug, Default)]
pub struct Cycles;

impl Measurement for Cycles {
    type Intermediate = u64;
    type Value = u64;

    #[inline(always)]
    fn start(&self) -> u64 {
        tracer::cycles::start()
    }

    #[inline(always)]
    fn end(&self, start: u64) -> u64 {
        tracer::cycles::since(start)
    }

    fn add(&self, a: &u64, b: &u64) -> u64 {
        a + b
    }

    fn zero(&self) -> u64 {
        0
    }

    fn to_f64(&self, v: &u64) -> f64 {
        *v as f64
    }

    fn formatter(&self) -> &dyn ValueFormatter {
        &CyclesFormatter
    }
}

/// Prints ticks as `cycles`, `Kcycles`, `Mcycles`, and throughput per cycle.
struct CyclesFormatter;

impl ValueFormatter for CyclesFormatter {
    fn scale_values(&self, typical: f64, values: &mut [f64]) -> &'static str {
        let (div, unit) = if typical < 1e4 {
            (1.0, "cycles")
        } else if typical < 1e7 {
            (1e3, "Kcycles")
        } else {
            (1e6, "Mcycles")
        };
        values.iter_mut().for_each(|v| *v /= div);
        unit
    }

    fn scale_throughputs(&self, _typical: f64, t: &Throughput, values: &mut [f64]) -> &'static str {
        let (n, unit) = match t {
            Throughput::Bytes(n) | Throughput::BytesDecimal(n) => (*n as f64, "B/cycle"),
            Throughput::Elements(n) => (*n as f64, "elem/cycle"),
            Throughput::Bits(n) => (*n as f64, "bit/cycle"),
        };
        values.iter_mut().for_each(|v| *v = n / *v);
        unit
    }

    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "cycles"
    }
}
