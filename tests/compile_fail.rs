//! Type errors a user meets first, checked with their full messages: each file in
//! `compile_fail/` must fail to compile with exactly the `.stderr` next to it (the first
//! line says what is wrong and what to write instead).
//!
//! After a deliberate change of a message: `TRYBUILD=overwrite cargo test -p
//! integration-tests --test integration compile_fail::`, then review the new `.stderr` files.

#[test]
fn plain_word_errors() {
    let t = trybuild::TestCases::new();
    t.compile_fail("compile_fail/*.rs");
}
