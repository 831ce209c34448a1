//! Emitting the probes' assembly with the toolchain at hand.
//!
//! The whole dependency graph is built with `-C target-cpu=<cpu>` (glam selects code
//! paths with `cfg(target_feature)`, so only a full build shows what a user with that
//! `RUSTFLAGS` gets), in a target directory of its own per CPU, and the `asm-dumps`
//! library is additionally asked for `--emit asm` in Intel syntax. The profile is pinned
//! on the command line, so the dumps do not depend on the workspace's release profile:
//! `opt-level=3`, one codegen unit, no LTO, no debug info.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A code-generation target of the dumps: a name (the directory under `dumps/`) and
/// the `RUSTFLAGS` the whole build gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Target {
    /// Name used in `bounds.txt` and as the dump directory.
    pub name: &'static str,
    /// `RUSTFLAGS` for every crate of the build.
    pub rustflags: &'static str,
    /// If the toolchain rejects these flags, skip the target with a warning instead of
    /// failing (for flags that rely on an unstable pass-through).
    pub optional: bool,
    /// One line for the dump headers.
    pub note: &'static str,
}

/// Every target the dumps are made for.
pub const TARGETS: [Target; 4] = [
    Target {
        name: "x86-64",
        rustflags: "-C target-cpu=x86-64",
        optional: false,
        note: "baseline x86-64: SSE2, no FMA",
    },
    Target {
        name: "x86-64-v3",
        rustflags: "-C target-cpu=x86-64-v3",
        optional: false,
        note: "AVX2 + FMA (Haswell and later)",
    },
    Target {
        name: "x86-64-v4",
        rustflags: "-C target-cpu=x86-64-v4",
        optional: false,
        note: "AVX-512; LLVM still prefers 256-bit vectors when it vectorises",
    },
    Target {
        name: "x86-64-v4-zmm",
        rustflags: "-C target-cpu=x86-64-v4 -C target-feature=-prefer-256-bit",
        optional: true,
        note: "AVX-512 with LLVM's 256-bit preference turned off (an unstable pass-through flag)",
    },
];

/// The target called `name`.
pub fn target(name: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.name == name)
}

/// Profile settings passed as `--config` so the workspace profile cannot change them.
/// `lto=false` matters most: with the workspace's `lto = "thin"`, rustc emits the ThinLTO
/// pre-link code for a library, in which nothing is unrolled or vectorised yet.
pub const PROFILE: [&str; 5] = [
    "profile.release.opt-level=3",
    "profile.release.codegen-units=1",
    "profile.release.lto=false",
    "profile.release.debug=false",
    "profile.release.incremental=false",
];

/// Arguments after `--`, passed to rustc for the `asm-dumps` crate only.
pub const RUSTC_ARGS: [&str; 2] = ["-C", "llvm-args=-x86-asm-syntax=intel"];

/// Environment variables that would otherwise leak the caller's build settings into
/// the generation (`CARGO_ENCODED_RUSTFLAGS` beats `RUSTFLAGS`, for example).
const CLEARED_ENV: [&str; 7] = [
    "CARGO_ENCODED_RUSTFLAGS",
    "CARGO_BUILD_RUSTFLAGS",
    "CARGO_BUILD_TARGET",
    "CARGO_BUILD_TARGET_DIR",
    "CARGO_INCREMENTAL",
    "CARGO_MAKEFLAGS",
    "RUSTC_WORKSPACE_WRAPPER",
];

/// The cargo to run: the one running us if any (`$CARGO`), else `cargo` on the path.
pub fn cargo() -> String {
    std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string())
}

/// `rustc -vV`'s `release`, `commit-hash` and `LLVM version` lines, condensed into one
/// line such as `rustc 1.95.0 (59807616e), LLVM 22.1.2`.
///
/// # Errors
/// If rustc cannot be run.
pub fn toolchain() -> Result<String, String> {
    let text = rustc_version()?;
    let field = |k: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(k))
            .map(|v| v.trim().to_string())
            .unwrap_or_else(|| "?".to_string())
    };
    let commit = field("commit-hash:");
    Ok(format!(
        "rustc {} ({}), LLVM {}",
        field("release:"),
        &commit[..commit.len().min(9)],
        field("LLVM version:")
    ))
}

/// The output of `rustc -vV` (`$RUSTC` if set), run once per process.
fn rustc_version() -> Result<String, String> {
    static TEXT: std::sync::OnceLock<Result<String, String>> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| {
        let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".to_string());
        let out = Command::new(&rustc)
            .arg("-vV")
            .output()
            .map_err(|e| format!("cannot run {rustc}: {e}"))?;
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    })
    .clone()
}

/// The host's target triple (`rustc -vV`'s `host` line).
///
/// The build passes it as `--target`, so that `RUSTFLAGS` reach the crates compiled for
/// the target only and not the build scripts and proc macros, which run on this machine:
/// built for `x86-64-v4` they would stop with an illegal instruction on a CPU without
/// AVX-512.
///
/// # Errors
/// If rustc cannot be run or prints no host.
pub fn host() -> Result<String, String> {
    rustc_version()?
        .lines()
        .find_map(|l| l.strip_prefix("host:"))
        .map(|h| h.trim().to_string())
        .ok_or_else(|| "rustc -vV printed no host".to_string())
}

/// The command line that [`emit`] runs, as it appears in the dump headers.
pub fn command_line(target: &Target) -> String {
    let config: String = PROFILE.iter().map(|c| format!(" --config {c}")).collect();
    format!(
        "RUSTFLAGS=\"{}\" cargo rustc --release --target HOST -p asm-dumps --lib{config} -- --emit asm {}",
        target.rustflags,
        RUSTC_ARGS.join(" ")
    )
}

/// Builds the `asm-dumps` library for `target` under `target_dir/<name>` and returns the
/// emitted assembly.
///
/// `manifest` is `asm-dumps/Cargo.toml`. Repeated calls reuse the build directory, so
/// only the first one per CPU compiles the dependencies.
///
/// # Errors
/// If cargo cannot be started or the build fails (its stderr is returned).
pub fn emit(manifest: &Path, target_dir: &Path, target: &Target) -> Result<String, String> {
    emit_package(manifest, "asm-dumps", target_dir, target)
}

/// As [`emit`], for the library of any package of the workspace that `manifest`
/// belongs to (for example `tracer`, whose whole code is checked for out-of-line
/// intrinsics); the same build directory per target serves every package.
///
/// # Errors
/// If cargo cannot be started or the build fails (its stderr is returned).
pub fn emit_package(
    manifest: &Path,
    package: &str,
    target_dir: &Path,
    target: &Target,
) -> Result<String, String> {
    let dir = target_dir.join(target.name);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let asm_path: PathBuf = dir.join(format!("{}.s", package.replace('-', "_")));
    let mut cmd = Command::new(cargo());
    cmd.arg("rustc")
        .arg("--release")
        .arg("--lib")
        .arg("--quiet")
        .arg("--target")
        .arg(host()?)
        .arg("--manifest-path")
        .arg(manifest)
        .arg("-p")
        .arg(package);
    for c in PROFILE {
        cmd.arg("--config").arg(c);
    }
    cmd.arg("--")
        .arg(format!("--emit=asm={}", asm_path.display()))
        .args(RUSTC_ARGS);
    for k in CLEARED_ENV {
        cmd.env_remove(k);
    }
    cmd.env("RUSTFLAGS", target.rustflags)
        .env("CARGO_TARGET_DIR", &dir);
    let out = cmd
        .output()
        .map_err(|e| format!("cannot run {}: {e}", cargo()))?;
    if !out.status.success() {
        return Err(format!(
            "assembly generation of {package} for {} failed ({}):\n{}",
            target.name,
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    std::fs::read_to_string(&asm_path).map_err(|e| format!("{}: {e}", asm_path.display()))
}
