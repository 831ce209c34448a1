//! Turns criterion result directories (one per target) into the tables and the plot of
//! `benches/RESULTS.md`.
//!
//! ```text
//! cargo run -p benches --release --example report -- \
//!     --out benches/results x86-64=DIR x86-64-v3=DIR x86-64-v4=DIR
//! ```
//! writes `tables.md` (per-kernel medians and ratios, long-vector bandwidth, the
//! performance targets evaluated) and `speedup.svg` into the `--out` directory.

use benches::results::{load, long_table, speedup_svg, tables, targets, Run};
use std::path::PathBuf;

fn main() {
    let mut out = PathBuf::from("benches/results");
    let mut runs = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--out" {
            out = PathBuf::from(args.next().expect("--out needs a directory"));
            continue;
        }
        let Some((target, dir)) = a.split_once('=') else {
            eprintln!("usage: report [--out DIR] TARGET=CRITERION_DIR...");
            std::process::exit(2);
        };
        let data = load(std::path::Path::new(dir)).unwrap_or_else(|e| {
            eprintln!("{e}");
            std::process::exit(1);
        });
        eprintln!("{target}: {} measurements from {dir}", data.len());
        runs.push(Run {
            target: target.to_string(),
            data,
        });
    }
    if runs.is_empty() {
        eprintln!("usage: report [--out DIR] TARGET=CRITERION_DIR...");
        std::process::exit(2);
    }
    std::fs::create_dir_all(&out).expect("create the output directory");
    let md = format!(
        "### Performance targets\n\n{}\n### Long vectors and bandwidth\n\n{}\n### All medians (ratio to vecexpr in parentheses)\n{}",
        targets(&runs),
        long_table(&runs),
        tables(&runs)
    );
    std::fs::write(out.join("tables.md"), md).expect("write tables.md");
    std::fs::write(out.join("speedup.svg"), speedup_svg(&runs)).expect("write speedup.svg");
    eprintln!(
        "wrote {} and {}",
        out.join("tables.md").display(),
        out.join("speedup.svg").display()
    );
}
