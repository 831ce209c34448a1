//! Process CPU time (`clock_gettime(CLOCK_PROCESS_CPUTIME_ID)`, through
//! [`tracer::stats::process_cpu_ms`]) as a criterion [`Measurement`], in nanoseconds.
//!
//! On a machine shared with other jobs, wall time counts the time the benchmark thread
//! waits for a core; CPU time does not, so medians stay steady under load (what remains
//! is the other jobs' effect on caches). Criterion times iterations on one thread, so
//! the process clock is that thread's. Where the clock is unavailable every value is 0.

use criterion::measurement::{Measurement, ValueFormatter};
use criterion::Throughput;

/// Criterion measurement in nanoseconds of process CPU time.
#[derive(Clone, Copy, Debug, Default)]
pub struct CpuTime;

fn now_ns() -> f64 {
    tracer::stats::process_cpu_ms().unwrap_or(0.0) * 1e6
}

impl Measurement for CpuTime {
    type Intermediate = f64;
    type Value = f64;

    fn start(&self) -> f64 {
        now_ns()
    }

    fn end(&self, start: f64) -> f64 {
        now_ns() - start
    }

    fn add(&self, a: &f64, b: &f64) -> f64 {
        a + b
    }

    fn zero(&self) -> f64 {
        0.0
    }

    fn to_f64(&self, v: &f64) -> f64 {
        *v
    }

    fn formatter(&self) -> &dyn ValueFormatter {
        &CpuFormatter
    }
}

/// Prints CPU nanoseconds as `ns`, `µs`, `ms` or `s` of CPU, and throughput per CPU
/// second.
struct CpuFormatter;

impl ValueFormatter for CpuFormatter {
    fn scale_values(&self, typical: f64, values: &mut [f64]) -> &'static str {
        let (div, unit) = if typical < 1e3 {
            (1.0, "ns cpu")
        } else if typical < 1e6 {
            (1e3, "µs cpu")
        } else if typical < 1e9 {
            (1e6, "ms cpu")
        } else {
            (1e9, "s cpu")
        };
        values.iter_mut().for_each(|v| *v /= div);
        unit
    }

    fn scale_throughputs(&self, _typical: f64, t: &Throughput, values: &mut [f64]) -> &'static str {
        let (n, unit) = match t {
            Throughput::Bytes(n) | Throughput::BytesDecimal(n) => (*n as f64 / 1e9, "GB/cpu s"),
            Throughput::Elements(n) => (*n as f64 / 1e9, "Gelem/cpu s"),
            Throughput::Bits(n) => (*n as f64 / 1e9, "Gbit/cpu s"),
        };
        values.iter_mut().for_each(|v| *v = n / (*v * 1e-9));
        unit
    }

    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}
