//! The cross-crate integration tests, one module per file of this directory, built as
//! one test binary (each binary links the libraries and instantiates its expressions
//! anew). Run one file's tests with its module name as the filter, for example
//! `cargo test -p integration-tests --test integration vecexpr_edges::`.

/// Declares each test file as a module and records the names for
/// [`every_file_is_a_module`].
macro_rules! suites {
    ($($m:ident),* $(,)?) => {
        $(mod $m;)*
        const SUITES: &[&str] = &[$(stringify!($m)),*];
    };
}

/// The property-test runner and input strategies, shared by the property tests.
mod prop;

suites!(
    compile_fail,
    vecexpr_big,
    vecexpr_edges,
    vecexpr_layout,
    vecexpr_matrix,
    vecexpr_names,
    vecexpr_nan,
    vecexpr_props,
    vecexpr_scalar_left
);

/// Files of this directory that are not test modules: the library and the
/// property-test glue (`prop`, declared above).
const NOT_SUITES: &[&str] = &["main", "support", "prop"];

/// The test files are listed in `Cargo.toml` by hand: a new file must be added to the
/// list above, or its tests would silently never run.
#[test]
fn every_file_is_a_module() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if let Some(stem) = name.strip_suffix(".rs") {
            if !NOT_SUITES.contains(&stem) && !SUITES.contains(&stem) {
                missing.push(name);
            }
        }
    }
    assert!(missing.is_empty(), "main.rs does not declare {missing:?}");
}
