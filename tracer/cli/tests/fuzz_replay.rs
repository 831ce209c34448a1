//! Replays the command line's fuzzing corpus (`tracer/fuzz/corpus/cli/`) and every input
//! the fuzzer found a fault with (`tracer/fuzz/regressions/cli/`) through
//! [`tracer_cli::fuzz::Sandbox::run`], as the AFL++ target feeds them: no input may
//! panic or hang.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use tracer_cli::fuzz::{Outcome, Sandbox};

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = match std::fs::read_dir(dir) {
        Ok(entries) => entries
            .map(|e| e.unwrap().path())
            .filter(|p| p.is_file() && p.file_name().is_some_and(|n| n != "README.md"))
            .collect(),
        Err(_) => Vec::new(),
    };
    out.sort();
    out
}

/// Longer than any input should take by far (a hang, not a speed check: the machine
/// may be loaded by the other tests).
const HANG: Duration = Duration::from_secs(20);

#[test]
fn cli_fuzz_corpus_replays_without_panic_or_hang() {
    let tracer = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let fuzz = tracer.join("fuzz");
    let dir = std::env::temp_dir().join(format!("tracer-cli-fuzz-replay-{}", std::process::id()));
    let sandbox = Sandbox::new(&dir, &tracer).unwrap();
    let inputs: Vec<PathBuf> = ["corpus", "regressions"]
        .iter()
        .flat_map(|kind| files(&fuzz.join(kind).join("cli")))
        .collect();
    assert!(
        inputs.len() >= 20,
        "the cli corpus is missing ({} inputs)",
        inputs.len()
    );
    for path in &inputs {
        let data = std::fs::read(path).unwrap();
        let start = Instant::now();
        let outcome = std::panic::catch_unwind(|| {
            sandbox.run(&data);
        });
        let elapsed = start.elapsed();
        assert!(outcome.is_ok(), "{}: panicked", path.display());
        assert!(elapsed < HANG, "{}: took {elapsed:?}", path.display());
    }
}

/// A run the fuzzer kills at its time limit (SIGKILL) leaves its temporary files; the
/// next input is not blamed for them. The first campaign of the `cli` target reported
/// `regressions/cli/merge-after-a-killed-run` as a crash ("files left behind") that did
/// not reproduce alone: a `tracer merge` that fails on its third tile, run after a killed
/// one.
#[test]
fn a_killed_run_s_files_are_not_blamed_on_the_next_input() {
    let tracer = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = std::env::temp_dir().join(format!("tracer-cli-fuzz-killed-{}", std::process::id()));
    let sandbox = Sandbox::new(&dir, &tracer).unwrap();
    let input = std::fs::read(tracer.join("fuzz/regressions/cli/merge-after-a-killed-run")).unwrap();
    for stray in [".meiqf.json.1.tmp", "sub/.out.png.1.tmp"] {
        std::fs::write(sandbox.dir().join(stray), b"killed").unwrap();
        assert!(matches!(sandbox.run(&input), Outcome::Checked(Err(_))));
        assert!(!sandbox.dir().join(stray).exists());
    }
}

/// The sandbox gives the commands what they need: seeds of the corpus pass every check,
/// or fail on the check they were written for, and a `tracer merge` writes.
#[test]
fn cli_fuzz_seeds_reach_the_checks() {
    let tracer = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = std::env::temp_dir().join(format!("tracer-cli-fuzz-seeds-{}", std::process::id()));
    let sandbox = Sandbox::new(&dir, &tracer).unwrap();
    let seed = |name: &str| {
        let data = std::fs::read(tracer.join("fuzz/corpus/cli").join(name)).unwrap();
        sandbox.run(&data)
    };
    for ok in ["render-png", "render-obj", "render-gz", "render-script", "render-tile", "bench", "accuracy"] {
        assert_eq!(seed(ok), Outcome::Checked(Ok(())), "{ok}");
    }
    assert_eq!(seed("merge"), Outcome::Wrote);
    assert_eq!(seed("merge-missing"), Outcome::Checked(Ok(())));
    let failed = |name: &str, text: &str| match seed(name) {
        Outcome::Checked(Err(e)) => assert!(e.contains(text), "{name}: {e}"),
        other => panic!("{name}: {other:?}"),
    };
    failed("render-missing", "missing.nff");
    failed("render-camera", "`from` equals its `at`");
    failed("render-sched-bad", "--tile-size 8 has no effect");
    failed("merge-foreign", "is not a tile of the render");
    failed("accuracy-same", "two scenes named");
    assert!(matches!(seed("render-eq"), Outcome::Refused(_)));
    assert!(matches!(sandbox.run(b"render\n/etc/passwd\n-o\nx.png"), Outcome::Outside));
}
