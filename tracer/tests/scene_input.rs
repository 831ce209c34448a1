//! Scene input the readers must neither refuse nor lose: degenerate primitives are
//! accepted, counted and never hit; numbers that do not fit the precision are
//! `FILE:LINE` errors; counts in a file cannot make a reader allocate without bound.

use tracer::geometry::AccelOptions;
use tracer::scene::{
    parse_nff, parse_nff_for, parse_obj, ObjOptions, Precision, SceneDesc, SceneError,
};
use tracer::{render, Image, Scene, Settings};

// ---------------------------------------------------------------------------------------
// Degenerate primitives

/// A small scene of every kind: sphere, floor polygon, cone, patch. `{}` marks where the
/// degenerate primitives go, between the sphere and the rest, so that the primitives
/// after them get other ids than without them.
const SCENE: &str = "\
v
from 0 1 6
at 0 0 0
up 0 1 0
angle 40
hither 0.1
resolution 48 36
b 0.1 0.2 0.3
l 4 5 6
l -3 4 2 0.5 0.5 0.4
f 0.9 0.4 0.3 0.7 0.3 30 0 1
s 0 0 0 1
{}
f 0.3 0.8 0.3 0.6 0.2 10 0.2 1.3
p 4
-3 -1 -3
-3 -1 3
3 -1 3
3 -1 -3
c 1.5 -1 0 0.3 1.5 1 0 0.2
pp 3
-2 0 0 0 0 1
-1 0 0 0 0 1
-1.5 1 0 0 0 1
";

/// One degenerate primitive of each kind a real file may hold, with a name for messages.
const DEGENERATE: [(&str, &str); 9] = [
    ("zero-radius sphere", "s 0.5 0.5 0.5 0"),
    ("negative-zero-radius sphere", "s 0 0 0 -0"),
    ("cone with both radii zero", "c 0 0 0 0 0 1 0 0"),
    ("cone with coinciding ends", "c 1 1 1 0.5 1 1 1 0.5"),
    (
        "triangle with one repeated vertex",
        "p 3\n0 0 0\n0 0 0\n0 0 0",
    ),
    ("collinear triangle", "p 3\n0 0 0\n1 1 1\n2 2 2"),
    (
        "collinear quadrilateral",
        "p 4\n-1 0 2\n0 0 2\n1 0 2\n2 0 2",
    ),
    (
        "zero-area patch",
        "pp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n2 0 0 0 0 1",
    ),
    (
        "triangle with two coinciding vertices",
        "p 3\n0 0 1\n1 1 1\n1 1 1",
    ),
];

fn with(degenerate: &str) -> SceneDesc {
    parse_nff(SCENE.replace("{}", degenerate), "t.nff").unwrap_or_else(|e| panic!("{e}"))
}

/// The render at the scene's own resolution, its pixels as bits, and the number of
/// primitives the builder dropped as degenerate.
fn render_bits<T: tracer::Float>(desc: &SceneDesc) -> (Vec<u32>, usize) {
    let scene = Scene::<T>::from_desc(desc, &AccelOptions::default());
    let settings = Settings {
        aa: 2,
        threads: Some(1),
        ..Settings::default()
    };
    let image: Image = render(&scene, &settings);
    let bits = image.pixels.iter().flatten().map(|c| c.to_bits()).collect();
    (bits, scene.geometry.stats().skipped)
}

fn degenerate_primitives_are_never_hit<T: tracer::Float>() {
    let (plain, skipped) = render_bits::<T>(&with(""));
    assert_eq!(skipped, 0);
    // The plain scene shows every kind (the image is not all background).
    assert!(plain.iter().collect::<std::collections::HashSet<_>>().len() > 100);
    for (name, text) in DEGENERATE {
        let desc = with(text);
        assert_eq!(desc.shapes.len(), 5, "{name}: accepted and kept");
        let (image, skipped) = render_bits::<T>(&desc);
        assert_eq!(skipped, 1, "{name}: counted as degenerate");
        assert!(image == plain, "{name}: the render changed");
    }
    let all: Vec<&str> = DEGENERATE.iter().map(|(_, t)| *t).collect();
    let (image, skipped) = render_bits::<T>(&with(&all.join("\n")));
    assert_eq!(skipped, DEGENERATE.len());
    assert!(image == plain, "all together: the render changed");
}

#[test]
fn degenerate_primitives_are_accepted_counted_and_never_hit_f32() {
    degenerate_primitives_are_never_hit::<f32>();
}

#[test]
fn degenerate_primitives_are_accepted_counted_and_never_hit_f64() {
    degenerate_primitives_are_never_hit::<f64>();
}

#[test]
fn degenerate_obj_faces_are_accepted_and_counted() {
    // A quad, a face with a repeated vertex and a collinear face.
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 0\n\
               f 1 2 3 4\nf 1 1 1\nf 1 3 5\n";
    let desc = parse_obj(obj, "t.obj", &ObjOptions::default(), Precision::F32, |_| {
        Err(std::io::ErrorKind::NotFound.into())
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(desc.shapes.len(), 3);
    let scene = Scene::<f32>::from_desc(&desc, &AccelOptions::default());
    assert_eq!(scene.geometry.stats().skipped, 2);
    assert_eq!(scene.geometry.stats().triangles, 2);
}

// ---------------------------------------------------------------------------------------
// Numbers that do not fit the precision

const VIEW: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n";

fn nff_error(text: &str, precision: Precision) -> String {
    let e: SceneError = parse_nff_for(text, "t.nff", precision).expect_err("rejected");
    let shown = e.to_string();
    assert!(!shown.contains('\n'), "{shown:?}");
    shown
}

#[test]
fn f32_overflow_is_an_error_with_file_and_line_and_f64_accepts_it() {
    let cases = [
        ("s 1e39 0 0 1\n", 8, "1e39"),
        ("s 0 0 0 -3.5e38\n", 8, "-3.5e38"),
        ("l 1 1 1\nl 0 0 0 1 1 4e38\n", 9, "4e38"),
        ("b 0 1e40 0\n", 8, "1e40"),
        ("f 1 1 1e39 1 0 1 0 1\ns 0 0 0 1\n", 8, "1e39"),
        ("c 0 0 0 1\n0 1e300 0 1\n", 9, "1e300"),
        ("p 3\n0 0 0\n1 0 0\n0 1 -1e39\n", 11, "-1e39"),
        (
            "pp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1e39\n",
            11,
            "1e39",
        ),
    ];
    for (body, line, token) in cases {
        let text = format!("{VIEW}{body}");
        assert_eq!(
            nff_error(&text, Precision::F32),
            format!(
                "t.nff:{line}: number `{token}` does not fit in f32 (largest magnitude 3.4028235e38)"
            ),
            "{body}"
        );
        parse_nff_for(&text, "t.nff", Precision::F64).unwrap_or_else(|e| panic!("{e}"));
    }
    // In the camera block too.
    let cam = "v\nfrom 0 0 1e39\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n";
    assert!(nff_error(cam, Precision::F32).starts_with("t.nff:2: number `1e39`"));
    // The largest f32 and a value that rounds to it fit.
    let edge = format!("{VIEW}s 3.4028235e38 0 0 1\ns 3.40282356e38 0 0 1\n");
    parse_nff_for(&edge, "t.nff", Precision::F32).unwrap_or_else(|e| panic!("{e}"));
    // What f64 cannot hold stays an error in both.
    let huge = format!("{VIEW}s 1e999 0 0 1\n");
    assert_eq!(
        nff_error(&huge, Precision::F64),
        "t.nff:8: non-finite number `1e999`"
    );
    assert_eq!(
        nff_error(&huge, Precision::F32),
        "t.nff:8: non-finite number `1e999`"
    );
}

#[test]
fn f32_overflow_in_obj_and_mtl_names_file_and_line() {
    let none = |_: &str| -> std::io::Result<Vec<u8>> { Err(std::io::ErrorKind::NotFound.into()) };
    let parse = |text: &str, p: Precision| {
        parse_obj(text, "t.obj", &ObjOptions::default(), p, none).map(|_| ())
    };
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let big = format!("{tri}v 0 2e39 0\n");
    assert_eq!(
        parse(&big, Precision::F32).unwrap_err().to_string(),
        "t.obj:5: number `2e39` does not fit in f32 (largest magnitude 3.4028235e38)"
    );
    parse(&big, Precision::F64).unwrap();
    // Fits before dividing by w, not after.
    let w = format!("{tri}v 3e38 0 0 0.5\n");
    assert_eq!(
        parse(&w, Precision::F32).unwrap_err().to_string(),
        "t.obj:5: vertex does not fit in f32 after dividing by `w`"
    );
    parse(&w, Precision::F64).unwrap();
    // A material library's line.
    let obj = format!("mtllib m.mtl\n{tri}");
    let mtl = |_: &str| Ok(b"newmtl a\nKd 1 1 1\nNs 1e39\n".to_vec());
    let err = parse_obj(&obj, "t.obj", &ObjOptions::default(), Precision::F32, mtl);
    assert_eq!(
        err.unwrap_err().to_string(),
        "m.mtl:3: number `1e39` does not fit in f32 (largest magnitude 3.4028235e38)"
    );
    parse_obj(&obj, "t.obj", &ObjOptions::default(), Precision::F64, mtl).unwrap();
}

// ---------------------------------------------------------------------------------------
// Counts and sizes

#[test]
fn huge_counts_in_tiny_files_are_one_line_errors() {
    let start = std::time::Instant::now();
    assert_eq!(
        nff_error(&format!("{VIEW}p 65536\n0 0 0\n"), Precision::F64),
        "t.nff:8: polygon declares 65536 vertices but the file ends after 1"
    );
    assert_eq!(
        nff_error(&format!("{VIEW}pp 65537\n"), Precision::F64),
        "t.nff:8: patch vertex count 65537 is too large (the limit is 65536)"
    );
    assert_eq!(
        nff_error(&format!("{VIEW}p 4294967296\n0 0 0\n"), Precision::F64),
        "t.nff:8: polygon vertex count 4294967296 is too large (the limit is 65536)"
    );
    // An OBJ face of more than the limit: refused as soon as the limit is passed.
    let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
    for _ in 0..(65536 / 3 + 1) {
        obj.push_str(" 1 2 3");
    }
    obj.push('\n');
    let none = |_: &str| -> std::io::Result<Vec<u8>> { Err(std::io::ErrorKind::NotFound.into()) };
    let err = parse_obj(&obj, "t.obj", &ObjOptions::default(), Precision::F64, none);
    assert_eq!(
        err.unwrap_err().to_string(),
        "t.obj:4: face has more than 65536 vertices"
    );
    assert!(start.elapsed().as_secs() < 5, "{:?}", start.elapsed());
}
