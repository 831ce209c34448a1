//! NFF reader: the shipped scenes, every statement form, gzip input, and the exact
//! one-line message for each kind of malformed input.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use tracer::scene::{
    load, load_nff, parse_nff, MaterialDesc, SceneDesc, SceneError, Shape, ShapeCounts,
    DEFAULT_MATERIAL,
};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn shipped(name: &str) -> SceneDesc {
    load(&scenes_dir().join(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// A camera block for snippets.
const VIEW: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 64 48\n";

fn parse(text: &str) -> SceneDesc {
    parse_nff(text, "t.nff").unwrap_or_else(|e| panic!("{e}"))
}

/// The message for `text`, checked to be one line.
fn error(text: &str) -> String {
    let e = parse_nff(text, "t.nff").expect_err("the input should be rejected");
    let shown = e.to_string();
    assert!(!shown.contains('\n'), "{shown:?}");
    shown
}

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
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

// ---------------------------------------------------------------------------------------
// Shipped scenes

/// One row of the SPD scene table.
struct Row {
    file: &'static str,
    counts: ShapeCounts,
    lights: usize,
    /// `f` statements.
    materials: usize,
    /// Side of the square image.
    resolution: u32,
    /// Some material has Ks > 0.
    reflective: bool,
    /// Some material has T > 0.
    transmissive: bool,
}

/// A [`Row`] from the table's column order: s, p, pp, cyl, cone, lights, f.
const fn row(
    file: &'static str,
    [s, p, pp, cyl, cone, lights, f]: [usize; 7],
    resolution: u32,
    reflective: bool,
    transmissive: bool,
) -> Row {
    Row {
        file,
        counts: ShapeCounts {
            spheres: s,
            cylinders: cyl,
            cones: cone,
            polygons: p,
            patches: pp,
        },
        lights,
        materials: f,
        resolution,
        reflective,
        transmissive,
    }
}

/// The size-1 rows of the SPD scene table.
const SPD: [Row; 12] = [
    row("balls-s1.nff", [10, 1, 0, 0, 0, 3, 2], 512, true, false),
    row("gears-s1.nff", [0, 147, 0, 0, 0, 5, 2], 512, true, true),
    row("jacks-s1.nff", [6, 0, 0, 3, 0, 1, 1], 256, true, false),
    row("lattice-s1.nff", [8, 0, 0, 12, 0, 6, 20], 512, true, false),
    row("mount-s1.nff", [4, 8, 0, 0, 0, 1, 2], 512, true, true),
    row(
        "nurbtst-s1.nff",
        [0, 0, 1500, 0, 0, 1, 1],
        256,
        false,
        false,
    ),
    row("rings-s1.nff", [30, 1, 0, 30, 0, 3, 7], 512, true, false),
    row("shells-s1.nff", [361, 0, 0, 0, 0, 1, 1], 512, true, false),
    row(
        "sombrero-s1.nff",
        [0, 1922, 0, 0, 0, 1, 1],
        512,
        false,
        false,
    ),
    row("teapot-s1.nff", [0, 1, 56, 0, 0, 2, 3], 512, true, false),
    row("tetra-s1.nff", [0, 4, 0, 0, 0, 1, 1], 512, false, false),
    row("tree-s1.nff", [3, 1, 0, 0, 3, 7, 2], 512, false, false),
];

#[test]
fn every_shipped_spd_scene_loads_with_the_published_counts() {
    for row in &SPD {
        let file = row.file;
        let scene = shipped(file);
        assert_eq!(scene.shape_counts(), row.counts, "{file}");
        assert_eq!(scene.lights.len(), row.lights, "{file}");
        assert!(scene.lights.iter().all(|l| l.color.is_none()), "{file}");
        assert_eq!(scene.materials.len(), row.materials, "{file}");
        let res = row.resolution;
        assert_eq!(scene.camera.resolution, (res, res), "{file}");
        let reflective = scene.materials.iter().any(|m| m.ks > 0.0);
        assert_eq!(reflective, row.reflective, "{file}");
        let transmissive = scene.materials.iter().any(|m| m.t > 0.0);
        assert_eq!(transmissive, row.transmissive, "{file}");
        let lines: Vec<u32> = scene.shapes.iter().map(|s| s.line).collect();
        assert!(
            lines.windows(2).all(|w| w[0] < w[1]),
            "{file}: lines in order"
        );
        assert!(
            scene
                .shapes
                .iter()
                .all(|s| (s.material as usize) < row.materials),
            "{file}: material indices in range"
        );
    }
}

#[test]
fn the_readme_table_lists_every_shipped_spd_scene() {
    let mut files: Vec<String> = std::fs::read_dir(scenes_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with("-s1.nff"))
        .collect();
    files.sort();
    let table: Vec<&str> = SPD.iter().map(|row| row.file).collect();
    assert_eq!(files, table);
}

#[test]
fn tetra_s1_in_full() {
    let scene = shipped("tetra-s1.nff");
    assert_eq!(scene.background, [0.078, 0.361, 0.753]);
    let cam = &scene.camera;
    assert_eq!(cam.from, [1.02285, -3.17715, -2.17451]);
    assert_eq!(cam.at, [-0.004103, -0.004103, 0.216539]);
    assert_eq!(cam.up, [-0.816497, -0.816497, 0.816497]);
    assert_eq!((cam.angle_deg, cam.hither), (45.0, 1.0));
    assert_eq!(scene.lights[0].position, [2.0, -18.0, -5.0]);
    let red = MaterialDesc {
        color: [1.0, 0.2, 0.2],
        kd: 1.0,
        ks: 0.0,
        shine: 100000.0,
        t: 0.0,
        ior: 0.0,
    };
    assert_eq!(scene.materials, vec![red]);
    let first = &scene.shapes[0];
    assert_eq!((first.line, first.material), (11, 0));
    assert_eq!(
        first.shape,
        Shape::Polygon {
            vertices: vec![[-1.0, -1.0, 1.0], [-1.0, 1.0, -1.0], [1.0, -1.0, -1.0]]
        }
    );
    assert_eq!(scene.shapes[3].line, 23);
}

#[test]
fn gears_faces_are_quads_and_two_concave_144_gons() {
    let scene = shipped("gears-s1.nff");
    let mut sizes: Vec<usize> = scene
        .shapes
        .iter()
        .map(|s| match &s.shape {
            Shape::Polygon { vertices } => vertices.len(),
            other => panic!("unexpected {other:?}"),
        })
        .collect();
    sizes.sort();
    assert_eq!(sizes.iter().filter(|&&n| n == 4).count(), 145);
    assert_eq!(&sizes[145..], &[144, 144]);
    assert!(scene.materials.iter().any(|m| m.t > 0.0 && m.ior == 1.1));
}

#[test]
fn teapot_patches_carry_their_normals() {
    let scene = shipped("teapot-s1.nff");
    let Shape::Patch { vertices, normals } = &scene.shapes[1].shape else {
        panic!("expected a patch");
    };
    assert_eq!(vertices[0], [1.4, 0.0, 2.4]);
    assert_eq!(normals[0], [-0.902861, -0.0, -0.429934]);
    assert_eq!(normals[1], [7.30595e-17, 0.902861, -0.429934]);
    assert_eq!((vertices.len(), normals.len()), (3, 3));
}

#[test]
fn showcase_has_every_feature() {
    let scene = shipped("showcase.nff");
    let counts = scene.shape_counts();
    let want = ShapeCounts {
        spheres: 4,
        cylinders: 1,
        cones: 1,
        polygons: 2,
        patches: 4,
    };
    assert_eq!(counts, want);
    assert_eq!(scene.background, [0.15, 0.25, 0.45]);
    assert_eq!(scene.lights.len(), 2);
    assert_eq!(scene.lights[0].color, None);
    assert_eq!(scene.lights[1].color, Some([1.0, 0.55, 0.3]));
    assert_eq!(scene.camera.resolution, (512, 512));
    let mat = |i: u32| &scene.materials[i as usize];
    assert!(scene.materials.iter().any(|m| m.ks >= 0.9), "a mirror");
    assert!(
        scene.materials.iter().any(|m| m.t > 0.5 && m.ior == 1.5),
        "glass"
    );
    let mut inside = 0;
    let mut concave = 0;
    for s in &scene.shapes {
        match &s.shape {
            Shape::Sphere {
                inside_visible: true,
                radius,
                ..
            } => {
                assert_eq!(*radius, 0.8);
                inside += 1;
            }
            Shape::Cone {
                base,
                apex,
                base_radius,
                apex_radius,
                ..
            } if base_radius == apex_radius => {
                // Written over three lines.
                assert_eq!((*base, *apex), ([-3.9, 2.4, 0.0], [-3.9, 2.4, 2.2]));
                assert_eq!(*base_radius, 0.4);
            }
            Shape::Cone { apex_radius, .. } => assert_eq!(*apex_radius, 0.0),
            Shape::Polygon { vertices } if vertices.len() == 10 => concave += 1,
            Shape::Patch { .. } => assert!(mat(s.material).ks > 0.0),
            _ => {}
        }
    }
    assert_eq!((inside, concave), (1, 1));
}

// ---------------------------------------------------------------------------------------
// Statement forms

#[test]
fn cone_on_one_line_two_lines_or_eight() {
    let one = parse(&format!("{VIEW}c 0 0 0 1 0 0 2 0.5\n"));
    let two = parse(&format!("{VIEW}c\n0 0 0 1\n0 0 2 0.5\n"));
    let eight = parse(&format!("{VIEW}c 0\n0\n0\n1\n0\n0\n2\n0.5"));
    assert_eq!(one.shapes[0].shape, two.shapes[0].shape);
    assert_eq!(one.shapes[0].shape, eight.shapes[0].shape);
    assert_eq!(
        one.shapes[0].shape,
        Shape::Cone {
            base: [0.0; 3],
            base_radius: 1.0,
            apex: [0.0, 0.0, 2.0],
            apex_radius: 0.5,
            inside_visible: false,
        }
    );
    assert_eq!(two.shapes[0].line, 8);
}

#[test]
fn negative_radii_mean_the_inside_is_visible() {
    let scene = parse(&format!(
        "{VIEW}s 1 2 3 -0.5\ns 0 0 0 2\nc 0 0 0 -1 0 0 1 -1\nc 0 0 0 -1 0 0 1 0\n"
    ));
    let shapes: Vec<&Shape> = scene.shapes.iter().map(|s| &s.shape).collect();
    assert_eq!(
        *shapes[0],
        Shape::Sphere {
            center: [1.0, 2.0, 3.0],
            radius: 0.5,
            inside_visible: true
        }
    );
    assert!(matches!(
        shapes[1],
        Shape::Sphere {
            inside_visible: false,
            ..
        }
    ));
    assert!(matches!(
        shapes[2],
        Shape::Cone {
            base_radius: 1.0,
            apex_radius: 1.0,
            inside_visible: true,
            ..
        }
    ));
    assert!(matches!(
        shapes[3],
        Shape::Cone {
            base_radius: 1.0,
            apex_radius: 0.0,
            inside_visible: true,
            ..
        }
    ));
}

#[test]
fn lights_with_and_without_colour() {
    let scene = parse(&format!("{VIEW}l 1 2 3\nl 4 5 6 0.5 0.25 1\nl 7 8 9\n"));
    let lights: Vec<_> = scene.lights.iter().map(|l| (l.position, l.color)).collect();
    assert_eq!(
        lights,
        vec![
            ([1.0, 2.0, 3.0], None),
            ([4.0, 5.0, 6.0], Some([0.5, 0.25, 1.0])),
            ([7.0, 8.0, 9.0], None)
        ]
    );
}

#[test]
fn primitives_before_any_material_get_the_default() {
    let scene = parse(&format!(
        "{VIEW}s 0 0 0 1\nf 1 0 0 1 0 1 0 1\ns 0 0 0 1\nf 0 1 0 1 0 1 0 1\nf 0 0 1 1 0 1 0 1\ns 0 0 0 1\n"
    ));
    assert_eq!(scene.materials.len(), 4);
    assert_eq!(scene.materials[0], DEFAULT_MATERIAL);
    assert_eq!(scene.materials[1].color, [1.0, 0.0, 0.0]);
    let used: Vec<u32> = scene.shapes.iter().map(|s| s.material).collect();
    assert_eq!(used, vec![0, 1, 3]);
    // No default material when the first primitive follows an `f`.
    assert_eq!(
        parse(&format!("{VIEW}f 1 1 1 1 0 1 0 1\ns 0 0 0 1\n"))
            .materials
            .len(),
        1
    );
}

#[test]
fn camera_fields_in_any_order_and_background_anywhere() {
    let scene = parse(
        "s 0 0 0 1\nv resolution 32 16 angle 30 up 0 0 1\nhither 0.5 at 1 1 1 from 9 9 9\nb 1 0.5 0\n",
    );
    let cam = &scene.camera;
    assert_eq!(
        (cam.from, cam.at, cam.up),
        ([9.0; 3], [1.0; 3], [0.0, 0.0, 1.0])
    );
    assert_eq!(
        (cam.angle_deg, cam.hither, cam.resolution),
        (30.0, 0.5, (32, 16))
    );
    assert_eq!(scene.background, [1.0, 0.5, 0.0]);
    assert_eq!(parse(VIEW).background, [0.0; 3]);
}

#[test]
fn comments_blank_lines_and_line_endings() {
    let text = "# header\r\n\r\nv # camera\r\nfrom 0 0 5\r\nat 0 0 0\r\nup 0 1 0\r\nangle 45\r\nhither 1\r\n\
                resolution 8 8 # end of view\r\np 3 # a triangle\r\n0 0 0\r\n# inside the polygon\r\n1 0 0\r\n0 1 0#tight\r\n\
                s 0 0 0 1";
    let scene = parse(text);
    assert_eq!(scene.shapes.len(), 2);
    assert_eq!((scene.shapes[0].line, scene.shapes[1].line), (10, 15));
    // Old Mac line ends count as lines too.
    assert_eq!(
        error("s 0 0 0 1\rs 0 0 0\r"),
        "t.nff:2: expected 4 numbers after `s`, found 3"
    );
}

#[test]
fn concave_polygon_and_patch_keep_every_vertex() {
    let scene = parse(&format!(
        "{VIEW}p 6\n0 0 0\n4 0 0\n4 4 0\n3 4 0\n3 1 0\n0 1 0\npp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0.1 0 1\n"
    ));
    let Shape::Polygon { vertices } = &scene.shapes[0].shape else {
        panic!()
    };
    assert_eq!(vertices.len(), 6);
    assert_eq!(vertices[4], [3.0, 1.0, 0.0]);
    let Shape::Patch { vertices, normals } = &scene.shapes[1].shape else {
        panic!()
    };
    assert_eq!(
        (vertices[2], normals[2]),
        ([0.0, 1.0, 0.0], [0.1, 0.0, 1.0])
    );
}

// ---------------------------------------------------------------------------------------
// gzip

fn gzip(data: &[u8]) -> Vec<u8> {
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(data).unwrap();
    enc.finish().unwrap()
}

#[test]
fn gzip_round_trip_in_memory_and_on_disk() {
    let path = scenes_dir().join("rings-s1.nff");
    let text = std::fs::read(&path).unwrap();
    let plain = parse_nff(&text, "rings-s1.nff").unwrap();
    let packed = gzip(&text);
    assert_eq!(parse_nff(&packed, "rings-s1.nff.gz").unwrap(), plain);

    let dir = TempDir::new("scene-gz");
    let gz = dir.0.join("rings.nff.gz");
    std::fs::write(&gz, &packed).unwrap();
    assert_eq!(load(&gz).unwrap(), plain);
    // Recognised by the magic bytes, not the name.
    let disguised = dir.0.join("rings.nff");
    std::fs::write(&disguised, &packed).unwrap();
    assert_eq!(load_nff(&disguised).unwrap(), plain);
    // Several gzip members in a row decompress as one stream.
    let half = text.len() / 2;
    let mut two = gzip(&text[..half]);
    two.extend(gzip(&text[half..]));
    assert_eq!(parse_nff(&two, "two.nff.gz").unwrap(), plain);
}

#[test]
fn corrupt_gzip_is_an_error_without_a_line() {
    let mut packed = gzip(&std::fs::read(scenes_dir().join("tetra-s1.nff")).unwrap());
    let n = packed.len();
    packed.truncate(n / 2);
    let e = parse_nff(&packed, "cut.nff.gz").unwrap_err();
    assert_eq!(e.line(), None);
    assert!(
        e.to_string().starts_with("cut.nff.gz: invalid gzip data: "),
        "{e}"
    );
    assert!(!e.to_string().contains('\n'));
}

#[test]
fn missing_file() {
    let e: SceneError = load(Path::new("no/such/scene.nff")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "no/such/scene.nff: cannot read file: No such file or directory"
    );
    assert!(std::error::Error::source(&e).is_some());
}

// ---------------------------------------------------------------------------------------
// Malformed input: exact messages

#[test]
fn truncated_polygon() {
    assert_eq!(
        error(&format!("{VIEW}p 4\n0 0 0\n1 0 0\n")),
        "t.nff:8: polygon declares 4 vertices but the file ends after 2"
    );
    assert_eq!(
        error(&format!("{VIEW}p 4\n0 0 0\n1 0 0\n1 1\ns 0 0 0 1\n")),
        "t.nff:8: polygon declares 4 vertices but only 2 are given before `s` on line 12"
    );
    assert_eq!(
        error(&format!("{VIEW}pp 3\n0 0 0 0 0 1\n")),
        "t.nff:8: patch declares 3 vertices but the file ends after 1"
    );
}

#[test]
fn unknown_keyword() {
    assert_eq!(
        error(&format!("{VIEW}\nsphere 0 0 0 1\n")),
        "t.nff:9: unknown keyword `sphere`"
    );
    assert_eq!(error("V\n"), "t.nff:1: unknown keyword `V`");
    assert_eq!(
        error(&format!("{VIEW}s 0 0 0 1\nfrom 1 2 3\n")),
        "t.nff:9: `from` outside the `v` block"
    );
}

#[test]
fn bad_numbers() {
    assert_eq!(
        error(&format!("{VIEW}s 0 1.2.3 0 1\n")),
        "t.nff:8: invalid number `1.2.3`"
    );
    assert_eq!(
        error(&format!("{VIEW}s 0 0 0 1,5\n")),
        "t.nff:8: invalid number `1,5`"
    );
    assert_eq!(
        error(&format!("{VIEW}l 0 0\n-\n")),
        "t.nff:9: invalid number `-`"
    );
}

#[test]
fn non_finite_numbers() {
    assert_eq!(
        error(&format!("{VIEW}s 0 0 0 nan\n")),
        "t.nff:8: non-finite number `nan`"
    );
    assert_eq!(
        error(&format!("{VIEW}s 0 0 NaN 1\n")),
        "t.nff:8: non-finite number `NaN`"
    );
    assert_eq!(
        error(&format!("{VIEW}s 0 -inf 0 1\n")),
        "t.nff:8: non-finite number `-inf`"
    );
    assert_eq!(
        error(&format!("{VIEW}s 1e999 0 0 1\n")),
        "t.nff:8: non-finite number `1e999`"
    );
    assert_eq!(
        error("v\nfrom 0 0 infinity\n"),
        "t.nff:2: non-finite number `infinity`"
    );
}

#[test]
fn missing_view() {
    assert_eq!(error("b 0 0 0\ns 0 0 0 1\n"), "t.nff:1: missing `v` block");
    assert_eq!(
        error("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nresolution 8 8\n"),
        "t.nff:1: `v` block is missing `hither`"
    );
    assert_eq!(
        error(&format!("{VIEW}{VIEW}")),
        "t.nff:8: duplicate `v` block (the first is on line 1)"
    );
    assert_eq!(
        error("v\nfrom 0 0 5\nfrom 0 0 5\n"),
        "t.nff:3: duplicate `from` in the `v` block (the first is on line 2)"
    );
}

#[test]
fn too_few_numbers() {
    assert_eq!(
        error("v\nfrom 0 0\nat 0 0 0\n"),
        "t.nff:2: expected 3 numbers after `from`, found 2"
    );
    assert_eq!(
        error("v\nangle\n"),
        "t.nff:2: expected 1 number after `angle`, found 0"
    );
    assert_eq!(
        error(&format!("{VIEW}f 1 1 1 1 0 1 0\ns 0 0 0 1\n")),
        "t.nff:8: expected 8 numbers after `f`, found 7"
    );
    assert_eq!(
        error(&format!("{VIEW}c 0 0 0 1\n0 0 1\n")),
        "t.nff:8: expected 8 numbers after `c`, found 7"
    );
    assert_eq!(
        error(&format!("{VIEW}l 1 2 3 4\n")),
        "t.nff:8: expected 3 or 6 numbers after `l`, found 4"
    );
    assert_eq!(
        error(&format!("{VIEW}b 1\n")),
        "t.nff:8: expected 3 numbers after `b`, found 1"
    );
    assert_eq!(
        error(&format!("{VIEW}p\n")),
        "t.nff:8: expected a vertex count after `p`"
    );
}

#[test]
fn too_many_numbers() {
    assert_eq!(
        error(&format!("{VIEW}s 0 0 0 1 2\n")),
        "t.nff:8: unexpected number `2`: the `s` on line 8 takes 4 numbers"
    );
    assert_eq!(
        error(&format!("{VIEW}p 3\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n")),
        "t.nff:12: unexpected number `0`: the `p` on line 8 declares 3 vertices"
    );
    assert_eq!(
        error(&format!("{VIEW}l 0 0 0 1 1 1 1\n")),
        "t.nff:8: unexpected number `1`: the `l` on line 8 takes 3 or 6 numbers"
    );
    assert_eq!(
        error("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nhither 1\nresolution 8 8\nangle 45 50\n"),
        "t.nff:7: unexpected number `50`: the `angle` on line 7 takes 1 number"
    );
    assert_eq!(
        error("1 2 3\n"),
        "t.nff:1: expected a keyword, found number `1`"
    );
}

#[test]
fn bad_camera() {
    let cam = |fields: &str| error(&format!("v\n{fields}\ns 0 0 0 1\n"));
    let ok = "from 0 0 5 at 0 0 0 up 0 1 0 angle 45 hither 1";
    assert_eq!(
        cam(&format!("{ok} resolution -512 512")),
        "t.nff:2: resolution must be positive"
    );
    assert_eq!(
        cam(&format!("{ok} resolution 512 0")),
        "t.nff:2: resolution must be positive"
    );
    assert_eq!(
        cam(&format!("{ok} resolution 512.5 512")),
        "t.nff:2: resolution must be a whole number of pixels, found 512.5"
    );
    assert_eq!(
        cam(&format!("{ok} resolution 100000 512")),
        "t.nff:2: resolution must be at most 65536, found 100000"
    );
    assert_eq!(
        cam("from 0 0 5 at 0 0 0 up 0 1 0 angle 180 hither 1 resolution 8 8"),
        "t.nff:2: angle must be between 0 and 180 degrees, found 180"
    );
    assert_eq!(
        cam("from 0 0 5 at 0 0 0 up 0 1 0 angle -5 hither 1 resolution 8 8"),
        "t.nff:2: angle must be between 0 and 180 degrees, found -5"
    );
    assert_eq!(
        cam("from 1 1 1\nat 1 1 1 up 0 1 0 angle 45 hither 1 resolution 8 8"),
        "t.nff:3: `at` equals `from`"
    );
    assert_eq!(
        cam("from 0 0 5 at 0 0 0\nup 0 0 -2 angle 45 hither 1 resolution 8 8"),
        "t.nff:3: `up` is parallel to the view direction"
    );
}

#[test]
fn degenerate_primitives() {
    // Zero radii and coinciding cone ends are degenerate but legal (see
    // tests/scene_degenerate.rs); opposite radius signs have no meaning.
    assert_eq!(
        error(&format!("{VIEW}c 0 0 0 1 0 0 1 -1\n")),
        "t.nff:8: cone radii must have the same sign"
    );
    assert_eq!(
        error(&format!("{VIEW}p 2\n0 0 0\n1 0 0\n")),
        "t.nff:8: polygon needs at least 3 vertices, found 2"
    );
    assert_eq!(
        error(&format!("{VIEW}pp 3.5\n")),
        "t.nff:8: vertex count must be a whole number, found 3.5"
    );
    assert_eq!(
        error(&format!("{VIEW}p 1e12\n")),
        "t.nff:8: polygon vertex count 1000000000000 is too large (the limit is 65536)"
    );
}

#[test]
fn empty_files() {
    assert_eq!(error(""), "t.nff:1: file has no statements");
    assert_eq!(
        error("  \n\n# only a comment\n"),
        "t.nff:1: file has no statements"
    );
}

#[test]
fn duplicate_background() {
    assert_eq!(
        error(&format!("b 0 0 0\n{VIEW}b 1 1 1\n")),
        "t.nff:9: duplicate `b` (the first is on line 1)"
    );
}

#[test]
fn messages_quote_odd_tokens_safely() {
    assert_eq!(
        error("\u{1}\u{2}"),
        "t.nff:1: unknown keyword `\\u{1}\\u{2}`"
    );
    let long = "k".repeat(100);
    assert_eq!(
        error(&long),
        format!("t.nff:1: unknown keyword `{}...`", "k".repeat(40))
    );
    let e = parse_nff(b"s 0 0 0 1\n\xff\xfe", "bin.nff").unwrap_err();
    assert_eq!(
        e.to_string(),
        "bin.nff:2: unknown keyword `\u{fffd}\u{fffd}`"
    );
}

/// A small deterministic generator (PCG-XSH-RR 64/32, O'Neill 2014) for the fuzz test.
struct Pcg(u64);

impl Pcg {
    fn next(&mut self) -> u32 {
        let old = self.0;
        self.0 = old
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }
}

#[test]
fn no_input_makes_the_reader_panic() {
    let text = std::fs::read(scenes_dir().join("showcase.nff")).unwrap();
    // Every prefix: truncation anywhere gives a clean result.
    for end in 0..=text.len() {
        if let Err(e) = parse_nff(&text[..end], "cut.nff") {
            let shown = e.to_string();
            assert!(
                shown.starts_with("cut.nff:") && !shown.contains('\n'),
                "{shown}"
            );
        }
    }
    // Random byte edits.
    let alphabet = b" \n\r\t#-+.0123456789eEpsclfvbnaix\x00\xff";
    let mut rng = Pcg(0x853c_49e6_748f_ea9b);
    for _ in 0..3000 {
        let mut t = text.clone();
        for _ in 0..1 + rng.next() % 4 {
            let i = rng.next() as usize % t.len();
            t[i] = alphabet[rng.next() as usize % alphabet.len()];
        }
        if let Err(e) = parse_nff(&t, "edit.nff") {
            assert!(!e.to_string().contains('\n'));
        }
    }
}
