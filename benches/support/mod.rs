//! Shared support code for the benchmarks.
