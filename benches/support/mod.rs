//! Shared support code for the benchmarks: fixed-seed input data, the eager vector
//! types every operator of which materialises a temporary, the hand-written loops
//! (the ceiling), the benchmark configuration, and the reading of criterion's results
//! for `RESULTS.md` and the plot, the cycle counter and process CPU time as criterion measurements,
//! and the sphere test of the Embree bench's user geometry.

pub mod config;
pub mod cpu;
pub mod cycles;
pub mod data;
pub mod eager;
pub mod hand;
pub mod results;
pub mod run;
pub mod user_spheres;
