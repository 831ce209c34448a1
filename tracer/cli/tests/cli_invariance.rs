//! The command line's invariance promises, tested at the command line: for each flag the
//! README says leaves the image unchanged (`--threads`, `--scheduler`, `--tile-size`,
//! `--packets`, `--isa`, `--binary-bvh`, `--no-bvh`, `--effects`), in `f32` and `f64`,
//! the PFM file (linear 32-bit floats) is the same byte for byte as the default
//! render's. Bytes compare `-0.0` and `+0.0` as different and NaN as equal to itself, the
//! `to_bits` comparison "bit for bit" means.

use std::path::{Path, PathBuf};
use std::process::Command;

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name)
}

fn tmpdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracer-cli-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Renders `name` with `args` into a PFM and returns the file's bytes, or the exit code
/// and stderr on failure.
fn render(dir: &Path, name: &str, args: &[&str]) -> Result<Vec<u8>, (Option<i32>, String)> {
    let out = dir.join(format!("{name}-{}.pfm", args.join("_").replace('-', "")));
    let st = Command::new(env!("CARGO_BIN_EXE_tracer"))
        .arg("render")
        .arg(scene(name))
        .arg("-o")
        .arg(&out)
        .args(args)
        .output()
        .unwrap();
    if !st.status.success() {
        return Err((
            st.status.code(),
            String::from_utf8_lossy(&st.stderr).into_owned(),
        ));
    }
    let bytes = std::fs::read(&out).unwrap();
    std::fs::remove_file(&out).unwrap();
    Ok(bytes)
}

/// The instruction sets of `--isa` this CPU has, by the README's rule (`avx2` needs
/// AVX2 and FMA, `avx512` AVX-512F), checked here independently of the tracer.
fn isa_available(isa: &str) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        match isa {
            "sse2" => true,
            "avx2" => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
            }
            "avx512" => std::arch::is_x86_feature_detected!("avx512f"),
            _ => unreachable!(),
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = isa;
        false
    }
}

/// The flag sets whose image must equal the default's.
fn variants() -> Vec<Vec<&'static str>> {
    let mut v: Vec<Vec<&str>> = vec![
        vec!["--threads", "1"],
        vec!["--threads", "2"],
        vec!["--threads", "3"],
        vec!["--scheduler", "rayon", "--threads", "3"],
        vec!["--scheduler", "static", "--threads", "1"],
        vec!["--scheduler", "static", "--threads", "3"],
        vec!["--scheduler", "tiles", "--tile-size", "1", "--threads", "2"],
        vec!["--scheduler", "tiles", "--tile-size", "7", "--threads", "3"],
        vec!["--scheduler", "tiles", "--tile-size", "64"],
        vec!["--packets", "off"],
        vec!["--packets", "on"],
        vec!["--binary-bvh"],
        vec!["--no-bvh"],
        vec!["--effects", "all"],
        vec!["--effects", "auto"],
        vec!["--effects", "all", "--packets", "off", "--binary-bvh"],
    ];
    for isa in ["sse2", "avx2", "avx512"] {
        if isa_available(isa) {
            v.push(vec!["--isa", isa]);
            v.push(vec!["--isa", isa, "--scheduler", "tiles", "--tile-size", "5"]);
        }
    }
    v
}

/// Every variant gives the default's bytes, for a mirror scene, a glass scene and the
/// showcase (every primitive kind), in both precisions, with one ray per pixel centre
/// and with 2 x 2 supersampling (both traced in packets in f32); packets asked for by
/// name where single rays are traced (f64) are refused.
#[test]
fn every_invariance_flag_keeps_the_pfm_bytes() {
    let dir = tmpdir("invariance");
    let mut checked = 0;
    for name in ["balls-s1.nff", "mount-s1.nff", "showcase.nff"] {
        for precision in ["f32", "f64"] {
            for aa in ["1", "2"] {
                let base = [
                    "--width",
                    "29",
                    "--height",
                    "21",
                    "--precision",
                    precision,
                    "--aa",
                    aa,
                ];
                let reference = render(&dir, name, &base).unwrap();
                // Header, then width * height * 3 floats.
                let header = b"PF\n29 21\n-1.0\n";
                assert!(reference.starts_with(header));
                assert_eq!(reference.len(), header.len() + 29 * 21 * 12);
                for extra in variants() {
                    let args: Vec<&str> = base.iter().copied().chain(extra.clone()).collect();
                    // Packets asked for by name where none are traced (f64) would be
                    // ignored: refused instead.
                    let named = extra.contains(&"--isa") || extra.windows(2).any(|w| w == ["--packets", "on"]);
                    if named && precision == "f64" {
                        let (code, err) = render(&dir, name, &args).unwrap_err();
                        assert_eq!(code, Some(2), "{name} {args:?}: {err}");
                        assert!(err.contains("has no effect"), "{name} {args:?}: {err}");
                        checked += 1;
                        continue;
                    }
                    let got = render(&dir, name, &args)
                        .unwrap_or_else(|e| panic!("{name} {args:?}: {e:?}"));
                    assert!(
                        got == reference,
                        "{name} {args:?}: the PFM differs from the default render"
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked >= 3 * 2 * 2 * 16, "{checked}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// An `--isa` the CPU lacks is refused with status 2 and a one-line message, and
/// writes nothing.
#[test]
fn a_missing_isa_is_refused() {
    let dir = tmpdir("missing-isa");
    for isa in ["sse2", "avx2", "avx512"] {
        if isa_available(isa) {
            continue;
        }
        let args = ["--width", "8", "--height", "8", "--isa", isa];
        let (code, err) = render(&dir, "balls-s1.nff", &args).unwrap_err();
        assert_eq!(code, Some(2), "{isa}: {err}");
        assert_eq!(err.lines().count(), 1, "{isa}: {err}");
        assert!(err.contains("does not support"), "{isa}: {err}");
    }
    let leftovers = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(leftovers, 0);
    let _ = std::fs::remove_dir_all(&dir);
}
