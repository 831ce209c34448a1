//! The report: per scene a Markdown table with findings and a CSV table, for all scenes
//! a summary, and the files written.

use super::experiment::{Clock, Config, Knob, Row, SceneReport};
use crate::Precision;
use std::fmt::Write as _;
use std::path::Path;
use tracer::arith::HARDWARE_FMA;
use tracer::image::write_atomic;
use tracer::stats::median;

/// A number in short form: `0.1`, `0.01`, `1e-3`, `2.5e-4`, `12.5`.
pub(crate) fn short(x: f64) -> String {
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    if x.abs() >= 0.01 && x.abs() < 1e5 {
        trim(format!("{x:.4}"))
    } else {
        let e = x.abs().log10().floor();
        let m = x / 10f64.powf(e);
        format!("{}e{e}", trim(format!("{m:.2}")))
    }
}

/// A value with three significant digits.
pub(crate) fn sig3(x: f64) -> String {
    if !x.is_finite() {
        return if x > 0.0 {
            "inf".into()
        } else {
            format!("{x}")
        };
    }
    if x == 0.0 {
        return "0".into();
    }
    let e = x.abs().log10().floor() as i32;
    if (-3..5).contains(&e) {
        let decimals = (2 - e).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.2e}")
    }
}

impl SceneReport {
    fn row(&self, label: &str) -> Option<&Row> {
        self.rows.iter().find(|r| r.case.label == label)
    }

    fn clock_text(&self) -> &'static str {
        match self.clock {
            Clock::Cpu => "the process's CPU time (all threads) during the trace",
            Clock::Wall => "the wall-clock trace time",
        }
    }

    fn reference_ms(&self) -> f64 {
        self.rows[0].median_ms()
    }

    /// The table as CSV (one header line, one line per setting).
    pub fn to_csv(&self) -> String {
        let mut s = String::from(
            "scene,width,height,knob,setting,precision,depth,threshold,aa,rsqrt,int_pow,fma,\
             against,runs,clock,median_ms,min_ms,max_ms,median_wall_ms,time_vs_reference,rays,rmse,psnr_db,\
             max_abs,share_over_1_255,pareto\n",
        );
        let ref_ms = self.reference_ms();
        for r in &self.rows {
            let c = &r.case.config;
            let min = r.times_ms.iter().copied().fold(f64::INFINITY, f64::min);
            let max = r.times_ms.iter().copied().fold(0.0, f64::max);
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3},{:.3},{:.3},{:.3},{:.4},{},{:.6e},{},{:.6e},{:.6},{}",
                self.name,
                self.width,
                self.height,
                r.case.knob.name(),
                r.case.label,
                c.precision.name(),
                c.depth,
                c.threshold(),
                c.aa,
                c.arith.rsqrt,
                c.arith.int_pow,
                c.arith.fma,
                if r.case.fine { "fine" } else { "reference" },
                r.times_ms.len(),
                self.clock.name(),
                r.median_ms(),
                min,
                max,
                median(&r.wall_ms),
                r.median_ms() / ref_ms,
                r.rays,
                r.metrics.rmse,
                if r.metrics.psnr.is_finite() {
                    format!("{:.3}", r.metrics.psnr)
                } else {
                    "inf".into()
                },
                r.metrics.max_abs,
                r.metrics.over_1_255,
                r.pareto
            );
        }
        s
    }

    /// Plain-language findings drawn from the measured numbers.
    pub fn findings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let o = &self.options;
        let pct = |x: f64| format!("{}%", sig3(100.0 * x));
        // Threshold against depth 5.
        if let Some(d5) = self.row("depth 5") {
            let matching: Vec<&Row> = self
                .rows
                .iter()
                .filter(|r| r.case.knob == Knob::Threshold && r.metrics.rmse <= d5.metrics.rmse)
                .collect();
            let best = matching.iter().max_by(|a, b| {
                a.case
                    .config
                    .threshold()
                    .total_cmp(&b.case.config.threshold())
            });
            let mut line = match best {
                Some(t) => format!(
                    "Threshold vs depth 5: the largest threshold at least as accurate as depth 5 \
                     (RMSE {}) is {} (RMSE {}), at {}x the time of depth 5.",
                    sig3(d5.metrics.rmse),
                    short(t.case.config.threshold()),
                    sig3(t.metrics.rmse),
                    sig3(t.median_ms() / d5.median_ms())
                ),
                None => format!(
                    "Threshold vs depth 5: no threshold measured is as accurate as depth 5 \
                     (RMSE {}).",
                    sig3(d5.metrics.rmse)
                ),
            };
            // The next larger threshold: cheaper, less accurate than depth 5.
            let limit = best.map_or(f64::NEG_INFINITY, |b| b.case.config.threshold());
            let coarser = self
                .rows
                .iter()
                .filter(|r| r.case.knob == Knob::Threshold && r.case.config.threshold() > limit)
                .min_by(|a, b| {
                    a.case
                        .config
                        .threshold()
                        .total_cmp(&b.case.config.threshold())
                });
            if let Some(c) = coarser {
                let _ = write!(
                    line,
                    " The next larger, {}, has RMSE {} at {}x the time of depth 5.",
                    short(c.case.config.threshold()),
                    sig3(c.metrics.rmse),
                    sig3(c.median_ms() / d5.median_ms())
                );
            }
            out.push(line);
        }
        if let Some(f32row) = self.row("f32") {
            out.push(format!(
                "Precision: f64 takes {}x the time of f32; f32 differs from the f64 reference \
                 by RMSE {}, at most {}, in {} of the pixels by more than 1/255.",
                sig3(self.reference_ms() / f32row.median_ms()),
                sig3(f32row.metrics.rmse),
                sig3(f32row.metrics.max_abs),
                pct(f32row.metrics.over_1_255)
            ));
        }
        let aa: Vec<&Row> = self
            .rows
            .iter()
            .filter(|r| r.case.knob == Knob::Antialiasing)
            .collect();
        if let Some(a1) = aa.iter().find(|r| r.case.config.aa == 1) {
            let parts: Vec<String> = aa
                .iter()
                .map(|r| {
                    format!(
                        "{0}x{0}: {1}x the time of 1x1, RMSE {2}, {3} of pixels off by more than 1/255",
                        r.case.config.aa,
                        sig3(r.median_ms() / a1.median_ms()),
                        sig3(r.metrics.rmse),
                        pct(r.metrics.over_1_255)
                    )
                })
                .collect();
            out.push(format!(
                "Antialiasing (against {0}x{0}): {1}.",
                o.fine_aa,
                parts.join("; ")
            ));
        }
        for p in [Precision::F32, Precision::F64] {
            let exact = self.rows.iter().find(|r| {
                r.case.config
                    == Config {
                        precision: p,
                        ..o.reference()
                    }
            });
            let Some(exact) = exact else { continue };
            let parts: Vec<String> = self
                .rows
                .iter()
                .filter(|r| r.case.knob == Knob::Arithmetic && r.case.config.precision == p)
                .map(|r| {
                    format!(
                        "{}: {}x the time, RMSE {} (exact {}: {}), {} of pixels off by more than 1/255",
                        r.case.config.arith.label(),
                        sig3(r.median_ms() / exact.median_ms()),
                        sig3(r.metrics.rmse),
                        p.name(),
                        sig3(exact.metrics.rmse),
                        pct(r.metrics.over_1_255)
                    )
                })
                .collect();
            if !parts.is_empty() {
                out.push(format!(
                    "Approximations in {} (time against exact {}): {}.",
                    p.name(),
                    p.name(),
                    parts.join("; ")
                ));
            }
        }
        out
    }

    /// The table and findings as Markdown.
    pub fn to_markdown(&self) -> String {
        let o = &self.options;
        let mut s = String::new();
        let _ = writeln!(s, "# Accuracy against time: {}\n", self.name);
        let _ = writeln!(
            s,
            "Scene `{}`, {}x{} pixels, {} timed runs per setting (interleaved), threads: {}. \
             Times are medians of {}. Reference: f64, depth {}, {}x{} rays per pixel, \
             exact arithmetic ({} ms). Antialiasing rows are compared with a {}x{} render \
             instead ({} ms, one run). Every other row changes one knob of the reference. \
             Hardware FMA in this build: {}.\n",
            self.path,
            self.width,
            self.height,
            o.runs,
            o.threads
                .map_or_else(|| "all cores".to_string(), |t| t.to_string()),
            self.clock_text(),
            o.ref_depth,
            o.ref_aa,
            o.ref_aa,
            sig3(self.reference_ms()),
            o.fine_aa,
            o.fine_aa,
            sig3(self.fine_ms),
            if HARDWARE_FMA {
                "yes"
            } else {
                "no (mul_add is a library call)"
            }
        );
        let _ = writeln!(s, "## Findings\n");
        for f in self.findings() {
            let _ = writeln!(s, "- {f}");
        }
        let _ = writeln!(
            s,
            "\n## Table\n\n`ms`: median {} time; `wall ms`: median wall-clock trace time; \
             `time`: `ms` relative to the reference; \
             `>1/255` the share of pixels with a channel off by more than one 8-bit step; \
             `spread`: (slowest - fastest run) / median; \
             `front`: on the Pareto front of RMSE against time (antialiasing rows among \
             themselves).\n",
            self.clock.name()
        );
        let _ = writeln!(
            s,
            "| knob | setting | ms | spread | wall ms | time | rays | RMSE | PSNR dB | max abs | >1/255 | front |"
        );
        let _ = writeln!(
            s,
            "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|:---:|"
        );
        let ref_ms = self.reference_ms();
        for r in &self.rows {
            let m = &r.metrics;
            let lo = r.times_ms.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = r.times_ms.iter().copied().fold(0.0, f64::max);
            let _ = writeln!(
                s,
                "| {} | {} | {} | {}% | {} | {} | {} | {} | {} | {} | {}% | {} |",
                r.case.knob.name(),
                r.case.label,
                sig3(r.median_ms()),
                sig3(100.0 * (hi - lo) / r.median_ms()),
                sig3(median(&r.wall_ms)),
                sig3(r.median_ms() / ref_ms),
                r.rays,
                sig3(m.rmse),
                sig3(m.psnr),
                sig3(m.max_abs),
                sig3(100.0 * m.over_1_255),
                if r.pareto { "●" } else { "" }
            );
        }
        s
    }
}

/// Summary across scenes as (Markdown, CSV).
pub fn summary(reports: &[SceneReport]) -> (String, String) {
    let mut md = String::from(
        "# Accuracy against time: summary\n\n\
         Times are medians (of the clock each scene's table names) relative to the named \
         baseline; errors are RMSE \
         against the reference (antialiasing: against the fine reference).\n\n\
         | scene | image | reference ms | f64 / f32 time | f32 RMSE | f32 >1/255 | depth 5 RMSE | \
         threshold ≈ depth 5 (time vs depth 5) | aa 1 : 2 : 3 : 4 time | aa 1 → 4 RMSE | \
         f32 rsqrt / int-pow / fma time |\n\
         |---|---|---:|---:|---:|---:|---:|---|---|---|---|\n",
    );
    let mut csv = String::from(
        "scene,width,height,reference_ms,f64_over_f32_time,f32_rmse,f32_share_over_1_255,\
         depth5_rmse,threshold_matching_depth5,threshold_time_vs_depth5,aa_time_vs_aa1,\
         aa_rmse,f32_rsqrt_time,f32_int_pow_time,f32_fma_time\n",
    );
    for r in reports {
        let ref_ms = r.reference_ms();
        let f32row = r.row("f32");
        let f64_over_f32 = f32row.map(|x| ref_ms / x.median_ms());
        let d5 = r.row("depth 5");
        let thr = d5.and_then(|d5| {
            r.rows
                .iter()
                .filter(|x| x.case.knob == Knob::Threshold && x.metrics.rmse <= d5.metrics.rmse)
                .max_by(|a, b| {
                    a.case
                        .config
                        .threshold()
                        .total_cmp(&b.case.config.threshold())
                })
                .map(|t| (t.case.config.threshold(), t.median_ms() / d5.median_ms()))
        });
        let aa: Vec<&Row> = r
            .rows
            .iter()
            .filter(|x| x.case.knob == Knob::Antialiasing && x.case.config.aa <= r.options.max_aa)
            .collect();
        let aa1 = aa.first().map_or(1.0, |x| x.median_ms());
        let aa_time: Vec<String> = aa.iter().map(|x| sig3(x.median_ms() / aa1)).collect();
        let aa_err: Vec<String> = aa.iter().map(|x| sig3(x.metrics.rmse)).collect();
        let f32_exact = f32row.map_or(f64::NAN, |x| x.median_ms());
        let ar = |label: &str| r.row(label).map_or(f64::NAN, |x| x.median_ms() / f32_exact);
        let approx = [ar("f32 rsqrt"), ar("f32 int-pow"), ar("f32 fma")];
        let opt = |x: Option<f64>| x.map_or("-".to_string(), sig3);
        let _ = writeln!(
            md,
            "| {} | {}x{} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.name,
            r.width,
            r.height,
            sig3(ref_ms),
            opt(f64_over_f32),
            opt(f32row.map(|x| x.metrics.rmse)),
            f32row.map_or("-".into(), |x| format!(
                "{}%",
                sig3(100.0 * x.metrics.over_1_255)
            )),
            opt(d5.map(|x| x.metrics.rmse)),
            thr.map_or("none".into(), |(t, q)| format!(
                "{} ({}x)",
                short(t),
                sig3(q)
            )),
            aa_time.join(" : "),
            aa_err.join(" → "),
            approx.map(sig3).join(" / ")
        );
        let _ = writeln!(
            csv,
            "{},{},{},{:.3},{},{},{},{},{},{},{},{},{},{},{}",
            r.name,
            r.width,
            r.height,
            ref_ms,
            opt(f64_over_f32),
            f32row.map_or(String::new(), |x| format!("{:.6e}", x.metrics.rmse)),
            f32row.map_or(String::new(), |x| format!("{:.6}", x.metrics.over_1_255)),
            d5.map_or(String::new(), |x| format!("{:.6e}", x.metrics.rmse)),
            thr.map_or(String::new(), |(t, _)| t.to_string()),
            thr.map_or(String::new(), |(_, q)| format!("{q:.4}")),
            aa_time.join(";"),
            aa_err.join(";"),
            sig3(approx[0]),
            sig3(approx[1]),
            sig3(approx[2])
        );
    }
    (md, csv)
}

/// The scene's name for file names: the file name without `.gz`, `.nff` or `.obj`.
pub fn scene_name(path: &Path) -> String {
    let mut n = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    for ext in [".gz", ".nff", ".obj"] {
        if n.to_ascii_lowercase().ends_with(ext) && n.len() > ext.len() {
            n.truncate(n.len() - ext.len());
        }
    }
    n
}

fn write_text(path: &Path, text: &str) -> Result<(), String> {
    write_atomic(path, |w| std::io::Write::write_all(w, text.as_bytes()))
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// Writes `<name>.md`, `<name>.csv`, `<name>.svg` and `<name>-reference.png` into `dir`
/// for every report, and `summary.md` and `summary.csv`. Each file is written to a
/// temporary file and renamed.
pub fn write_report(dir: &Path, reports: &[SceneReport]) -> Result<(), String> {
    for r in reports {
        let file = |ext: &str| dir.join(format!("{}.{ext}", r.name));
        write_text(&file("md"), &r.to_markdown())?;
        write_text(&file("csv"), &r.to_csv())?;
        write_text(&file("svg"), &r.to_svg())?;
        let png = dir.join(format!("{}-reference.png", r.name));
        r.reference
            .save(&png)
            .map_err(|e| format!("{}: cannot write image: {e}", png.display()))?;
    }
    let (md, csv) = summary(reports);
    write_text(&dir.join("summary.md"), &md)?;
    write_text(&dir.join("summary.csv"), &csv)
}
