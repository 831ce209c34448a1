//! Regenerates the probes' assembly with the toolchain at hand and checks it.
//!
//! For every kernel and target in `bounds.txt` the test fails if the kernel contains a
//! call, a branch, a stack access, no packed SIMD instruction (unless `bounds.txt`
//! exempts it) or more instructions than its bound, or if its checked-in dump is
//! missing. Text that differs from the checked-in dump is only reported: compilers
//! change, and the properties above are what matter.
//!
//! `ASM_DUMPS_UPDATE=1` (what `asm-dumps/regen.sh` sets) rewrites the dumps instead of
//! comparing them; the rules are checked either way.
#![cfg(target_arch = "x86_64")]

use asm_dumps::asm::{diff_summary, extract, Analysis};
use asm_dumps::bounds::{self, Bound};
use asm_dumps::dump::{render, significant, toolchain_of};
use asm_dumps::generate::{self, Target};
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Emits the assembly of every target, one build per target, in parallel (each build
/// is mostly single-threaded: one codegen unit per crate).
fn emit_all(targets: &[&'static Target]) -> Vec<Result<String, String>> {
    let manifest = crate_dir().join("Cargo.toml");
    let build_dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("asm-dumps");
    std::thread::scope(|s| {
        let handles: Vec<_> = targets
            .iter()
            .map(|t| {
                let (manifest, build_dir) = (&manifest, &build_dir);
                s.spawn(move || generate::emit(manifest, build_dir, t))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("generation thread panicked"))
            .collect()
    })
}

#[test]
fn probes_meet_their_bounds() {
    let update = std::env::var_os("ASM_DUMPS_UPDATE").is_some_and(|v| v != "0");
    let bounds_path = crate_dir().join("bounds.txt");
    let text = std::fs::read_to_string(&bounds_path).expect("asm-dumps/bounds.txt");
    let bounds: Vec<Bound> = bounds::parse(&text).unwrap_or_else(|e| panic!("{e}"));
    let mut targets: Vec<&'static Target> = Vec::new();
    for b in &bounds {
        let t = generate::target(&b.target)
            .unwrap_or_else(|| panic!("bounds.txt: unknown target {}", b.target));
        if !targets.contains(&t) {
            targets.push(t);
        }
    }
    let toolchain = generate::toolchain().unwrap_or_else(|e| panic!("{e}"));
    let asm = emit_all(&targets);

    let dumps = crate_dir().join("dumps");
    let mut failures = Vec::new();
    let mut warnings = Vec::new();
    let mut table = String::new();
    let mut expected_files = BTreeSet::new();
    for b in &bounds {
        let ti = targets.iter().position(|t| t.name == b.target).unwrap();
        let target = targets[ti];
        let code = match &asm[ti] {
            Ok(code) => code,
            Err(e) if target.optional => {
                warnings.push(format!("{}: skipped, generation failed: {e}", target.name));
                continue;
            }
            Err(e) => {
                failures.push(e.clone());
                continue;
            }
        };
        let id = format!("{} on {}", b.kernel, b.target);
        let Some(f) = extract(code, &b.kernel) else {
            failures.push(format!("{id}: symbol not found in the emitted assembly"));
            continue;
        };
        let a = Analysis::of(&f.body);
        let violations = b.violations(&a);
        let status = if violations.is_empty() { "ok" } else { "FAIL" };
        writeln!(
            table,
            "  {:<30} {:<14} {:>4} / {:<4} {:>4} SIMD {:>3}-bit  {}",
            b.kernel, b.target, a.instructions, b.max_instructions, a.simd, a.widest, status
        )
        .unwrap();
        for v in violations {
            failures.push(format!("{id}: {v}"));
        }

        let rel = format!("{}/{}.s", b.target, b.kernel);
        expected_files.insert(rel.clone());
        let path = dumps.join(&rel);
        let fresh = render(&f, target, &toolchain, b);
        if update {
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, &fresh).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            continue;
        }
        match std::fs::read_to_string(&path) {
            Err(_) => failures.push(format!(
                "{id}: no checked-in dump dumps/{rel}; run asm-dumps/regen.sh"
            )),
            Ok(old) => {
                if let Some(d) = diff_summary(&significant(&old), &significant(&fresh), 6) {
                    warnings.push(format!(
                        "{id}: drifted from dumps/{rel} (recorded with {}, now {toolchain}): {d}",
                        toolchain_of(&old).unwrap_or("an unknown toolchain")
                    ));
                }
            }
        }
    }

    // Dumps that no bound covers any more are stale.
    for t in generate::TARGETS {
        let Ok(dir) = std::fs::read_dir(dumps.join(t.name)) else {
            continue;
        };
        for entry in dir.flatten() {
            let rel = format!("{}/{}", t.name, entry.file_name().to_string_lossy());
            if !expected_files.contains(&rel) {
                warnings.push(format!("dumps/{rel} has no entry in bounds.txt"));
            }
        }
    }

    // Written to stderr directly, not through the test harness's captured `println!`,
    // so the summary and any drift show in CI logs even when the test passes.
    let mut report = format!("asm-dumps check with {toolchain}\n");
    writeln!(
        report,
        "  {:<30} {:<14} {:>4} / {:<4} {:>9} {:>7}",
        "kernel", "target", "ins", "max", "", "widest"
    )
    .unwrap();
    report.push_str(&table);
    if update {
        writeln!(report, "dumps rewritten under {}", dumps.display()).unwrap();
    }
    for w in &warnings {
        writeln!(report, "warning: {w}").unwrap();
    }
    std::io::stderr().write_all(report.as_bytes()).unwrap();
    assert!(
        failures.is_empty(),
        "{} assembly check(s) failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
