//! `tracer render` before and after the rays: outputs and memory checked first, options
//! that take effect or are refused, what is printed with and without a terminal, and the
//! output formats (OpenEXR, tagged PNG).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn tracer() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tracer"))
}

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name)
}

fn tmpdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracer-checks-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `tracer render SCENE -o OUT ARGS...`.
fn render(scene: &Path, out: &Path, args: &[&str]) -> Output {
    tracer()
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit status 2, exactly one line on stderr (returned), no panic.
fn refused(o: &Output) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", stderr(o));
}

/// The files in `dir` (names).
fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A small NFF scene of `w` x `h` pixels.
fn small_nff(dir: &Path, w: u32, h: u32) -> PathBuf {
    let p = dir.join(format!("small-{w}x{h}.nff"));
    std::fs::write(
        &p,
        format!(
            "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution {w} {h}\n\
             b 0.1 0.2 0.3\nl 4 4 4\nf 1 0.5 0.2 0.7 0.3 20 0 1\ns 0 0 0 1\ns 1.5 0 -1 0.5\n"
        ),
    )
    .unwrap();
    p
}

fn stats_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

// 1. Outputs checked before the first ray, written together or not at all.

#[test]
fn output_in_a_missing_directory_is_refused_before_the_scene_is_read() {
    let d = tmpdir("nodir");
    // The scene does not exist either: the output is checked first.
    let o = render(&d.join("missing.nff"), &d.join("nodir/out.png"), &[]);
    let err = refused(&o);
    assert!(err.contains("nodir"), "{err}");
    assert!(err.contains("does not exist"), "{err}");
    assert!(files(&d).is_empty(), "{:?}", files(&d));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn stats_in_a_missing_directory_leaves_no_image() {
    let d = tmpdir("nostats");
    let png = d.join("out.png");
    let o = render(
        &scene("tetra-s1.nff"),
        &png,
        &["--width", "8", "--stats", "/missing/dir/s.json"],
    );
    let err = refused(&o);
    assert!(err.starts_with("/missing/dir/s.json:"), "{err}");
    assert!(files(&d).is_empty(), "{:?}", files(&d));
    let _ = std::fs::remove_dir_all(&d);
}

/// A render ended by a signal (Ctrl-C, `kill`, a batch system's time limit) after its
/// outputs were staged leaves neither output nor temporary file, and its exit status
/// names the signal.
#[test]
#[cfg(unix)]
fn a_signal_during_a_render_leaves_no_file() {
    use std::os::unix::process::ExitStatusExt;
    use std::time::{Duration, Instant};
    for (signal, name) in [(15, "TERM"), (2, "INT"), (1, "HUP")] {
        let dir = tmpdir(&format!("signal-{name}"));
        // Minutes of work on one thread: the signal arrives long before the end.
        let mut child = tracer()
            .arg("render")
            .arg(scene("showcase.nff"))
            .arg("-o")
            .arg(dir.join("out.png"))
            .arg("--stats")
            .arg(dir.join("s.json"))
            .args(["--width", "4096", "--height", "4096", "--aa", "4", "--threads", "1"])
            .spawn()
            .unwrap();
        // Both outputs are staged (as hidden temporary files) before the first ray.
        let start = Instant::now();
        while files(&dir).len() < 2 {
            assert!(start.elapsed() < Duration::from_secs(120), "{name}: nothing staged");
            assert!(child.try_wait().unwrap().is_none(), "{name}: ended early");
            std::thread::sleep(Duration::from_millis(20));
        }
        assert!(files(&dir).iter().all(|f| f.starts_with('.') && f.ends_with(".tmp")));
        let sent = Command::new("kill")
            .arg(format!("-{name}"))
            .arg(child.id().to_string())
            .status()
            .unwrap();
        assert!(sent.success());
        let status = child.wait().unwrap();
        assert_eq!(status.signal(), Some(signal), "{name}: {status:?}");
        assert_eq!(files(&dir), Vec::<String>::new(), "{name}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn unknown_formats_and_directories_are_refused() {
    let d = tmpdir("formats");
    let tetra = scene("tetra-s1.nff");
    let err = refused(&render(&tetra, &d.join("x.jpg"), &[]));
    assert!(err.contains(".png, .pfm or .exr"), "{err}");
    let err = refused(&render(
        &tetra,
        &d.join("x.png"),
        &["--stats", d.join("s.txt").to_str().unwrap()],
    ));
    assert!(err.contains(".json"), "{err}");
    let dir_png = d.join("dir.png");
    std::fs::create_dir(&dir_png).unwrap();
    refused(&render(&tetra, &dir_png, &[]));
    let same = d.join("same.json");
    let o = tracer()
        .arg("render")
        .arg(&tetra)
        .arg("-o")
        .arg(d.join("x.png"))
        .arg("--stats")
        .arg(&same)
        .output()
        .unwrap();
    ok(&o);
    assert_eq!(files(&d), ["dir.png", "same.json", "x.png"]);
    let _ = std::fs::remove_dir_all(&d);
}

// 2. Memory.

#[test]
fn a_render_too_large_for_memory_is_refused() {
    let d = tmpdir("memory");
    let out = d.join("huge.png");
    let o = render(
        &scene("tetra-s1.nff"),
        &out,
        &[
            "--width",
            "65536",
            "--height",
            "65536",
            "--precision",
            "f64",
            "--aa",
            "2",
        ],
    );
    let err = refused(&o);
    assert!(err.contains("65536x65536"), "{err}");
    assert!(err.contains("needs about"), "{err}");
    assert!(err.contains("available"), "{err}");
    assert!(files(&d).is_empty(), "{:?}", files(&d));
    let _ = std::fs::remove_dir_all(&d);
}

// 3. Options take effect or are refused.

#[test]
fn camera_options_override_an_nff_camera() {
    let d = tmpdir("camera");
    let tetra = scene("tetra-s1.nff");
    let (a, b) = (d.join("a.pfm"), d.join("b.pfm"));
    let stats = d.join("b.json");
    ok(&render(&tetra, &a, &["--width", "16"]));
    ok(&render(
        &tetra,
        &b,
        &[
            "--width",
            "16",
            "--from",
            "1,-3,2",
            "--angle",
            "30",
            "--stats",
            stats.to_str().unwrap(),
        ],
    ));
    assert_ne!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let json = stats_json(&stats);
    assert_eq!(json["camera"]["from"], serde_json::json!([1.0, -3.0, 2.0]));
    assert_eq!(json["camera"]["angle"], 30.0);
    assert_eq!(
        json["camera"]["from_command_line"],
        serde_json::json!(["from", "angle"])
    );
    let err = refused(&render(&tetra, &d.join("c.png"), &["--angle", "200"]));
    assert!(err.contains("--angle"), "{err}");
    let err = refused(&render(
        &tetra,
        &d.join("c.png"),
        &["--from", "0,0,0", "--at", "0,0,0"],
    ));
    assert!(err.starts_with(tetra.to_str().unwrap()), "{err}");
    assert!(!d.join("c.png").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn spd_refuses_explicit_aa_depth_and_threshold() {
    let d = tmpdir("spd");
    let tetra = scene("tetra-s1.nff");
    for extra in [["--aa", "2"], ["--depth", "3"], ["--threshold", "0.1"]] {
        let mut args = vec!["--spd", "--width", "8", "--height", "8"];
        args.extend(extra);
        let err = refused(&render(&tetra, &d.join("x.png"), &args));
        assert!(err.contains(&extra[0][2..]), "{err}");
    }
    // The ray counts are --spd's output: printed without a terminal too, and with --quiet.
    for quiet in [&[][..], &["--quiet"][..]] {
        let mut args = vec!["--spd", "--width", "8", "--height", "8"];
        args.extend(quiet);
        let o = render(&tetra, &d.join("x.png"), &args);
        ok(&o);
        let err = stderr(&o);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with("rays: eye 81 "), "{err}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn options_that_would_be_ignored_are_refused() {
    let d = tmpdir("ignored");
    let tetra = scene("tetra-s1.nff");
    let err = refused(&render(
        &tetra,
        &d.join("x.png"),
        &["--packets", "off", "--isa", "sse2"],
    ));
    assert!(err.contains("--isa sse2 has no effect"), "{err}");
    let err = refused(&render(
        &tetra,
        &d.join("x.png"),
        &["--packets", "on", "--precision", "f64"],
    ));
    assert!(err.contains("--packets on has no effect with"), "{err}");
    let err = refused(&render(&tetra, &d.join("x.png"), &["--tile-size", "8"]));
    assert!(err.contains("--tile-size 8 has no effect without --scheduler tiles"), "{err}");
    let err = refused(&render(
        &tetra,
        &d.join("x.png"),
        &["--scheduler", "static", "--tile-size", "8"],
    ));
    assert!(err.contains("--tile-size"), "{err}");
    let err = refused(&render(&tetra, &d.join("x.png"), &["--no-bvh", "--binary-bvh"]));
    assert!(err.contains("--binary-bvh") && err.contains("--no-bvh"), "{err}");
    assert!(files(&d).is_empty());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn one_side_keeps_the_aspect_ratio() {
    let d = tmpdir("aspect");
    let nff = small_nff(&d, 64, 48);
    let out = d.join("a.pfm");
    ok(&render(&nff, &out, &["--width", "40"]));
    assert!(std::fs::read(&out).unwrap().starts_with(b"PF\n40 30\n"));
    ok(&render(&nff, &out, &["--height", "3"]));
    assert!(std::fs::read(&out).unwrap().starts_with(b"PF\n4 3\n"));
    ok(&render(&nff, &out, &["--width", "5", "--height", "7"]));
    assert!(std::fs::read(&out).unwrap().starts_with(b"PF\n5 7\n"));
    let help = tracer().args(["render", "--help"]).output().unwrap();
    let help = String::from_utf8(help.stdout).unwrap();
    assert!(help.contains("aspect ratio"), "{help}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_z_up_obj_gets_a_warning() {
    let d = tmpdir("zup");
    let obj = d.join("tower.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 10\nf 1 2 3\nf 1 2 4\n",
    )
    .unwrap();
    let out = d.join("t.png");
    let o = render(&obj, &out, &["--width", "8", "--quiet"]);
    ok(&o);
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("warning") && err.contains("--up 0,0,1"), "{err}");
    let o = render(&obj, &out, &["--width", "8", "--up", "0,0,1"]);
    ok(&o);
    assert_eq!(stderr(&o), "");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn negative_numbers_get_our_message() {
    let d = tmpdir("negative");
    for flag in ["--width", "--height", "--aa", "--depth", "--threads"] {
        let err = refused(&render(&scene("tetra-s1.nff"), &d.join("x.png"), &[flag, "-5"]));
        assert!(err.contains(flag), "{err}");
        assert!(err.contains("expected a whole number from 1 to"), "{err}");
        assert!(!err.contains("-- -5"), "{err}");
    }
    let err = refused(&render(
        &scene("tetra-s1.nff"),
        &d.join("x.png"),
        &["--threshold", "-0.5"],
    ));
    assert!(err.contains("threshold must be in [0, 1]"), "{err}");
    assert!(files(&d).is_empty());
    let _ = std::fs::remove_dir_all(&d);
}

// 4. What is printed.

#[test]
fn without_a_terminal_nothing_is_printed_unless_asked() {
    let d = tmpdir("feedback");
    let out = d.join("x.png");
    let tetra = scene("tetra-s1.nff");
    let args = ["--width", "16"];
    let o = render(&tetra, &out, &args);
    ok(&o);
    assert_eq!(stderr(&o), "");
    let o = render(&tetra, &out, &["--width", "16", "--quiet"]);
    ok(&o);
    assert_eq!(stderr(&o), "");
    let o = render(&tetra, &out, &["--width", "16", "--progress"]);
    ok(&o);
    let err = stderr(&o);
    for phase in ["parsing", "building", "tracing", "traced", "writing"] {
        assert!(err.contains(&format!("s: {phase}")), "{phase}: {err}");
    }
    let last = err.lines().last().unwrap();
    assert!(last.starts_with(&format!("{}: 16x16, ", out.display())), "{last}");
    assert!(last.ends_with(" Mrays/s"), "{last}");
    refused(&render(&tetra, &out, &["--quiet", "--progress"]));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bench_explains_its_columns() {
    let o = tracer()
        .arg("bench")
        .arg(scene("tetra-s1.nff"))
        .args(["--width", "8", "--height", "8", "--runs", "1", "--packets", "off"])
        .output()
        .unwrap();
    ok(&o);
    let out = String::from_utf8(o.stdout).unwrap();
    let legend = out
        .lines()
        .find(|l| l.starts_with("Columns: "))
        .unwrap_or_else(|| panic!("no legend: {out}"));
    for col in ["prims", "build ms", "B/prim", "frame ms", "POV-Ray / tracer"] {
        assert!(legend.contains(&format!("{col} =")), "{col}: {legend}");
    }
}

// 5. Output formats.

/// The linear floats of a PFM file, top row first.
fn pfm_pixels(bytes: &[u8]) -> (usize, usize, Vec<[f32; 3]>) {
    let text = String::from_utf8_lossy(&bytes[..32]).into_owned();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("PF"));
    let mut wh = lines.next().unwrap().split(' ').map(|n| n.parse::<usize>().unwrap());
    let (w, h) = (wh.next().unwrap(), wh.next().unwrap());
    let header = format!("PF\n{w} {h}\n-1.0\n").len();
    let floats: Vec<f32> = bytes[header..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let rows: Vec<&[f32]> = floats.chunks_exact(w * 3).collect();
    let pixels = rows
        .iter()
        .rev()
        .flat_map(|r| r.chunks_exact(3).map(|c| [c[0], c[1], c[2]]))
        .collect();
    (w, h, pixels)
}

#[test]
fn exr_holds_the_pfm_floats_bit_for_bit() {
    let d = tmpdir("exr");
    let (pfm, exr) = (d.join("a.pfm"), d.join("a.exr"));
    let args = ["--width", "24", "--height", "16", "--aa", "2"];
    ok(&render(&scene("balls-s1.nff"), &pfm, &args));
    ok(&render(&scene("balls-s1.nff"), &exr, &args));
    let (w, h, want) = pfm_pixels(&std::fs::read(&pfm).unwrap());
    let image = exr::prelude::read_first_rgba_layer_from_file(
        &exr,
        |res, _| vec![[0f32; 3]; res.width() * res.height()],
        move |px: &mut Vec<[f32; 3]>, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            px[pos.y() * w + pos.x()] = [r, g, b];
        },
    )
    .unwrap();
    let size = image.layer_data.size;
    assert_eq!((size.width(), size.height()), (w, h));
    let bits = |p: &[[f32; 3]]| -> Vec<u32> { p.iter().flatten().map(|c| c.to_bits()).collect() };
    assert_eq!(bits(&image.layer_data.channel_data.pixels), bits(&want));
    assert!(want.iter().flatten().any(|&c| c > 0.0 && c < 1.0));
    let err = refused(&render(&scene("tetra-s1.nff"), &d.join("b.exr"), &["--srgb"]));
    assert!(err.contains("--srgb"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

/// The chunks of a PNG file: type and data.
fn png_chunks(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let mut out = Vec::new();
    let mut i = 8;
    while i + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap()) as usize;
        let kind = String::from_utf8_lossy(&bytes[i + 4..i + 8]).into_owned();
        out.push((kind, bytes[i + 8..i + 8 + len].to_vec()));
        i += 12 + len;
    }
    out
}

#[test]
fn png_is_tagged_linear_or_srgb() {
    let d = tmpdir("png");
    let nff = small_nff(&d, 20, 10);
    let (pfm, lin, srgb) = (d.join("a.pfm"), d.join("lin.png"), d.join("srgb.png"));
    ok(&render(&nff, &pfm, &[]));
    ok(&render(&nff, &lin, &[]));
    ok(&render(&nff, &srgb, &["--srgb"]));
    let (_, _, floats) = pfm_pixels(&std::fs::read(&pfm).unwrap());
    let chunk = |path: &Path, kind: &str| {
        png_chunks(&std::fs::read(path).unwrap())
            .into_iter()
            .find(|(k, _)| k == kind)
            .map(|(_, data)| data)
    };
    // Linear values: gAMA 1.0 (100000), no sRGB chunk.
    assert_eq!(chunk(&lin, "gAMA"), Some(100_000u32.to_be_bytes().to_vec()));
    assert_eq!(chunk(&lin, "sRGB"), None);
    // sRGB-encoded values: an sRGB chunk (perceptual intent) and gAMA 1/2.2.
    assert_eq!(chunk(&srgb, "sRGB"), Some(vec![0]));
    assert_eq!(chunk(&srgb, "gAMA"), Some(45_455u32.to_be_bytes().to_vec()));
    let byte = |c: f32| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    let lin = tracer::Image::read_png(&lin).unwrap();
    let srgb = tracer::Image::read_png(&srgb).unwrap();
    let mut brighter = 0;
    for ((f, l), s) in floats.iter().zip(&lin.pixels).zip(&srgb.pixels) {
        for k in 0..3 {
            assert_eq!(byte(l[k]), byte(f[k]));
            assert_eq!(byte(s[k]), byte(tracer::image::srgb_encode(f[k].clamp(0.0, 1.0))));
            brighter += usize::from(s[k] > l[k]);
        }
    }
    assert!(brighter > 0);
    let _ = std::fs::remove_dir_all(&d);
}
