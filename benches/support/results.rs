//! Reading criterion's results back (`<criterion dir>/<group>/<impl>/<size>/new/*.json`)
//! and turning the medians of one or more runs (one per target) into the Markdown
//! tables and the SVG plot of `RESULTS.md`.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;

/// One benchmark's median.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// The criterion group: the kernel.
    pub group: String,
    /// The implementation (`vecexpr`, `eager`, ...).
    pub implementation: String,
    /// The size label (`3`, `aos4096`, `1K`, ...).
    pub size: String,
    /// Median time per iteration in nanoseconds (over several rounds: the median of
    /// the rounds' medians).
    pub median_ns: f64,
    /// Largest over smallest of the rounds' medians; 1 for a single round.
    pub spread: f64,
}

/// All measurements of one run, for one target.
#[derive(Clone, Debug, Default)]
pub struct Run {
    /// The target name (`x86-64`, `x86-64-v3`, ...).
    pub target: String,
    /// The medians.
    pub data: Vec<Measurement>,
}

/// Reads every `new/benchmark.json` + `new/estimates.json` pair under `dir`.
///
/// # Errors
/// If `dir` cannot be read or a JSON file is malformed.
pub fn load(dir: &Path) -> Result<Vec<Measurement>, String> {
    let mut out = Vec::new();
    walk(dir, &mut out)?;
    out.sort_by(|a, b| {
        (&a.group, &a.size, &a.implementation).cmp(&(&b.group, &b.size, &b.implementation))
    });
    Ok(out)
}

fn walk(dir: &Path, out: &mut Vec<Measurement>) -> Result<(), String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for entry in entries.flatten() {
        let path = entry.path();
        if !path.is_dir() {
            continue;
        }
        if path.file_name().is_some_and(|n| n == "new") {
            let bench = path.join("benchmark.json");
            let est = path.join("estimates.json");
            if bench.exists() && est.exists() {
                out.push(parse(&read(&bench)?, &read(&est)?)?);
            }
        } else {
            walk(&path, out)?;
        }
    }
    Ok(())
}

fn read(p: &Path) -> Result<String, String> {
    std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))
}

/// One measurement from the texts of `benchmark.json` and `estimates.json`.
///
/// # Errors
/// If a field is missing.
pub fn parse(benchmark: &str, estimates: &str) -> Result<Measurement, String> {
    let b: serde_json::Value = serde_json::from_str(benchmark).map_err(|e| e.to_string())?;
    let e: serde_json::Value = serde_json::from_str(estimates).map_err(|e| e.to_string())?;
    let field = |k: &str| {
        b[k].as_str()
            .map(str::to_string)
            .ok_or_else(|| format!("benchmark.json: no {k}"))
    };
    Ok(Measurement {
        group: field("group_id")?,
        implementation: field("function_id")?,
        size: field("value_str")?,
        median_ns: e["median"]["point_estimate"]
            .as_f64()
            .ok_or("estimates.json: no median")?,
        spread: 1.0,
    })
}

/// One run's measurements from several rounds of the same suite: per benchmark the
/// median of the rounds' medians (the mean of the middle two for an even count) and
/// their spread. A benchmark missing from some rounds keeps the rounds that have it.
pub fn merge_rounds(rounds: &[Vec<Measurement>]) -> Vec<Measurement> {
    let mut by_key: std::collections::BTreeMap<(&str, &str, &str), Vec<f64>> =
        std::collections::BTreeMap::new();
    for m in rounds.iter().flatten() {
        by_key
            .entry((&m.group, &m.size, &m.implementation))
            .or_default()
            .push(m.median_ns);
    }
    by_key
        .into_iter()
        .map(|((group, size, implementation), mut v)| {
            v.sort_by(f64::total_cmp);
            let n = v.len();
            let median = if n % 2 == 1 {
                v[n / 2]
            } else {
                0.5 * (v[n / 2 - 1] + v[n / 2])
            };
            Measurement {
                group: group.into(),
                implementation: implementation.into(),
                size: size.into(),
                median_ns: median,
                spread: v[n - 1] / v[0],
            }
        })
        .collect()
}

impl Run {
    /// The median of `group/implementation/size`, if measured.
    pub fn median(&self, group: &str, implementation: &str, size: &str) -> Option<f64> {
        self.data
            .iter()
            .find(|m| m.group == group && m.implementation == implementation && m.size == size)
            .map(|m| m.median_ns)
    }

    /// ", rounds within ±N %" for the given implementations of one benchmark when
    /// they were measured in more than one round: the largest spread, as half of
    /// (largest / smallest − 1).
    pub fn spread_note(&self, group: &str, implementations: &[&str], size: &str) -> String {
        let worst = self
            .data
            .iter()
            .filter(|m| {
                m.group == group
                    && m.size == size
                    && implementations.contains(&m.implementation.as_str())
            })
            .map(|m| m.spread)
            .fold(1.0f64, f64::max);
        if worst > 1.0 {
            format!(" (rounds within ±{:.0} %)", 50.0 * (worst - 1.0))
        } else {
            String::new()
        }
    }

    /// Triad bandwidth in bytes per nanosecond (= GB/s).
    pub fn triad_gbs(&self) -> Option<f64> {
        self.median("bandwidth", "triad", "32M")
            .map(|t| 12.0 * crate::config::STREAM_LEN as f64 / t)
    }

    /// Copy bandwidth in GB/s.
    pub fn copy_gbs(&self) -> Option<f64> {
        self.median("bandwidth", "copy", "32M")
            .map(|t| 8.0 * crate::config::STREAM_LEN as f64 / t)
    }
}

/// Order in which implementations appear as table columns.
pub const IMPLEMENTATIONS: [&str; 16] = [
    "vecexpr",
    "vecexpr_vec3a",
    "vecexpr_vec3a_fast",
    "vecexpr_matrix",
    "vecexpr_fma",
    "eager",
    "hand",
    "glam_vec3",
    "glam_vec3a",
    "glam_vec4",
    "glam",
    "nalgebra",
    "ultraviolet",
    "ultraviolet_x8",
    "vecexpr_f32x8",
    "vecexpr_f32x16",
];

/// Order of the size labels.
pub const SIZES: [&str; 10] = [
    "3",
    "4",
    "4x4",
    "aos4096",
    "soa8x4096",
    "soa16x4096",
    "1K",
    "64K",
    "1M",
    "16M",
];

/// Bytes moved per element by the long-vector kernels (STREAM convention: loads plus
/// stores, no write-allocate).
pub fn bytes_per_element(group: &str) -> Option<f64> {
    match group {
        "abcde" => Some(24.0),
        "axpy" => Some(12.0),
        "dot" => Some(8.0),
        _ => None,
    }
}

/// Number of `f32` elements of a long-vector size label.
pub fn long_len(size: &str) -> Option<usize> {
    crate::config::LONG
        .iter()
        .find(|(_, l)| *l == size)
        .map(|(n, _)| *n)
}

/// A time in ns, µs or ms with three significant digits.
pub fn format_ns(ns: f64) -> String {
    let (v, unit) = if ns < 1e3 {
        (ns, "ns")
    } else if ns < 1e6 {
        (ns / 1e3, "µs")
    } else {
        (ns / 1e6, "ms")
    };
    let digits = if v < 10.0 {
        2
    } else if v < 100.0 {
        1
    } else {
        0
    };
    format!("{v:.digits$} {unit}")
}

/// The kernels (criterion groups) measured in any run, in name order; the bandwidth
/// reference is not one.
fn kernels(runs: &[Run]) -> BTreeSet<&str> {
    runs.iter()
        .flat_map(|r| r.data.iter().map(|m| m.group.as_str()))
        .filter(|g| *g != "bandwidth")
        .collect()
}

/// One Markdown table per kernel: a row per size and target, a column per
/// implementation; each cell is the median and, in parentheses, its time relative to
/// vecexpr (above 1 means slower than vecexpr).
pub fn tables(runs: &[Run]) -> String {
    let mut s = String::new();
    for group in kernels(runs) {
        let impls: Vec<&str> = IMPLEMENTATIONS
            .iter()
            .copied()
            .filter(|i| {
                runs.iter().any(|r| {
                    r.data
                        .iter()
                        .any(|m| m.group == group && m.implementation == *i)
                })
            })
            .collect();
        writeln!(s, "\n#### `{group}`\n").unwrap();
        writeln!(s, "| size | target | {} |", impls.join(" | ")).unwrap();
        writeln!(s, "|---|---|{}", "---:|".repeat(impls.len())).unwrap();
        for size in SIZES {
            for r in runs {
                let base = r.median(group, "vecexpr", size);
                let cells: Vec<String> = impls
                    .iter()
                    .map(|i| match (r.median(group, i, size), base) {
                        (Some(t), Some(b)) if *i != "vecexpr" => {
                            format!("{} ({:.2})", format_ns(t), t / b)
                        }
                        (Some(t), _) => format_ns(t),
                        (None, _) => "".to_string(),
                    })
                    .collect();
                if cells.iter().all(String::is_empty) {
                    continue;
                }
                writeln!(s, "| {size} | {} | {} |", r.target, cells.join(" | ")).unwrap();
            }
        }
    }
    s
}

/// The bandwidth table and, for the long-vector kernels, ns per element, the speedup
/// over eager, the ratio to the hand loop and the fraction of triad bandwidth.
pub fn long_table(runs: &[Run]) -> String {
    let mut s = String::new();
    writeln!(s, "| target | copy GB/s | triad GB/s |").unwrap();
    writeln!(s, "|---|---:|---:|").unwrap();
    for r in runs {
        let f = |x: Option<f64>| x.map(|v| format!("{v:.1}")).unwrap_or_default();
        writeln!(
            s,
            "| {} | {} | {} |",
            r.target,
            f(r.copy_gbs()),
            f(r.triad_gbs())
        )
        .unwrap();
    }
    writeln!(
        s,
        "\n| kernel | size | target | vecexpr ns/elem | hand ns/elem | eager ns/elem | vecexpr / hand | eager / vecexpr | vecexpr GB/s | of triad |"
    )
    .unwrap();
    writeln!(s, "|---|---|---|---:|---:|---:|---:|---:|---:|---:|").unwrap();
    for group in ["abcde", "axpy", "dot"] {
        for (n, size) in crate::config::LONG {
            for r in runs {
                let per = |i: &str| r.median(group, i, size).map(|t| t / n as f64);
                let (Some(v), Some(h), Some(e)) = (per("vecexpr"), per("hand"), per("eager"))
                else {
                    continue;
                };
                let gbs = bytes_per_element(group).unwrap() / v;
                let of_triad = r
                    .triad_gbs()
                    .map(|t| format!("{:.0}%", 100.0 * gbs / t))
                    .unwrap_or_default();
                writeln!(
                    s,
                    "| {group} | {size} | {} | {v:.3} | {h:.3} | {e:.3} | {:.2} | {:.2} | {gbs:.1} | {of_triad} |",
                    r.target,
                    v / h,
                    e / v
                )
                .unwrap();
            }
        }
    }
    s
}

/// One performance target evaluated on one run's medians.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// The target name of the run (`x86-64`, ...).
    pub target: String,
    /// The kernel (criterion group) the target is about.
    pub group: String,
    /// The size label the target is about.
    pub size: String,
    /// What is asked, in words (`within 5% of hand`).
    pub case: String,
    /// The numbers that decide it.
    pub measured: String,
    /// Whether the target is met.
    pub met: bool,
}

impl Verdict {
    fn word(&self) -> &'static str {
        if self.met {
            "met"
        } else {
            "MISSED"
        }
    }
}

/// The project's performance targets (vecexpr's issues), each evaluated on the medians
/// of every run that has the numbers it needs.
pub fn verdicts(runs: &[Run]) -> Vec<Verdict> {
    let mut out = Vec::new();
    for r in runs {
        let mut add = |group: &str, size: &str, case: String, measured: String, met: bool| {
            out.push(Verdict {
                target: r.target.clone(),
                group: group.into(),
                size: size.into(),
                case,
                measured,
                met,
            })
        };
        for size in SIZES {
            if let (Some(v), Some(h)) = (
                r.median("abcde", "vecexpr", size),
                r.median("abcde", "hand", size),
            ) {
                let m = format!("vecexpr / hand = {:.3}", v / h);
                add("abcde", size, "within 5% of hand".into(), m, v <= 1.05 * h);
            }
        }
        for (_, size) in crate::config::LONG {
            if let (Some(v), Some(e)) = (
                r.median("abcde", "vecexpr", size),
                r.median("abcde", "eager", size),
            ) {
                let m = format!("eager / vecexpr = {:.2}", e / v);
                add("abcde", size, "at least 2.5x eager".into(), m, e >= 2.5 * v);
            }
        }
        if let (Some(v), Some(tr)) = (r.median("abcde", "vecexpr", "16M"), r.triad_gbs()) {
            let gbs = 24.0 * (1 << 24) as f64 / v;
            let m = format!("{gbs:.1} of {tr:.1} GB/s = {:.0}%", 100.0 * gbs / tr);
            add(
                "abcde",
                "16M",
                "at least 90% of triad".into(),
                m,
                gbs >= 0.9 * tr,
            );
        }
        // The padded single 3-vector against glam's: at most 1.0x its time, one vector
        // and batches of 4096, robust and fast normalisation.
        for group in ["reflect", "normalize", "reflect_normalize"] {
            for size in ["3", "aos4096"] {
                let Some(g) = r.median(group, "glam_vec3a", size) else {
                    continue;
                };
                for (imp, name) in [
                    ("vecexpr_vec3a", "Vec3A"),
                    ("vecexpr_vec3a_fast", "Vec3A normalize_fast"),
                ] {
                    if let Some(v) = r.median(group, imp, size) {
                        let m = format!(
                            "{} vs {} = {:.3}{}",
                            format_ns(v),
                            format_ns(g),
                            v / g,
                            r.spread_note(group, &[imp, "glam_vec3a"], size)
                        );
                        add(
                            group,
                            size,
                            format!("{name} at most 1.0x glam Vec3A"),
                            m,
                            v <= g,
                        );
                    }
                }
            }
        }
        if let (Some(v), Some(g)) = (
            r.median("reflect", "vecexpr", "aos4096"),
            r.median("reflect", "glam_vec3a", "aos4096"),
        ) {
            let m = format!("{} vs {}", format_ns(v), format_ns(g));
            add(
                "reflect",
                "aos4096",
                "at least as fast as glam Vec3A".into(),
                m,
                v <= g,
            );
        }
        let g = r.median("reflect_normalize", "glam_vec3a", "aos4096");
        let uv = r.median("reflect_normalize", "ultraviolet", "soa8x4096");
        for size in ["soa16x4096", "soa8x4096"] {
            let Some(v) = r.median("reflect_normalize", "vecexpr", size) else {
                continue;
            };
            if let Some(g) = g {
                let m = format!("glam / vecexpr = {:.2}", g / v);
                let case = "at least 1.5x glam Vec3A".into();
                add("reflect_normalize", size, case, m, g >= 1.5 * v);
            }
            if let Some(u) = uv {
                let m = format!("{} vs {}", format_ns(v), format_ns(u));
                let case = "at least as fast as ultraviolet Vec3x8".into();
                add("reflect_normalize", size, case, m, v <= u);
            }
        }
        // The same target for vecexpr on the explicit lane types of `vecexpr::simd`.
        for (imp, size) in [
            ("vecexpr_f32x16", "soa16x4096"),
            ("vecexpr_f32x8", "soa8x4096"),
        ] {
            if let (Some(v), Some(u)) = (r.median("reflect_normalize", imp, size), uv) {
                let m = format!("{} vs {}", format_ns(v), format_ns(u));
                let case = format!("{imp}: at least as fast as ultraviolet Vec3x8");
                add("reflect_normalize", size, case, m, v <= u);
            }
        }
    }
    out
}

/// The targets as a table: one line per target and case with the numbers and `met` or
/// `MISSED`.
pub fn targets(runs: &[Run]) -> String {
    let mut s = String::new();
    writeln!(s, "| target | case | measured | verdict |").unwrap();
    writeln!(s, "|---|---|---|---|").unwrap();
    for v in verdicts(runs) {
        let kernel = v.group.replace("reflect_normalize", "reflect+normalize");
        writeln!(
            s,
            "| {} | {kernel} {}: {} | {} | {} |",
            v.target,
            v.size,
            v.case,
            v.measured,
            v.word()
        )
        .unwrap();
    }
    s
}

/// Today's answer in one table: per kernel, size and target the time of vecexpr's
/// generic form, and each peer's time as a ratio to it (above 1: vecexpr is faster);
/// for a peer with several types (glam's `Vec3`/`Vec3A`/`Vec4`, vecexpr's other forms)
/// the fastest, named; then the targets evaluated on that row.
pub fn answer(runs: &[Run]) -> String {
    const OTHER_FORMS: [(&str, &str); 6] = [
        ("vecexpr_vec3a", "Vec3A"),
        ("vecexpr_vec3a_fast", "Vec3A fast"),
        ("vecexpr_matrix", "Matrix"),
        ("vecexpr_f32x8", "F32x8"),
        ("vecexpr_f32x16", "F32x16"),
        ("vecexpr_fma", "mul_add"),
    ];
    const GLAM: [(&str, &str); 4] = [
        ("glam_vec3", "Vec3"),
        ("glam_vec3a", "Vec3A"),
        ("glam_vec4", "Vec4"),
        ("glam", ""),
    ];
    let all = verdicts(runs);
    let mut s = String::new();
    writeln!(
        s,
        "| kernel | size | target | vecexpr | other vecexpr form | eager | hand | glam | ultraviolet | nalgebra | fastest | targets |"
    )
    .unwrap();
    writeln!(
        s,
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|---|"
    )
    .unwrap();
    for group in kernels(runs) {
        for size in SIZES {
            for r in runs {
                let row: Vec<&Measurement> = r
                    .data
                    .iter()
                    .filter(|m| m.group == group && m.size == size)
                    .collect();
                if row.is_empty() {
                    continue;
                }
                let t = |i: &str| r.median(group, i, size);
                // The base: the generic form, or the only vecexpr form the kernel has.
                let Some((base_name, base)) = std::iter::once(("vecexpr", "vecexpr"))
                    .chain(OTHER_FORMS)
                    .find_map(|(i, name)| t(i).map(|v| (name, v)))
                else {
                    continue;
                };
                let best = |forms: &[(&str, &'static str)]| -> Option<(&'static str, f64)> {
                    forms
                        .iter()
                        .filter_map(|(i, name)| t(i).map(|v| (*name, v)))
                        .filter(|(name, _)| *name != base_name)
                        .min_by(|a, b| a.1.total_cmp(&b.1))
                };
                let cell = |x: Option<(&str, f64)>| match x {
                    Some(("", v)) => format!("{:.2}", v / base),
                    Some((name, v)) => format!("{:.2} ({name})", v / base),
                    None => String::new(),
                };
                let one = |i: &str| cell(t(i).map(|v| ("", v)));
                let fastest = row
                    .iter()
                    .min_by(|a, b| a.median_ns.total_cmp(&b.median_ns))
                    .map(|m| m.implementation.as_str())
                    .unwrap_or_default();
                let verdicts: Vec<String> = all
                    .iter()
                    .filter(|v| v.target == r.target && v.group == group && v.size == size)
                    .map(|v| format!("{}: {}", v.case, v.word()))
                    .collect();
                let base_cell = if base_name == "vecexpr" {
                    format_ns(base)
                } else {
                    format!("{} ({base_name})", format_ns(base))
                };
                writeln!(
                    s,
                    "| {group} | {size} | {} | {base_cell} | {} | {} | {} | {} | {} | {} | {fastest} | {} |",
                    r.target,
                    cell(best(&OTHER_FORMS)),
                    one("eager"),
                    one("hand"),
                    cell(best(&GLAM)),
                    cell(best(&[("ultraviolet", ""), ("ultraviolet_x8", "x8")])),
                    one("nalgebra"),
                    verdicts.join("; ")
                )
                .unwrap();
            }
        }
    }
    s
}

/// An SVG line plot of the speedup of vecexpr over eager (eager time / vecexpr time)
/// against vector length, one line per long-vector kernel and target, log-scaled x.
pub fn speedup_svg(runs: &[Run]) -> String {
    let (w, h) = (760.0, 460.0);
    let (left, right, top, bottom) = (70.0, 200.0, 40.0, 60.0);
    let (pw, ph) = (w - left - right, h - top - bottom);
    let mut series = Vec::new();
    for group in ["abcde", "axpy", "dot"] {
        for r in runs {
            let pts: Vec<(f64, f64)> = crate::config::LONG
                .iter()
                .filter_map(|(n, size)| {
                    let v = r.median(group, "vecexpr", size)?;
                    let e = r.median(group, "eager", size)?;
                    Some(((*n as f64).log2(), e / v))
                })
                .collect();
            if !pts.is_empty() {
                series.push((format!("{group}, {}", r.target), group, pts));
            }
        }
    }
    let ymax = series
        .iter()
        .flat_map(|(_, _, p)| p.iter().map(|q| q.1))
        .fold(1.0f64, f64::max)
        .ceil()
        .max(2.0);
    let (x0, x1) = (10.0, 24.0);
    let px = |x: f64| left + (x - x0) / (x1 - x0) * pw;
    let py = |y: f64| top + ph - y / ymax * ph;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    writeln!(
        s,
        "<text x=\"{}\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">Speedup of vecexpr over eager vectors (eager time / vecexpr time)</text>",
        w / 2.0
    )
    .unwrap();
    // Axes and grid.
    let step = if ymax > 12.0 {
        5
    } else if ymax > 6.0 {
        2
    } else {
        1
    };
    for k in (0..=(ymax as usize)).step_by(step) {
        let y = py(k as f64);
        writeln!(
            s,
            "<line x1=\"{left}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" stroke=\"#ddd\"/>",
            left + pw
        )
        .unwrap();
        writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{k}x</text>",
            left - 6.0,
            y + 4.0
        )
        .unwrap();
    }
    for (n, label) in crate::config::LONG {
        let x = px((n as f64).log2());
        writeln!(
            s,
            "<line x1=\"{x}\" y1=\"{top}\" x2=\"{x}\" y2=\"{}\" stroke=\"#ddd\"/>",
            top + ph
        )
        .unwrap();
        writeln!(
            s,
            "<text x=\"{x}\" y=\"{}\" text-anchor=\"middle\">{label}</text>",
            top + ph + 18.0
        )
        .unwrap();
    }
    writeln!(
        s,
        "<line x1=\"{left}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"black\" stroke-dasharray=\"4 3\"/>",
        py(1.0),
        left + pw,
        py(1.0)
    )
    .unwrap();
    writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">vector length (f32 elements, log scale)</text>",
        left + pw / 2.0,
        h - 18.0
    )
    .unwrap();
    let colors = ["#1b6ca8", "#d1495b", "#2e933c"];
    let dashes = ["", "6 3", "2 3"];
    for (k, (name, group, pts)) in series.iter().enumerate() {
        let color = match *group {
            "abcde" => colors[0],
            "axpy" => colors[1],
            _ => colors[2],
        };
        let dash = dashes[k % runs.len().max(1) % dashes.len()];
        let path: Vec<String> = pts
            .iter()
            .map(|(x, y)| format!("{:.1},{:.1}", px(*x), py(*y)))
            .collect();
        writeln!(
            s,
            "<polyline fill=\"none\" stroke=\"{color}\" stroke-width=\"2\" stroke-dasharray=\"{dash}\" points=\"{}\"/>",
            path.join(" ")
        )
        .unwrap();
        for (x, y) in pts {
            writeln!(
                s,
                "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"3\" fill=\"{color}\"/>",
                px(*x),
                py(*y)
            )
            .unwrap();
        }
        let ly = top + 14.0 + 18.0 * k as f64;
        let lx = left + pw + 14.0;
        writeln!(
            s,
            "<line x1=\"{lx}\" y1=\"{ly}\" x2=\"{}\" y2=\"{ly}\" stroke=\"{color}\" stroke-width=\"2\" stroke-dasharray=\"{dash}\"/><text x=\"{}\" y=\"{}\">{name}</text>",
            lx + 28.0,
            lx + 34.0,
            ly + 4.0
        )
        .unwrap();
    }
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(group: &str, i: &str, size: &str, ns: f64) -> Measurement {
        Measurement {
            group: group.into(),
            implementation: i.into(),
            size: size.into(),
            median_ns: ns,
            spread: 1.0,
        }
    }

    #[test]
    fn parses_criterion_json() {
        let b =
            r#"{"group_id":"abcde","function_id":"vecexpr","value_str":"1K","throughput":null}"#;
        let e = r#"{"mean":{"point_estimate":2.0},"median":{"point_estimate":1.5}}"#;
        assert_eq!(parse(b, e).unwrap(), m("abcde", "vecexpr", "1K", 1.5));
        assert!(parse("{}", e).is_err());
    }

    #[test]
    fn tables_and_targets_use_the_numbers() {
        let run = Run {
            target: "x86-64".into(),
            data: vec![
                m("abcde", "vecexpr", "16M", 40e6),
                m("abcde", "hand", "16M", 40e6),
                m("abcde", "eager", "16M", 120e6),
                m("bandwidth", "triad", "32M", 12.0 * (1 << 25) as f64 / 10.0),
            ],
        };
        assert!((run.triad_gbs().unwrap() - 10.0).abs() < 1e-9);
        let t = tables(std::slice::from_ref(&run));
        assert!(
            t.contains("| 16M | x86-64 | 40.0 ms | 120 ms (3.00) | 40.0 ms (1.00) |"),
            "{t}"
        );
        let v = targets(std::slice::from_ref(&run));
        assert!(v.contains("vecexpr / hand = 1.000 | met"), "{v}");
        assert!(v.contains("eager / vecexpr = 3.00 | met"), "{v}");
        // 24 bytes * 16 Mi / 40 ms = 10.07 GB/s of 10 GB/s triad.
        assert!(v.contains("= 101% | met"), "{v}");
        let l = long_table(std::slice::from_ref(&run));
        assert!(l.contains("| abcde | 16M | x86-64 |"), "{l}");
        let svg = speedup_svg(&[run]);
        assert!(svg.starts_with("<svg") && svg.contains("polyline"));
        assert_eq!(format_ns(1234.0), "1.23 µs");
    }
    #[test]
    fn rounds_merge_to_the_median_with_their_spread() {
        let r = |ns| vec![m("reflect", "vecexpr", "3", ns)];
        let merged = merge_rounds(&[r(3.0), r(1.0), r(2.0)]);
        assert_eq!(merged.len(), 1);
        assert_eq!(merged[0].median_ns, 2.0);
        assert_eq!(merged[0].spread, 3.0);
        let even = merge_rounds(&[r(1.0), r(2.0)]);
        assert_eq!(even[0].median_ns, 1.5);
    }

    #[test]
    fn the_answer_names_the_fastest_and_the_vec3a_targets() {
        let mut data = merge_rounds(&[
            vec![
                m("normalize", "vecexpr", "3", 4.0),
                m("normalize", "vecexpr_vec3a", "3", 3.0),
                m("normalize", "vecexpr_vec3a_fast", "3", 2.0),
                m("normalize", "glam_vec3a", "3", 2.2),
                m("normalize", "glam_vec3", "3", 5.0),
                m("normalize", "eager", "3", 8.0),
            ],
            vec![m("normalize", "glam_vec3a", "3", 2.6)],
        ]);
        data.push(m("mat4", "vecexpr_matrix", "4x4", 9.0));
        data.push(m("mat4", "glam", "4x4", 4.5));
        let run = Run {
            target: "x86-64".into(),
            data,
        };
        let runs = std::slice::from_ref(&run);
        let v = verdicts(runs);
        let fast = v
            .iter()
            .find(|v| v.case.starts_with("Vec3A normalize_fast"))
            .unwrap();
        // 2.0 against the median 2.4 of glam's two rounds (spread 2.6 / 2.2).
        assert!(
            fast.met && fast.measured.contains("= 0.833 (rounds within ±9 %)"),
            "{fast:?}"
        );
        assert!(
            !v.iter()
                .find(|v| v.case.starts_with("Vec3A at"))
                .unwrap()
                .met
        );
        let a = answer(runs);
        assert!(
            a.contains("| normalize | 3 | x86-64 | 4.00 ns | 0.50 (Vec3A fast) | 2.00 |  | 0.60 (Vec3A) |  |  | vecexpr_vec3a_fast | Vec3A at most 1.0x glam Vec3A: MISSED; Vec3A normalize_fast at most 1.0x glam Vec3A: met |"),
            "{a}"
        );
        assert!(
            a.contains(
                "| mat4 | 4x4 | x86-64 | 9.00 ns (Matrix) |  |  |  | 0.50 |  |  | glam |  |"
            ),
            "{a}"
        );
    }
}
