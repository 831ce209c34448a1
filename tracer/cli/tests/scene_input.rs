//! Scene input through the command line: degenerate primitives are counted in `--stats`,
//! and a number that does not fit the chosen precision is a `FILE:LINE` error that
//! writes nothing (the readers' own tests are in `tracer/tests/scene_input.rs`).

use std::path::PathBuf;
use std::process::Command;

fn tmpdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracer-input-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

const VIEW: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n";

#[test]
fn cli_counts_degenerate_primitives_in_the_stats() {
    let d = tmpdir("degenerate");
    let input = d.join("degenerate.nff");
    // One sphere, one floor triangle, and three degenerate primitives: a zero-radius
    // sphere, a collinear triangle and a cone with coinciding ends.
    let text = format!(
        "{VIEW}l 5 5 5\nf 1 0 0 1 0 0 0 0\ns 0 0 0 1\ns 1 1 1 0\np 3\n0 0 0\n1 1 1\n2 2 2\n\
         c 1 1 1 0.5 1 1 1 0.5\np 3\n-3 -1 -3\n-3 -1 3\n3 -1 3\n"
    );
    std::fs::write(&input, text).unwrap();
    let stats = d.join("stats.json");
    let st = Command::new(env!("CARGO_BIN_EXE_tracer"))
        .arg("render")
        .arg(&input)
        .arg("-o")
        .arg(d.join("out.png"))
        .arg("--stats")
        .arg(&stats)
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    let p = &json["primitives"];
    assert_eq!(p["degenerate"], 3, "{p}");
    assert_eq!(p["sphere"], 1, "{p}");
    assert_eq!(p["total"], 5, "{p}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn cli_refuses_f32_overflow_and_renders_it_in_f64() {
    let d = tmpdir("overflow");
    let input = d.join("big.nff");
    std::fs::write(&input, format!("{VIEW}l 5 5 5\ns 1e39 0 0 1\ns 0 0 0 1\n")).unwrap();
    let out = d.join("out.png");
    let run = |precision: &str| {
        Command::new(env!("CARGO_BIN_EXE_tracer"))
            .arg("render")
            .arg(&input)
            .arg("-o")
            .arg(&out)
            .args(["--precision", precision])
            .output()
            .unwrap()
    };
    let st = run("f32");
    assert_eq!(st.status.code(), Some(2));
    let err = String::from_utf8(st.stderr).unwrap();
    assert_eq!(
        err,
        format!(
            "{}:9: number `1e39` does not fit in f32 (largest magnitude 3.4028235e38)\n",
            input.display()
        )
    );
    assert!(!out.exists(), "output written");
    let st = run("f64");
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    assert!(out.exists());
    let _ = std::fs::remove_dir_all(&d);
}
