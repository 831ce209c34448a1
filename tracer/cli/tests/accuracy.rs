//! `tracer accuracy`: the report is written, its numbers are sane, bad input is refused.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use tracer::stats::median;
use tracer::Image;
use tracer_cli::accuracy::{compare, pareto};

fn tracer() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tracer"))
}

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name)
}

fn tmpdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracer-accuracy-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The CSV as one map from column name to value per row.
fn read_csv(path: &Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            assert_eq!(cells.len(), header.len(), "{l}");
            header
                .iter()
                .cloned()
                .zip(cells.into_iter().map(String::from))
                .collect()
        })
        .collect()
}

fn num(row: &HashMap<String, String>, key: &str) -> f64 {
    row[key]
        .parse()
        .unwrap_or_else(|_| panic!("{key} = {}", row[key]))
}

#[test]
fn report_on_a_reflective_scene() {
    let d = tmpdir("ok");
    let out = d.join("report");
    let st = tracer()
        .arg("accuracy")
        .arg(scene("balls-s1.nff"))
        .arg("-o")
        .arg(&out)
        .args([
            "--width",
            "32",
            "--runs",
            "2",
            "--ref-depth",
            "7",
            "--ref-aa",
            "2",
            "--fine-aa",
            "3",
            "--max-aa",
            "2",
            "--threads",
            "2",
        ])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    for f in [
        "balls-s1.md",
        "balls-s1.csv",
        "balls-s1.svg",
        "balls-s1-reference.png",
        "summary.md",
        "summary.csv",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let png = Image::read_png(&out.join("balls-s1-reference.png")).unwrap();
    assert_eq!((png.width, png.height), (32, 32));
    let svg = std::fs::read_to_string(out.join("balls-s1.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("Pareto front"));
    let md = std::fs::read_to_string(out.join("balls-s1.md")).unwrap();
    assert!(md.contains("## Findings") && md.contains("| depth | depth 3 |"));
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(summary.contains("| balls-s1 | 32x32 |"));

    let rows = read_csv(&out.join("balls-s1.csv"));
    // reference, f32, depths 1..6, 4 thresholds, 8 arithmetic, aa 1, 2 and 2 (= the
    // reference's grid, not repeated).
    assert_eq!(rows.len(), 1 + 1 + 6 + 4 + 8 + 2);
    for r in &rows {
        assert_eq!(num(r, "runs"), 2.0);
        assert!(num(r, "median_ms") > 0.0);
        assert!(num(r, "rays") >= 32.0 * 32.0);
        let rmse = num(r, "rmse");
        assert!((0.0..1.0).contains(&rmse), "{}: {rmse}", r["setting"]);
        assert!(num(r, "max_abs") >= rmse);
    }
    // The reference, re-rendered, against itself.
    let reference = &rows[0];
    assert_eq!(reference["knob"], "reference");
    assert_eq!(num(reference, "rmse"), 0.0);
    assert_eq!(num(reference, "max_abs"), 0.0);
    assert_eq!(reference["psnr_db"], "inf");
    assert_eq!(num(reference, "time_vs_reference"), 1.0);

    // Mirrors: the error falls as the depth grows, down to the reference's depth.
    let depth: Vec<&HashMap<String, String>> =
        rows.iter().filter(|r| r["knob"] == "depth").collect();
    assert_eq!(depth.len(), 6);
    for w in depth.windows(2) {
        assert!(num(w[1], "depth") > num(w[0], "depth"));
        for key in ["rmse", "max_abs", "share_over_1_255"] {
            assert!(
                num(w[1], key) <= num(w[0], key),
                "{key} rises from {} to {}",
                w[0]["setting"],
                w[1]["setting"]
            );
        }
    }
    assert!(num(depth[0], "rmse") > 10.0 * num(depth[5], "rmse"));
    assert!(
        num(depth[0], "rmse") > 0.01,
        "depth 1 misses the reflections"
    );

    // Approximations and f32 stay close to the reference.
    for r in rows
        .iter()
        .filter(|r| r["knob"] == "arithmetic" || r["knob"] == "precision")
    {
        assert!(num(r, "rmse") < 0.01, "{}", r["setting"]);
    }
    // FMA in f64 changes only the last bits.
    let fma = rows.iter().find(|r| r["setting"] == "f64 fma").unwrap();
    assert!(num(fma, "max_abs") < 1e-6);
    // More rays per pixel: closer to the fine reference.
    let aa: Vec<_> = rows
        .iter()
        .filter(|r| r["knob"] == "antialiasing")
        .collect();
    assert_eq!(aa.len(), 2);
    assert!(num(aa[1], "rmse") < num(aa[0], "rmse"));
    assert_eq!(num(aa[1], "rays"), num(reference, "rays"));
    assert!(rows.iter().any(|r| r["pareto"] == "true"));
    std::fs::remove_dir_all(&d).unwrap();
}

fn assert_refused(args: &[&std::ffi::OsStr], expect: &str) {
    let st = tracer().args(args).output().unwrap();
    assert_eq!(st.status.code(), Some(2), "{args:?}");
    let err = String::from_utf8_lossy(&st.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with(expect), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_input_is_one_line_and_exit_2() {
    let d = tmpdir("bad");
    let out = d.join("report");
    let missing = d.join("missing.nff");
    assert_refused(
        &[
            "accuracy".as_ref(),
            missing.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        &format!("{}:", missing.display()),
    );
    let broken = d.join("broken.nff");
    std::fs::write(&broken, "v\nfrom 0 0 5\nat 0 0 zero\n").unwrap();
    assert_refused(
        &[
            "accuracy".as_ref(),
            broken.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        &format!("{}:3:", broken.display()),
    );
    // A good scene after a bad one: nothing is rendered or written.
    assert_refused(
        &[
            "accuracy".as_ref(),
            scene("tetra-s1.nff").as_os_str(),
            broken.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        &format!("{}:3:", broken.display()),
    );
    assert!(!out.exists(), "no report directory for bad input");
    // The report directory is a file.
    let file = d.join("file");
    std::fs::write(&file, "x").unwrap();
    assert_refused(
        &[
            "accuracy".as_ref(),
            scene("tetra-s1.nff").as_os_str(),
            "-o".as_ref(),
            file.as_os_str(),
        ],
        &format!("{}:", file.display()),
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn metrics() {
    let mut a = Image::new(2, 2);
    a.pixels = vec![[0.5; 3], [0.2, 0.4, 0.6], [1.5, -1.0, 0.0], [0.0; 3]];
    let same = compare(&a, &a);
    assert_eq!((same.rmse, same.max_abs, same.over_1_255), (0.0, 0.0, 0.0));
    assert_eq!(same.psnr, f64::INFINITY);
    let mut b = a.clone();
    b.pixels[1][2] += 0.1;
    // Out-of-range values are clamped as on screen: 1.5 and 2.0 both show as 1.
    b.pixels[2][0] = 2.0;
    b.pixels[3][1] = 0.5 / 255.0;
    let m = compare(&b, &a);
    let d = f64::from(0.6f32 + 0.1) - f64::from(0.6f32);
    let mse = (d * d + (0.5f64 / 255.0).powi(2)) / 12.0;
    assert!((m.rmse - mse.sqrt()).abs() < 1e-12);
    assert!((m.psnr + 10.0 * mse.log10()).abs() < 1e-9);
    assert!((m.max_abs - d).abs() < 1e-12);
    assert_eq!(m.over_1_255, 0.25);
}

#[test]
fn pareto_front_and_median() {
    let pts = [
        (1.0, 5.0),
        (2.0, 3.0),
        (2.0, 4.0),
        (3.0, 3.0),
        (4.0, 0.0),
        (0.5, 9.0),
    ];
    assert_eq!(pareto(&pts), [true, true, false, false, true, true]);
    assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
    assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
}
