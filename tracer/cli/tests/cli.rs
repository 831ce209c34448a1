//! The command line contract: outputs, stats fields, exit status and one-line errors.

use std::path::{Path, PathBuf};
use std::process::Command;

fn tracer() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tracer"))
}

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name)
}

fn tmpdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracer-cli-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn renders_png_pfm_and_stats() {
    let d = tmpdir("ok");
    let png = d.join("out.png");
    let stats = d.join("stats.json");
    let st = tracer()
        .args(["render"])
        .arg(scene("balls-s1.nff"))
        .arg("-o")
        .arg(&png)
        .args([
            "--width",
            "40",
            "--height",
            "30",
            "--aa",
            "2",
            "--threads",
            "2",
            "--stats",
        ])
        .arg(&stats)
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let img = tracer::Image::read_png(&png).unwrap();
    assert_eq!((img.width, img.height), (40, 30));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    for key in ["parse", "build", "split", "trace", "total"] {
        assert!(json["times_ms"][key].as_f64().is_some(), "times_ms.{key}");
    }
    for key in ["eye", "reflection", "refraction", "shadow"] {
        assert!(json["rays"][key].as_u64().is_some(), "rays.{key}");
    }
    assert_eq!(json["rays"]["eye"], 40 * 30 * 4);
    assert_eq!(json["primitives"]["sphere"], 10);
    assert!(json["bvh"]["nodes"].as_u64().unwrap() >= 1);
    assert!(json["bvh"]["depth"].as_u64().is_some());
    assert_eq!(json["image"]["width"], 40);
    assert_eq!(json["settings"]["aa"], 2);
    assert_eq!(json["settings"]["precision"], "f32");

    let pfm = d.join("out.pfm");
    let st = tracer()
        .arg("render")
        .arg(scene("tetra-s1.nff"))
        .arg("-o")
        .arg(&pfm)
        .args(["--width", "8", "--height", "4", "--precision", "f64"])
        .output()
        .unwrap();
    assert!(st.status.success());
    let bytes = std::fs::read(&pfm).unwrap();
    assert!(bytes.starts_with(b"PF\n8 4\n-1.0\n"));
    assert_eq!(bytes.len(), b"PF\n8 4\n-1.0\n".len() + 8 * 4 * 3 * 4);
    let _ = std::fs::remove_dir_all(&d);
}

/// Each malformed scene exits with 2, prints exactly one line `FILE:LINE: message`,
/// and leaves no output file.
#[test]
fn bad_input_gives_one_line_and_status_2() {
    let d = tmpdir("bad");
    let cases: &[(&str, &str, &str)] = &[
        ("truncated.nff", "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\np 4\n0 0 0\n1 0 0\n", ":8:"),
        ("unknown.nff", "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\nzz 1 2 3\n", ":8:"),
        ("badnum.nff", "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\ns 0 0 x 1\n", ":8:"),
        ("nov.nff", "s 0 0 0 1\n", ":"),
        ("badres.nff", "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution -8 8\n", ":7:"),
    ];
    for (name, text, line_tag) in cases {
        let input = d.join(name);
        std::fs::write(&input, text).unwrap();
        let out = d.join(format!("{name}.png"));
        let st = tracer()
            .arg("render")
            .arg(&input)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(st.status.code(), Some(2), "{name}");
        let err = String::from_utf8(st.stderr).unwrap();
        assert_eq!(err.lines().count(), 1, "{name}: {err}");
        assert!(
            err.starts_with(&input.display().to_string()),
            "{name}: {err}"
        );
        assert!(err.contains(line_tag), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(!out.exists(), "{name}: output written");
        let leftovers = std::fs::read_dir(&d)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .ends_with(".tmp")
            })
            .count();
        assert_eq!(leftovers, 0);
    }
    // A missing file and a bad output extension are one-line errors too.
    let st = tracer()
        .arg("render")
        .arg(d.join("missing.nff"))
        .arg("-o")
        .arg(d.join("x.png"))
        .output()
        .unwrap();
    assert_eq!(st.status.code(), Some(2));
    assert_eq!(String::from_utf8(st.stderr).unwrap().lines().count(), 1);
    let st = tracer()
        .arg("render")
        .arg(scene("tetra-s1.nff"))
        .arg("-o")
        .arg(d.join("x.jpg"))
        .output()
        .unwrap();
    assert_eq!(st.status.code(), Some(2));
    assert!(!d.join("x.jpg").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn cli_reports_the_effect_set() {
    let d = std::env::temp_dir().join(format!("tracer-effects-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let mut images = Vec::new();
    for mode in ["auto", "all"] {
        let out = d.join(format!("{mode}.pfm"));
        let stats = d.join(format!("{mode}.json"));
        let st = tracer()
            .arg("render")
            .arg(scene("tetra-s1.nff"))
            .arg("-o")
            .arg(&out)
            .args([
                "--width",
                "24",
                "--height",
                "24",
                "--effects",
                mode,
                "--stats",
            ])
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
        let fx = &json["effects"];
        assert_eq!(fx["mode"], mode);
        assert_eq!(fx["required"], serde_json::json!(["shadows", "triangles"]));
        assert_eq!(fx["general"], mode == "all");
        let renderer = fx["renderer"].as_array().unwrap();
        assert_eq!(renderer.len(), if mode == "all" { 10 } else { 2 });
        assert_eq!(json["settings"]["effects"], mode);
        images.push(std::fs::read(&out).unwrap());
    }
    assert_eq!(images[0], images[1], "auto and all write the same file");
    let st = tracer()
        .arg("render")
        .arg(scene("tetra-s1.nff"))
        .arg("-o")
        .arg(d.join("x.png"))
        .args(["--effects", "some"])
        .output()
        .unwrap();
    assert_eq!(st.status.code(), Some(2));
    assert!(!d.join("x.png").exists());
    let _ = std::fs::remove_dir_all(&d);
}
