//! A cycle-accurate timer: the time-stamp counter read with serialisation, calibrated to
//! seconds.
//!
//! The method is G. Paoloni, "How to Benchmark Code Execution Times on Intel IA-32 and
//! IA-64 Instruction Set Architectures", Intel white paper 324264-001, September 2010:
//! a barrier keeps earlier instructions from drifting past the first read
//! ([`start`]), and `rdtscp`, which waits for all earlier instructions to retire,
//! followed by a barrier that keeps later instructions from starting early, closes the
//! interval ([`stop`]). Paoloni uses `cpuid` as the barrier; here it is `lfence`, which
//! the Intel SDM (vol. 2B, RDTSC) names for the same purpose. Inside a virtual machine,
//! like the one this project is measured on, `cpuid` traps to the hypervisor (a
//! microsecond or more per call, with a variable cost), while `lfence` stays a few
//! cycles.
//!
//! The counter counts at a constant rate only with an *invariant* TSC (CPUID leaf
//! `0x8000_0007`, EDX bit 8): its ticks are then reference cycles at the nominal
//! frequency, not core clock cycles, but steady across frequency changes and idle
//! states. Without one, or off x86-64, every function here falls back to nanoseconds of
//! [`Instant`] since a process-wide origin, and [`Clock::source`] says so.
//!
//! [`clock`] calibrates ticks against [`Instant`] once per process (about 10 ms of
//! sleeping), so converting to seconds costs nothing after the first call.

use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// Where the ticks come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// The invariant time-stamp counter (`rdtsc` / `rdtscp`).
    Tsc,
    /// Nanoseconds of [`Instant`] (no invariant TSC, or not x86-64).
    Instant,
}

impl Source {
    /// `"tsc"` or `"instant"`.
    pub fn name(self) -> &'static str {
        match self {
            Source::Tsc => "tsc",
            Source::Instant => "instant",
        }
    }
}

/// Does this processor have an invariant TSC?
pub fn has_invariant_tsc() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::__cpuid;
        // Leaf 0x8000_0000 gives the highest extended leaf; 0x8000_0007 is only asked
        // for when it exists.
        if __cpuid(0x8000_0000).eax < 0x8000_0007 {
            return false;
        }
        let edx = __cpuid(0x8000_0007).edx;
        edx & (1 << 8) != 0
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

fn source() -> Source {
    static SOURCE: OnceLock<Source> = OnceLock::new();
    *SOURCE.get_or_init(|| {
        if has_invariant_tsc() {
            Source::Tsc
        } else {
            Source::Instant
        }
    })
}

/// Nanoseconds since a process-wide origin: the fallback tick.
fn instant_ticks() -> u64 {
    static ORIGIN: OnceLock<Instant> = OnceLock::new();
    ORIGIN.get_or_init(Instant::now).elapsed().as_nanos() as u64
}

/// Opens an interval: the current tick, read after every earlier instruction has
/// completed and before any later one starts (`lfence; rdtsc; lfence`).
#[inline(always)]
pub fn start() -> u64 {
    #[cfg(target_arch = "x86_64")]
    if source() == Source::Tsc {
        use core::arch::x86_64::{_mm_lfence, _rdtsc};
        // SAFETY: `lfence` (SSE2, part of x86-64) and `rdtsc` are available on every
        // x86-64 processor and only order instructions / read a counter.
        return unsafe {
            _mm_lfence();
            let t = _rdtsc();
            _mm_lfence();
            t
        };
    }
    instant_ticks()
}

/// Closes an interval: the current tick, read after every earlier instruction has
/// retired and before any later one starts (`rdtscp; lfence`).
#[inline(always)]
pub fn stop() -> u64 {
    #[cfg(target_arch = "x86_64")]
    if source() == Source::Tsc {
        use core::arch::x86_64::{__rdtscp, _mm_lfence};
        let mut aux = 0u32;
        // SAFETY: an invariant TSC implies `rdtscp` (every such processor has it); `aux`
        // is a valid place for the processor id it writes; `lfence` only orders.
        return unsafe {
            let t = __rdtscp(&mut aux);
            _mm_lfence();
            t
        };
    }
    instant_ticks()
}

/// The tick source and its rate.
#[derive(Clone, Copy, Debug)]
pub struct Clock {
    source: Source,
    ticks_per_second: f64,
}

impl Clock {
    /// Measures the tick rate against [`Instant`] over `wait` (a sleep, so it costs no
    /// CPU time); the median of three such measurements.
    pub fn calibrate(wait: Duration) -> Self {
        let source = source();
        if source == Source::Instant {
            return Self {
                source,
                ticks_per_second: 1e9,
            };
        }
        let mut rates: Vec<f64> = (0..3)
            .map(|_| {
                let (i0, c0) = (Instant::now(), start());
                std::thread::sleep(wait);
                let (c1, i1) = (stop(), Instant::now());
                c1.wrapping_sub(c0) as f64 / (i1 - i0).as_secs_f64()
            })
            .collect();
        rates.sort_by(f64::total_cmp);
        Self {
            source,
            ticks_per_second: rates[1],
        }
    }

    /// Where the ticks come from.
    pub fn source(&self) -> Source {
        self.source
    }

    /// Ticks per second (10^9 for the [`Source::Instant`] fallback).
    pub fn ticks_per_second(&self) -> f64 {
        self.ticks_per_second
    }

    /// `ticks` in milliseconds.
    pub fn ms(&self, ticks: u64) -> f64 {
        ticks as f64 / self.ticks_per_second * 1e3
    }
}

/// The process-wide clock, calibrated on first use (3 x 3 ms).
pub fn clock() -> &'static Clock {
    static CLOCK: OnceLock<Clock> = OnceLock::new();
    CLOCK.get_or_init(|| Clock::calibrate(Duration::from_millis(3)))
}

/// Ticks elapsed since a [`start`] reading.
#[inline(always)]
pub fn since(start_ticks: u64) -> u64 {
    stop().wrapping_sub(start_ticks)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn monotonic() {
        let mut last = start();
        for _ in 0..10_000 {
            let a = start();
            let b = stop();
            assert!(a >= last && b >= a, "{last} {a} {b}");
            last = b;
        }
    }

    #[test]
    fn calibration_agrees_with_instant() {
        let c = Clock::calibrate(Duration::from_millis(2));
        match c.source() {
            // Any real counter runs between 100 MHz and 10 GHz.
            Source::Tsc => {
                assert!((1e8..1e10).contains(&c.ticks_per_second()), "{c:?}");
            }
            Source::Instant => assert_eq!(c.ticks_per_second(), 1e9),
        }
        // An interval measured both ways: loose bounds, the machine may be busy.
        let (i0, t0) = (Instant::now(), start());
        std::thread::sleep(Duration::from_millis(20));
        let (t1, i1) = (stop(), Instant::now());
        let tsc_ms = c.ms(t1 - t0);
        let inst_ms = (i1 - i0).as_secs_f64() * 1e3;
        assert!(
            tsc_ms > 0.5 * inst_ms && tsc_ms < 2.0 * inst_ms,
            "{tsc_ms} ms against {inst_ms} ms"
        );
    }

    #[test]
    fn source_matches_cpu() {
        assert_eq!(source() == Source::Tsc, has_invariant_tsc());
        assert_eq!(clock().source(), source());
    }
}
