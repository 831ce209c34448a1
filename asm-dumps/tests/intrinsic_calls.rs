//! No `core::arch` intrinsic is called out of line anywhere in `vecexpr`, `tracer` or
//! `tracer-cli`.
//!
//! The packet kernels are entered through `#[target_feature]` functions
//! (`vecexpr::simd`), and everything they call must be inlined into them to be compiled
//! for that instruction set. A closure or helper left out of line is compiled for the
//! baseline, where an AVX2 intrinsic cannot be one instruction: it becomes a call to the
//! intrinsic's own function, one per vector operation. This happened twice to the
//! packet traversal (a closure per leaf made it three times slower; the shear of the
//! packet set-up called `_mm256_div_ps` and `_mm256_mul_ps`) and shows in no result,
//! only in time. The test builds the three libraries as the dumps are built (baseline
//! `x86-64`, release, one codegen unit, no LTO, `--emit asm`) and fails on any `call`
//! or `jmp` to a `core_arch` function. `tracer-cli` is in the list because the generic
//! render and packet code is compiled where its scalar type is chosen: the `f64`
//! renderers, for example, are instantiated by the command line, not by the library.
#![cfg(target_arch = "x86_64")]

use asm_dumps::asm::intrinsic_calls;
use asm_dumps::generate;
use std::path::{Path, PathBuf};

#[test]
fn no_intrinsic_is_called_out_of_line() {
    let crate_dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let manifest = crate_dir
        .parent()
        .expect("asm-dumps lies in the workspace")
        .join("Cargo.toml");
    let build_dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("asm-dumps");
    let target = generate::target("x86-64").expect("the baseline target");
    let mut found = Vec::new();
    for package in ["vecexpr", "tracer", "tracer-cli"] {
        let asm = generate::emit_package(&manifest, package, &build_dir, target)
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(
            asm.contains("\tret"),
            "{package}: the emitted assembly holds no function"
        );
        found.extend(
            intrinsic_calls(&asm)
                .into_iter()
                .map(|c| format!("{package}: {} calls {}", c.caller, c.callee)),
        );
    }
    assert!(
        found.is_empty(),
        "{} out-of-line intrinsic call(s):\n{}",
        found.len(),
        found.join("\n")
    );
}
