//! OBJ reader: geometry, MTL materials, the default framing and its overrides, and the
//! messages for malformed files. Each test writes its files to a temporary directory.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use tracer::scene::{
    load, load_obj, LightDesc, ObjOptions, SceneDesc, Shape, ShapeCounts, DEFAULT_MATERIAL,
};

/// A directory of its own under the system temporary directory, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        // Unique per call: tests run in parallel threads of one process.
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let name = format!("tracer-{tag}-{}-{n}", std::process::id());
        let dir = std::env::temp_dir().join(name);
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    /// Writes `name` and returns its path.
    fn file(&self, name: &str, contents: &str) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, contents).unwrap();
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A unit cube with a smooth-shaded top, three materials (one unknown) and a comment.
const CUBE: &str = "\
# unit cube
mtllib cube.mtl
o cube
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
vn 0 0 1
vn 0.1 0 1
vt 0 0
vt 1 0
vt 1 1
f 1 4 3 2
usemtl red
f 1 2 6 5
f 2/2 3/3 7/3 6/1
usemtl glass
f 5/1/1 6/2/2 7/3/1 8//2
usemtl nowhere
f 3 4 8 7
usemtl red
f -8 -4 -1 -5
";

const CUBE_MTL: &str = "\
# two materials
newmtl red
Kd 0.9 0.1 0.1
Ks 0.5 0.5 0.5
Ns 50
illum 2

newmtl glass
Kd 1 1 1
Ks 0.2 0.2 0.2
Ns 300
Ni 1.5
d 0.1
illum 7
";

fn write_cube(dir: &TempDir) -> PathBuf {
    dir.file("cube.mtl", CUBE_MTL);
    dir.file("cube.obj", CUBE)
}

#[test]
fn cube_geometry_and_materials() {
    let dir = TempDir::new("obj-cube");
    let scene = load_obj(&write_cube(&dir), &ObjOptions::default()).unwrap();
    let counts = scene.shape_counts();
    let want = ShapeCounts {
        polygons: 5,
        patches: 1,
        ..ShapeCounts::default()
    };
    assert_eq!(counts, want);
    let lines: Vec<u32> = scene.shapes.iter().map(|s| s.line).collect();
    assert_eq!(lines, vec![17, 19, 20, 22, 24, 26]);
    // Quads stay quads.
    assert_eq!(
        scene.shapes[0].shape,
        Shape::Polygon {
            vertices: vec![[0.0; 3], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 0.0]]
        }
    );
    // Every corner of the top face has a normal; `8//2` mixes forms.
    assert_eq!(
        scene.shapes[3].shape,
        Shape::Patch {
            vertices: vec![
                [0.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
                [0.0, 1.0, 1.0]
            ],
            normals: vec![
                [0.0, 0.0, 1.0],
                [0.1, 0.0, 1.0],
                [0.0, 0.0, 1.0],
                [0.1, 0.0, 1.0]
            ],
        }
    );
    // Negative indices count back from the last vertex read.
    assert_eq!(
        scene.shapes[5].shape,
        Shape::Polygon {
            vertices: vec![[0.0; 3], [0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [0.0, 1.0, 0.0]]
        }
    );

    // Materials: the library's two in file order, then the default where first needed.
    assert_eq!(scene.materials.len(), 3);
    let red = &scene.materials[0];
    assert_eq!(red.color, [0.9, 0.1, 0.1]);
    assert_eq!(
        (red.kd, red.ks, red.shine, red.t, red.ior),
        (1.0, 0.0, 50.0, 0.0, 1.0)
    );
    let glass = &scene.materials[1];
    assert_eq!((glass.shine, glass.ior), (300.0, 1.5));
    // ks is the mean of Ks; t = 1 - d; kd = 1 - ks - t clamped at 0.
    assert!((glass.ks - 0.2).abs() < 1e-12 && (glass.t - 0.9).abs() < 1e-12);
    assert_eq!(glass.kd, 0.0);
    assert_eq!(scene.materials[2], DEFAULT_MATERIAL);
    let used: Vec<u32> = scene.shapes.iter().map(|s| s.material).collect();
    assert_eq!(used, vec![2, 0, 0, 1, 2, 0]);
}

#[test]
fn default_framing_and_light() {
    let dir = TempDir::new("obj-frame");
    let scene = load_obj(&write_cube(&dir), &ObjOptions::default()).unwrap();
    let cam = &scene.camera;
    assert_eq!(cam.at, [0.5; 3]);
    assert_eq!(cam.up, [0.0, 1.0, 0.0]);
    assert_eq!((cam.angle_deg, cam.resolution), (45.0, (512, 512)));
    // On the (1, 1, 1) diagonal, with the bounding sphere (radius sqrt(3)/2) just inside
    // the 22.5 degree half-angle.
    let d: Vec<f64> = (0..3).map(|k| cam.from[k] - cam.at[k]).collect();
    assert!((d[0] - d[1]).abs() < 1e-12 && (d[1] - d[2]).abs() < 1e-12 && d[0] > 0.0);
    let dist = (d[0] * d[0] * 3.0).sqrt();
    let want = (3f64.sqrt() / 2.0) / 22.5f64.to_radians().sin();
    assert!((dist - want).abs() < 1e-9, "{dist} vs {want}");
    assert_eq!(
        scene.lights,
        vec![LightDesc {
            position: cam.from,
            color: None
        }]
    );
    assert_eq!(scene.background, [0.0; 3]);
}

#[test]
fn options_override_the_framing() {
    let dir = TempDir::new("obj-options");
    let light = LightDesc {
        position: [9.0, 9.0, 9.0],
        color: Some([1.0, 0.5, 0.5]),
    };
    let options = ObjOptions {
        from: Some([0.5, 0.5, 10.0]),
        at: None,
        up: Some([1.0, 0.0, 0.0]),
        angle: Some(30.0),
        resolution: Some((320, 200)),
        light: Some(light.clone()),
    };
    let scene = load_obj(&write_cube(&dir), &options).unwrap();
    let cam = &scene.camera;
    assert_eq!(
        (cam.from, cam.at, cam.up),
        ([0.5, 0.5, 10.0], [0.5; 3], [1.0, 0.0, 0.0])
    );
    assert_eq!((cam.angle_deg, cam.resolution), (30.0, (320, 200)));
    assert_eq!(scene.lights, vec![light]);

    let bad = ObjOptions {
        up: Some([1.0, 1.0, 1.0]),
        ..ObjOptions::default()
    };
    let e = load_obj(&dir.0.join("cube.obj"), &bad).unwrap_err();
    assert_eq!(e.line(), None);
    assert!(e
        .to_string()
        .ends_with("cube.obj: camera `up` is parallel to the view direction"));
}

#[test]
fn load_dispatches_on_the_extension_and_reads_gzip() {
    let dir = TempDir::new("obj-dispatch");
    let path = write_cube(&dir);
    let plain = load(&path).unwrap();
    assert_eq!(plain, load_obj(&path, &ObjOptions::default()).unwrap());
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    enc.write_all(CUBE.as_bytes()).unwrap();
    std::fs::write(dir.0.join("cube.OBJ.gz"), enc.finish().unwrap()).unwrap();
    let packed = load(&dir.0.join("cube.OBJ.gz")).unwrap();
    assert_eq!(packed, plain);
}

#[test]
fn files_without_a_material_library_use_the_default() {
    // As the SPD OBJ exports: `usemtl` without any `mtllib`.
    let dir = TempDir::new("obj-nomtl");
    let path = dir.file(
        "tri.obj",
        "usemtl txt001\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 3 2 1\n",
    );
    let scene: SceneDesc = load_obj(&path, &ObjOptions::default()).unwrap();
    assert_eq!(scene.materials, vec![DEFAULT_MATERIAL]);
    assert!(scene.shapes.iter().all(|s| s.material == 0));
}

#[test]
fn forward_references_and_vertex_weights() {
    let dir = TempDir::new("obj-forward");
    let path = dir.file("fw.obj", "f 1 2 3\nv 0 0 0 2\nv 2 0 0 2\nv 0 4 0 2 \n");
    let scene = load_obj(&path, &ObjOptions::default()).unwrap();
    assert_eq!(
        scene.shapes[0].shape,
        Shape::Polygon {
            vertices: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0]]
        }
    );
}

/// The one-line message for an OBJ file with `text` (and `mtl` as `m.mtl`), with the
/// temporary directory stripped.
fn obj_error(text: &str, mtl: &str) -> String {
    let dir = TempDir::new("obj-err");
    dir.file("m.mtl", mtl);
    let path = dir.file("bad.obj", text);
    let e = load_obj(&path, &ObjOptions::default())
        .unwrap_err()
        .to_string();
    assert!(!e.contains('\n'), "{e}");
    let prefix = format!("{}/", dir.0.display());
    e.strip_prefix(&prefix)
        .unwrap_or_else(|| panic!("{e}"))
        .to_owned()
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn malformed_obj_files() {
    let err = |text: &str| obj_error(text, "");
    assert_eq!(
        err(&format!("{TRI}f 1 2\n")),
        "bad.obj:4: face needs at least 3 vertices, found 2"
    );
    assert_eq!(
        err(&format!("{TRI}f 1 2 4\n")),
        "bad.obj:4: vertex index 4 is out of range (the file has 3)"
    );
    assert_eq!(
        err(&format!("{TRI}f 1 2 -4\n")),
        "bad.obj:4: vertex index -4 is out of range (3 so far)"
    );
    assert_eq!(
        err(&format!("{TRI}f 0 1 2\n")),
        "bad.obj:4: vertex index 0 is invalid (indices start at 1)"
    );
    assert_eq!(
        err(&format!("{TRI}vn 0 0 1\nf 1//1 2//1 3//2\n")),
        "bad.obj:5: normal index 2 is out of range (the file has 1)"
    );
    assert_eq!(
        err(&format!("{TRI}f 1 2 x\n")),
        "bad.obj:4: invalid vertex index `x`"
    );
    assert_eq!(
        err(&format!("{TRI}f 1 2 3/1/1/1\n")),
        "bad.obj:4: invalid vertex reference `3/1/1/1`"
    );
    assert_eq!(err("v 0 0 nan\n"), "bad.obj:1: non-finite number `nan`");
    assert_eq!(err("v 0 0 1.2.3\n"), "bad.obj:1: invalid number `1.2.3`");
    assert_eq!(
        err("\nv 0 0\n"),
        "bad.obj:2: expected 3, 4 or 6 numbers after `v`, found 2"
    );
    assert_eq!(
        err("v 0 0 1 0\n"),
        "bad.obj:1: vertex weight `w` must not be zero"
    );
    assert_eq!(
        err("vn 0 1\n"),
        "bad.obj:1: expected 3 numbers after `vn`, found 2"
    );
    assert_eq!(
        err(&format!("{TRI}usemtl\n")),
        "bad.obj:4: expected a material name after `usemtl`"
    );
    assert_eq!(err(TRI), "bad.obj: file has no faces");
    assert_eq!(err(""), "bad.obj: file has no faces");
    assert_eq!(
        err("mtllib missing.mtl\n"),
        "bad.obj:1: cannot read material library `missing.mtl`: No such file or directory"
    );
}

#[test]
fn malformed_material_libraries() {
    let err = |mtl: &str| obj_error(&format!("mtllib m.mtl\n{TRI}f 1 2 3\n"), mtl);
    assert_eq!(
        err("newmtl a\nKd 1 1\n"),
        "m.mtl:2: expected 1 or 3 numbers after `Kd`, found 2"
    );
    assert_eq!(err("Ks 1 1 1\n"), "m.mtl:1: `Ks` before any `newmtl`");
    assert_eq!(
        err("newmtl a\nd\n"),
        "m.mtl:2: expected 1 number after `d`, found 0"
    );
    assert_eq!(
        err("newmtl a\nNi inf\n"),
        "m.mtl:2: non-finite number `inf`"
    );
}

#[test]
fn no_obj_input_makes_the_reader_panic() {
    let dir = TempDir::new("obj-fuzz");
    dir.file("cube.mtl", CUBE_MTL);
    let path = dir.0.join("cut.obj");
    for end in 0..=CUBE.len() {
        std::fs::write(&path, &CUBE.as_bytes()[..end]).unwrap();
        if let Err(e) = load_obj(&path, &ObjOptions::default()) {
            assert!(!e.to_string().contains('\n'));
        }
    }
    let huge = "v 0 0 0\nf 1 -99999999999999999 9223372036854775807\nf 1 2 -9223372036854775808\n";
    std::fs::write(&path, huge).unwrap();
    assert!(load_obj(Path::new(&path), &ObjOptions::default()).is_err());
}

/// A library named many times (on one `mtllib` line or on many) is read once, so an OBJ
/// file cannot multiply the work and memory of its library by its own size
/// (`tracer/fuzz/regressions/obj/mtllib-repeated.bin`); its materials stay in effect.
#[test]
fn a_library_named_again_is_read_once() {
    use tracer::scene::{parse_obj, Precision};
    let reads = std::cell::RefCell::new(Vec::new());
    let library = |name: &str| {
        reads.borrow_mut().push(name.to_string());
        match name {
            "m.mtl" => Ok(b"newmtl red\nKd 1 0 0\n".to_vec()),
            "n.mtl" => Ok(b"newmtl blue\nKd 0 0 1\n".to_vec()),
            _ => Err(std::io::ErrorKind::NotFound.into()),
        }
    };
    let obj = format!(
        "mtllib m.mtl m.mtl n.mtl\nmtllib m.mtl\n{TRI}usemtl red\nf 1 2 3\nusemtl blue\nf 1 2 3\n"
    );
    let scene = parse_obj(obj, "t.obj", &ObjOptions::default(), Precision::F32, library).unwrap();
    // The whole line first (a name may contain spaces), then each library once.
    assert_eq!(*reads.borrow(), ["m.mtl m.mtl n.mtl", "m.mtl", "n.mtl"]);
    let colors: Vec<[f64; 3]> = scene
        .shapes
        .iter()
        .map(|s| scene.materials[s.material as usize].color)
        .collect();
    assert_eq!(colors, [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
}
