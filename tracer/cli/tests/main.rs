//! The command line's integration tests, one module per file of this directory, built as
//! one test binary (as the library's, `tracer/tests/main.rs`). Run one file's tests with
//! its module name as the filter, for example `cargo test -p tracer-cli --test cli accuracy::`.

/// Declares each file of `tests/` as a module and records the names for
/// [`every_file_is_a_module`].
macro_rules! suites {
    ($($m:ident),* $(,)?) => {
        $(mod $m;)*
        const SUITES: &[&str] = &[$(stringify!($m)),*];
    };
}

suites!(
    accuracy,
    cli,
    cli_invariance,
    fuzz_replay,
    render_checks,
    scene_input,
    tiles,
    viewer
);

/// Cargo does not discover test files here on its own (`autotests = false`): a new
/// file must be added to the list above, or its tests would silently never run.
#[test]
fn every_file_is_a_module() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if let Some(stem) = name.strip_suffix(".rs") {
            if stem != "main" && !SUITES.contains(&stem) {
                missing.push(name);
            }
        }
    }
    assert!(
        missing.is_empty(),
        "tests/main.rs does not declare {missing:?}"
    );
}
