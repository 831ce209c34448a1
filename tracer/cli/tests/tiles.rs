//! Tiles and frames: `tracer render --tile I/N | --pixel-bounds | --crop` and `tracer
//! merge` give the one-process render byte for byte; incomplete, duplicate, overlapping
//! and foreign tiles are refused with nothing written; frames of a camera path.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use tracer_cli::tiles::{read_exr, read_header};

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name)
}

fn tmpdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracer-tiles-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn tracer(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_tracer"));
    c.args(args)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("SLURM_ARRAY_TASK_COUNT")
        .env_remove("JOB_COMPLETION_INDEX");
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

fn ok(args: &[&str]) {
    let out = tracer(args, &[]);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Exit 2 with one line on stderr that contains `needle`.
fn refused(args: &[&str], needle: &str) {
    let out = tracer(args, &[]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(needle), "{args:?}: {err}");
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A tile's pixels as bits (`to_bits`: -0 and +0 differ).
fn bits(p: &Path) -> Vec<u32> {
    let image = read_exr(p).unwrap();
    image.pixels.iter().flatten().map(|c| c.to_bits()).collect()
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

const SIZE: [&str; 4] = ["--width", "61", "--height", "47"];

#[test]
fn tiles_merge_to_the_full_render_byte_for_byte() {
    let d = tmpdir("merge");
    let sc = scene("showcase.nff");
    for (extra, tag) in [(&[][..], "plain"), (&["--aa", "2", "--precision", "f64"][..], "aa2"), (&["--spd"][..], "spd")] {
        let full_png = d.join(format!("{tag}-full.png"));
        let full_pfm = d.join(format!("{tag}-full.pfm"));
        let base: Vec<&str> = [s(&sc)].into_iter().chain(SIZE).chain(extra.iter().copied()).collect();
        for out in [&full_png, &full_pfm] {
            let mut a = vec!["render"];
            a.extend(&base);
            a.extend(["-o", s(out)]);
            ok(&a);
        }
        let pattern = d.join(format!("{tag}-tile-%d.exr"));
        for i in 0..5 {
            let spec = format!("{i}/5");
            let mut a = vec!["render"];
            a.extend(&base);
            a.extend(["--tile", &spec, "-o", s(&pattern)]);
            ok(&a);
        }
        let tiles: Vec<PathBuf> = (0..5).map(|i| d.join(format!("{tag}-tile-{i}.exr"))).collect();
        for (out, full) in [("m.png", &full_png), ("m.pfm", &full_pfm)] {
            let merged = d.join(format!("{tag}-{out}"));
            let mut a = vec!["merge"];
            a.extend(tiles.iter().map(|p| s(p)));
            a.extend(["-o", s(&merged)]);
            ok(&a);
            assert_eq!(bytes(&merged), bytes(full), "{tag} {out}");
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn pixel_bounds_and_crop_windows_fit_together() {
    let d = tmpdir("bounds");
    let sc = scene("balls-s1.nff");
    let full = d.join("full.pfm");
    let mut a = vec!["render", s(&sc)];
    a.extend(SIZE);
    a.extend(["-o", s(&full)]);
    ok(&a);
    // Left part by pixel bounds, right part by a crop window: ceil(0.5 * 61) = 31.
    let left = d.join("left.exr");
    let right = d.join("right.exr");
    for (flag, value, out) in [
        ("--pixel-bounds", "0,31,0,47", &left),
        ("--crop", "0.5,1,0,1", &right),
    ] {
        let mut a = vec!["render", s(&sc)];
        a.extend(SIZE);
        a.extend([flag, value, "-o", s(out)]);
        ok(&a);
    }
    let merged = d.join("merged.pfm");
    ok(&["merge", s(&left), s(&right), "-o", s(&merged)]);
    assert_eq!(bytes(&merged), bytes(&full));
    // A .pfm of pixel bounds holds just those pixels: 31 x 47.
    let part = d.join("part.pfm");
    let mut a = vec!["render", s(&sc)];
    a.extend(SIZE);
    a.extend(["--pixel-bounds", "0,31,0,47", "-o", s(&part)]);
    ok(&a);
    assert!(bytes(&part).starts_with(b"PF\n31 47\n"));
    // Bounds outside the image, or empty, are refused before rendering.
    let mut a = vec!["render", s(&sc)];
    a.extend(SIZE);
    a.extend(["--pixel-bounds", "0,62,0,47", "-o", s(&part)]);
    refused(&a, "outside the 61 x 47 image");
    refused(
        &["render", s(&sc), "--pixel-bounds", "5,5,0,1", "-o", s(&part)],
        "no pixel",
    );
    refused(
        &["render", s(&sc), "--crop", "0.5,0.2,0,1", "-o", s(&part)],
        "X0 < X1",
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn merge_refuses_missing_duplicate_overlapping_and_foreign_tiles() {
    let d = tmpdir("refuse");
    let sc = scene("tetra-s1.nff");
    let render = |extra: &[&str], out: &Path| {
        let mut a = vec!["render", s(&sc)];
        a.extend(SIZE);
        a.extend(extra);
        a.extend(["-o", s(out)]);
        ok(&a);
    };
    let t: Vec<PathBuf> = (0..4).map(|i| d.join(format!("t{i}.exr"))).collect();
    for (i, p) in t.iter().enumerate() {
        render(&["--tile", &format!("{i}/4")], p);
    }
    let out = d.join("out.png");
    // Tile 2 missing: named, nothing written; --missing lists it for sbatch --array.
    refused(&["merge", s(&t[0]), s(&t[1]), s(&t[3]), "-o", s(&out)], "tiles 2 of 4 are missing");
    assert!(!out.exists());
    let listed = tracer(&["merge", "--missing", s(&t[0]), s(&t[3])], &[]);
    assert!(listed.status.success());
    assert_eq!(String::from_utf8_lossy(&listed.stdout), "1,2\n");
    let all = tracer(&["merge", "--missing", s(&t[0]), s(&t[1]), s(&t[2]), s(&t[3])], &[]);
    assert!(all.status.success() && all.stdout.is_empty());
    // The same tile twice.
    refused(&["merge", s(&t[0]), s(&t[1]), s(&t[2]), s(&t[3]), s(&t[1]), "-o", s(&out)], "tile 1 given twice");
    // A tile of another render (other depth): named.
    let foreign = d.join("foreign.exr");
    render(&["--tile", "2/4", "--depth", "2"], &foreign);
    refused(&["merge", s(&t[0]), s(&t[1]), s(&foreign), s(&t[3]), "-o", s(&out)], "foreign.exr is not a tile of the render");
    // Overlapping bounds.
    let (a, b) = (d.join("a.exr"), d.join("b.exr"));
    render(&["--pixel-bounds", "0,40,0,47"], &a);
    render(&["--pixel-bounds", "30,61,0,47"], &b);
    refused(&["merge", s(&a), s(&b), "-o", s(&out)], "overlap");
    // Not covering the image.
    refused(&["merge", s(&a), "-o", s(&out)], "cover");
    // Not a tile at all.
    let png = d.join("x.png");
    render(&[], &png);
    refused(&["merge", s(&png), "-o", s(&out)], "not a readable OpenEXR file");
    assert!(!out.exists());
    // A tile must be OpenEXR.
    let mut args = vec!["render", s(&sc), "--tile", "0/4", "-o"];
    args.push(s(&png));
    refused(&args, "OpenEXR");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn tile_auto_reads_the_scheduler_environment() {
    let d = tmpdir("auto");
    let sc = scene("balls-s1.nff");
    let by_index = d.join("i.exr");
    let mut a = vec!["render", s(&sc)];
    a.extend(SIZE);
    a.extend(["--tile", "2/3", "-o", s(&by_index)]);
    ok(&a);
    for (spec, env) in [
        ("auto", vec![("SLURM_ARRAY_TASK_ID", "2"), ("SLURM_ARRAY_TASK_COUNT", "3")]),
        ("auto/3", vec![("SLURM_ARRAY_TASK_ID", "2"), ("SLURM_ARRAY_TASK_COUNT", "1")]),
        ("auto/3", vec![("JOB_COMPLETION_INDEX", "2")]),
    ] {
        let out = d.join("auto.exr");
        let mut a = vec!["render", s(&sc)];
        a.extend(SIZE);
        a.extend(["--tile", spec, "-o", s(&out)]);
        let r = tracer(&a, &env);
        assert!(r.status.success(), "{spec} {env:?}: {}", String::from_utf8_lossy(&r.stderr));
        // The same tile: place, digest and pixels (the header's times differ per run).
        let (a, b) = (read_header(&out).unwrap(), read_header(&by_index).unwrap());
        assert_eq!((a.bounds, a.tile, &a.digest), (b.bounds, b.tile, &b.digest), "{spec}");
        assert!(bits(&out) == bits(&by_index), "{spec}");
    }
    let r = tracer(&["render", s(&sc), "--tile", "auto", "-o", s(&by_index)], &[]);
    assert_eq!(r.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&r.stderr).contains("SLURM_ARRAY_TASK_ID"));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn frames_of_a_path_render_alone_or_in_a_range() {
    let d = tmpdir("frames");
    let sc = scene("balls-s1.nff");
    let path = d.join("path.txt");
    std::fs::write(&path, "move 0.5\nyaw 10\nstrafe -0.3\npitch -5\n").unwrap();
    let range = d.join("r-%04d.png");
    let mut a = vec!["render", s(&sc)];
    a.extend(SIZE);
    a.extend(["--script", s(&path), "--frame", "1-3", "-o", s(&range)]);
    ok(&a);
    for k in 1..=3 {
        let one = d.join(format!("one-{k}.png"));
        let frame = k.to_string();
        let mut a = vec!["render", s(&sc)];
        a.extend(SIZE);
        a.extend(["--script", s(&path), "--frame", &frame, "-o", s(&one)]);
        ok(&a);
        assert_eq!(bytes(&d.join(format!("r-{k:04}.png"))), bytes(&one), "frame {k}");
    }
    assert!(!d.join("r-0000.png").exists());
    assert_ne!(bytes(&d.join("r-0001.png")), bytes(&d.join("r-0002.png")));
    // Frames the path does not have, a range without a number in the name, and a
    // path that sets viewer knobs are refused.
    let out = d.join("x.png");
    refused(&["render", s(&sc), "--script", s(&path), "--frame", "4", "-o", s(&out)], "frames 0 to 3");
    refused(&["render", s(&sc), "--script", s(&path), "--frame", "0-1", "-o", s(&out)], "%04d");
    let knob = d.join("knob.txt");
    std::fs::write(&knob, "move 1\nset aa 2\n").unwrap();
    refused(&["render", s(&sc), "--script", s(&knob), "--frame", "0", "-o", s(&out)], "line 2 sets a viewer knob");
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}
