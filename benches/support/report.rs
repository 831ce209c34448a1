//! Turns criterion result directories (one per target) into the tables and the plot of
//! `benches/RESULTS.md`.
//!
//! ```text
//! cargo run -p benches --release --example report -- \
//!     --out benches/results x86-64=DIR x86-64-v3=DIR[,DIR...] x86-64-v4=DIR
//! ```
//! writes `tables.md` (today's answer in one table, the performance targets evaluated,
//! long-vector bandwidth, per-kernel medians and ratios) and `speedup.svg` into the
//! `--out` directory. Several directories for one target are rounds of the same suite:
//! each benchmark's median is then the median of the rounds' medians.

use benches::results::{answer, load, long_table, merge_rounds, speedup_svg, tables, targets, Run};
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
        let Some((target, dirs)) = a.split_once('=') else {
            eprintln!("usage: report [--out DIR] TARGET=CRITERION_DIR[,DIR...]...");
            std::process::exit(2);
        };
        let rounds: Vec<_> = dirs
            .split(',')
            .map(|dir| {
                load(std::path::Path::new(dir)).unwrap_or_else(|e| {
                    eprintln!("{e}");
                    std::process::exit(1);
                })
            })
            .collect();
        let data = merge_rounds(&rounds);
        eprintln!(
            "{target}: {} benchmarks from {} round(s) in {dirs}",
            data.len(),
            rounds.len()
        );
        runs.push(Run {
            target: target.to_string(),
            data,
        });
    }
    if runs.is_empty() {
        eprintln!("usage: report [--out DIR] TARGET=CRITERION_DIR[,DIR...]...");
        std::process::exit(2);
    }
    std::fs::create_dir_all(&out).expect("create the output directory");
    let md = format!(
        "### Today's answer\n\n{}\n### Performance targets\n\n{}\n### Long vectors and bandwidth\n\n{}\n### All medians (ratio to vecexpr in parentheses)\n{}",
        answer(&runs),
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
