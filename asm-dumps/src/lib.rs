//! Probe functions for assembly inspection, and the tools that check their assembly.
//!
//! Every probe in [`probes`] is `#[no_mangle]` and `#[inline(never)]`, takes its inputs
//! by reference and writes its result through a `&mut`, so the kernel survives
//! optimisation with a trivial ABI (pointers in `rdi`, `rsi`, `rdx`, ...) and its body is
//! exactly the kernel. The symbol is the function name (`reflect_f32x3`,
//! `reflect_glam_vec3a`, ...), so the body can be found in `--emit asm` output, or with
//! `cargo asm -p asm-dumps --lib reflect_f32x3`.
//!
//! [`asm`] parses emitted assembly and computes the properties the checked-in dumps
//! promise (instruction count, no call, no branch, no stack access, SIMD used);
//! [`bounds`] reads the checked-in per-kernel limits; [`generate`] runs the compiler;
//! [`dump`] writes and reads the checked-in dump files.
//! The integration test `tests/asm_check.rs` ties them together;
//! `tests/intrinsic_calls.rs` checks the whole `vecexpr`, `tracer` and `tracer-cli`
//! libraries for intrinsics called out of line ([`asm::intrinsic_calls`]).

pub mod asm;
pub mod bounds;
pub mod dump;
pub mod generate;
pub mod kernels;
pub mod probes;
