//! Eye rays traced in SIMD packets give the single-ray hits bit for bit, and shadow rays
//! traced as any-hit packets the single-ray answers, so images are identical with
//! packets on or off and for every instruction set the CPU has.
#![cfg(target_arch = "x86_64")]

use std::path::Path;
use tracer::geometry::{AccelOptions, TriangleTest};
use tracer::packets::{EyePackets, Packets};
use tracer::render::{render_with_stats, Settings};
use tracer::{Hit, Ray, Scene};
use vecexpr::simd::Isa;
use vecexpr::Expr;

/// Every scene shipped in `tracer/scenes`.
fn shipped() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".nff"))
        .collect();
    names.sort();
    assert!(names.len() >= 10, "{names:?}");
    names
}

fn scene(name: &str, accel: &AccelOptions) -> Scene<f32> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    Scene::from_desc(&tracer::scene::load(&path).unwrap(), accel)
}

fn bits(v: &vecexpr::Vec3<f32>) -> [u32; 3] {
    [v[0].to_bits(), v[1].to_bits(), v[2].to_bits()]
}

fn same_hit(a: Option<&Hit<f32>>, b: Option<&Hit<f32>>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.t.to_bits() == b.t.to_bits()
                && bits(&a.point) == bits(&b.point)
                && bits(&a.geometric_normal) == bits(&b.geometric_normal)
                && bits(&a.shading_normal) == bits(&b.shading_normal)
                && a.prim_id == b.prim_id
                && a.material == b.material
        }
        _ => false,
    }
}

/// The instruction sets this CPU has, by CPUID read through `std` (not through
/// `Isa::available`): SSE2, AVX2 with FMA, AVX-512F.
fn cpu_isas() -> Vec<Isa> {
    let mut v = vec![Isa::Sse2];
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        v.push(Isa::Avx2);
    }
    if std::arch::is_x86_feature_detected!("avx512f") {
        v.push(Isa::Avx512);
    }
    v
}

/// The instruction sets `test` runs its packets with: every one the CPU has, asserted
/// against [`cpu_isas`]. Writes one line naming those run and those not run straight to
/// stderr, so it appears in every test log (the harness captures only `print!` and
/// `eprint!`).
fn isas(test: &str) -> Vec<Isa> {
    use std::io::Write;
    let ran = Isa::available();
    assert_eq!(ran, cpu_isas(), "{test}");
    let names = |v: &[Isa]| v.iter().map(|i| i.name()).collect::<Vec<_>>().join(" ");
    let missing: Vec<Isa> = Isa::ALL.into_iter().filter(|i| !ran.contains(i)).collect();
    let mut line = format!("packets {test}: ran {}", names(&ran));
    if !missing.is_empty() {
        line += &format!(
            "; not run: {} (the CPU lacks it; its kernels are checked by assembly only, \
             asm-dumps)",
            names(&missing)
        );
    }
    let _ = writeln!(std::io::stderr(), "{line}");
    ran
}

/// The same image bit for bit (`to_bits`: +0 and -0 differ, a NaN equals itself).
fn same_image(a: &tracer::Image, b: &tracer::Image) -> bool {
    (a.width, a.height) == (b.width, b.height)
        && a.pixels
            .iter()
            .flatten()
            .zip(b.pixels.iter().flatten())
            .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Renders `s` with `off` (packets off) and then with packets on for each of `isas`, and
/// asserts the same image bit for bit and the same ray counts; `what` names the case.
fn assert_same_with_packets(s: &Scene<f32>, off: &Settings, isas: &[Isa], what: &str) {
    let (reference, rc) = render_with_stats(s, off);
    for &isa in isas {
        let on = Settings {
            packets: Packets::On(isa),
            ..off.clone()
        };
        let (img, st) = render_with_stats(s, &on);
        assert!(same_image(&img, &reference), "{what} {isa}: image differs");
        assert_eq!(st.rays, rc.rays, "{what} {isa}: ray counts differ");
    }
}

#[test]
fn packet_hits_are_the_single_ray_hits() {
    let isas = isas("eye hits");
    for name in shipped() {
        let s = scene(&name, &AccelOptions::default());
        // An odd size, so edge blocks are partly empty.
        let cam = s.camera_for(45, 31);
        for &isa in &isas {
            let mut p = EyePackets::new(&cam, isa);
            assert_eq!(p.len(), 45 * 31);
            p.cast(&s);
            let mut hits = 0;
            for y in 0..31 {
                for x in 0..45 {
                    let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                    let single = s.intersect(&Ray::new(cam.position, cam.direction(px, py)));
                    assert!(
                        same_hit(p.get(x, y), single.as_ref()),
                        "{name} {isa} pixel ({x}, {y}): {:?} vs {single:?}",
                        p.get(x, y)
                    );
                    hits += usize::from(single.is_some());
                }
            }
            assert!(hits > 0, "{name}: nothing hit");
        }
    }
}

/// `Scene::cast` (one ray, and packets on every instruction set) finds what
/// `Scene::intersect` finds, and `Scene::hit` completes it into the same record, bit for
/// bit, with both triangle tests; rays in a 4x4 block per packet and in scattered
/// directions, with empty lanes.
#[test]
fn casts_are_the_hits_without_their_records() {
    let isas = isas("casts");
    for test in [TriangleTest::Watertight, TriangleTest::MollerTrumbore] {
        let accel = AccelOptions {
            triangle: test,
            ..AccelOptions::default()
        };
        for name in shipped() {
            let s = scene(&name, &accel);
            let cam = s.camera_for(24, 16);
            let mut rays = Vec::new();
            for by in (0..16).step_by(4) {
                for bx in (0..24).step_by(4) {
                    let mut p = [None; 16];
                    for (l, r) in p.iter_mut().enumerate() {
                        let (x, y) = ((bx + l % 4) as f32 + 0.5, (by + l / 4) as f32 + 0.5);
                        *r = Some(Ray::new(cam.position, cam.direction(x, y)));
                    }
                    rays.push(p);
                }
            }
            let mut p = [None; 16];
            for (l, r) in p.iter_mut().enumerate().filter(|(l, _)| l % 5 != 4) {
                let a = l as f32 * 0.7;
                let d = vecexpr::vec3(a.cos(), (a * 1.3).sin(), -1.0 + 0.1 * l as f32);
                *r = Some(Ray::new(cam.position, d));
            }
            rays.push(p);
            let mut found = 0;
            for packet in &rays {
                let singles: Vec<_> = packet.iter().map(|r| r.as_ref().and_then(|r| s.cast(r))).collect();
                for (r, c) in packet.iter().zip(&singles) {
                    let full = r.as_ref().and_then(|r| s.intersect(r));
                    let made = r.as_ref().zip(c.as_ref()).map(|(r, c)| s.hit(r, c));
                    assert!(same_hit(made.as_ref(), full.as_ref()), "{name} {test:?}: {made:?} vs {full:?}");
                    if let (Some(c), Some(h)) = (c, full) {
                        assert_eq!(c.t().to_bits(), h.t.to_bits());
                        found += 1;
                    }
                }
                for &isa in &isas {
                    let n = isa.lanes();
                    for (chunk, want) in packet.chunks(n).zip(singles.chunks(n)) {
                        let mut lanes = [None; 16];
                        lanes[..n].copy_from_slice(chunk);
                        let got = s.cast_packet(isa, &lanes);
                        assert_eq!(&got[..n], want, "{name} {test:?} {isa}");
                        assert!(got[n..].iter().all(Option::is_none));
                    }
                }
            }
            assert!(found > 0, "{name}: nothing hit");
        }
    }
}

/// The shadow rays of the eye hits of a `w` x `h` image toward each light, from the
/// offset hit point, in 4x4 pixel blocks (one packet of sixteen per block and light),
/// plus rays toward a point just off each hit (a short `t_max`) and rays in a fixed
/// scatter of directions (lanes with different watertight shear axes); every fifth
/// lane of the scattered rays is left empty.
fn shadow_packets(s: &Scene<f32>, w: usize, h: usize) -> Vec<[Option<Ray<f32>>; 16]> {
    let cam = s.camera_for(w as u32, h as u32);
    let mut packets = Vec::new();
    for by in (0..h).step_by(4) {
        for bx in (0..w).step_by(4) {
            let hits: Vec<Option<Hit<f32>>> = (0..16)
                .map(|k| {
                    let (x, y) = (bx + k % 4, by + k / 4);
                    let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                    (x < w && y < h)
                        .then(|| s.intersect(&Ray::new(cam.position, cam.direction(px, py))))
                        .flatten()
                })
                .collect();
            let above = |h: &Hit<f32>| {
                let n = h.geometric_normal;
                vecexpr::vec3(
                    h.point[0] + 1e-3 * n[0],
                    h.point[1] + 1e-3 * n[1],
                    h.point[2] + 1e-3 * n[2],
                )
            };
            for light in &s.lights {
                packets.push(core::array::from_fn(|k| {
                    hits[k].as_ref().map(|h| {
                        let p = above(h);
                        let d = vecexpr::vec3(
                            light.position[0] - p[0],
                            light.position[1] - p[1],
                            light.position[2] - p[2],
                        );
                        Ray {
                            t_max: 1.0,
                            ..Ray::new(p, d)
                        }
                    })
                }));
            }
            packets.push(core::array::from_fn(|k| {
                hits[k].as_ref().map(|h| Ray {
                    t_max: 1e-4,
                    ..Ray::new(above(h), (cam.position - h.point).eval())
                })
            }));
            packets.push(core::array::from_fn(|k| {
                hits[k].as_ref().filter(|_| k % 5 != 4).map(|h| {
                    let f = k as f32;
                    let d = vecexpr::vec3((f * 1.7).sin(), (f * 2.3).cos(), (f * 0.9).sin());
                    Ray::new(above(h), d)
                })
            }));
        }
    }
    packets
}

#[test]
fn packet_shadow_rays_are_the_single_ray_answers() {
    let isas = isas("shadow rays");
    let (mut blocked, mut free) = (0, 0);
    for name in shipped() {
        let s = scene(&name, &AccelOptions::default());
        let packets = shadow_packets(&s, 23, 19);
        for &isa in &isas {
            for (k, rays) in packets.iter().enumerate() {
                let got = s.occluded_packet(isa, rays);
                for (l, r) in rays.iter().enumerate() {
                    let want =
                        l < isa.lanes() && r.as_ref().is_some_and(|r| s.geometry.occluded(r));
                    assert_eq!(got[l], want, "{name} {isa} packet {k} lane {l}: {r:?}");
                    if l < isa.lanes() && r.is_some() {
                        if want {
                            blocked += 1;
                        } else {
                            free += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(
        blocked > 1000 && free > 1000,
        "blocked {blocked}, free {free}"
    );
}

/// The shadow cache of the packets: whatever primitive reference the hint holds (none,
/// the one the previous packet left, each lane's own occluder, or values that name no
/// primitive), every lane is the single ray's answer; and the hint is left empty when no
/// lane is blocked.
#[test]
fn packet_shadow_rays_with_any_cached_occluder_are_the_single_ray_answers() {
    use tracer::geometry::{kinds, NO_HINT};
    let isas = isas("cached shadow rays");
    let (mut hinted, mut changed) = (0, 0);
    for name in shipped() {
        let s = scene(&name, &AccelOptions::default());
        let packets = shadow_packets(&s, 23, 19);
        for &isa in &isas {
            let mut carried = NO_HINT;
            for (k, rays) in packets.iter().enumerate() {
                let lanes = &rays[..isa.lanes()];
                let want: Vec<bool> = lanes
                    .iter()
                    .map(|r| r.as_ref().is_some_and(|r| s.geometry.occluded(r)))
                    .collect();
                // Each lane's occluder, as the single-ray cache records it.
                let own = lanes.iter().flatten().map(|r| {
                    let mut h = NO_HINT;
                    s.geometry
                        .occluded_hint_kinds::<{ kinds::ALL }>(r, &mut h);
                    h
                });
                let mut hints = vec![carried, NO_HINT, 0, 0x7fff_ffff, u32::MAX - 1];
                hints.extend(own);
                for (j, hint0) in hints.into_iter().enumerate() {
                    let mut hint = hint0;
                    let got = s.geometry.occluded_packet_hint(isa, rays, &mut hint);
                    assert_eq!(
                        &got[..isa.lanes()],
                        &want[..],
                        "{name} {isa} packet {k} hint {hint0:#x}"
                    );
                    assert!(got[isa.lanes()..].iter().all(|b| !b));
                    let any_ray = lanes.iter().any(Option::is_some);
                    assert!(
                        !any_ray || want.contains(&true) || hint == NO_HINT,
                        "{name} {isa} packet {k}: hint {hint:#x} left after {want:?}"
                    );
                    if hint0 != NO_HINT {
                        hinted += 1;
                    }
                    changed += usize::from(hint != hint0);
                    if j == 0 {
                        carried = hint;
                    }
                }
            }
        }
    }
    assert!(hinted > 1000 && changed > 100, "hinted {hinted}, changed {changed}");
}

#[test]
fn packet_shadow_fallbacks_are_the_single_ray_answers() {
    let isas = isas("shadow fallbacks");
    // Möller–Trumbore and brute force answer each ray alone; the binary tree is the
    // one packets walk.
    for accel in [
        AccelOptions {
            triangle: TriangleTest::MollerTrumbore,
            ..AccelOptions::default()
        },
        AccelOptions {
            use_bvh: false,
            ..AccelOptions::default()
        },
        AccelOptions {
            wide: false,
            ..AccelOptions::default()
        },
    ] {
        let s = scene("showcase.nff", &accel);
        for &isa in &isas {
            for rays in shadow_packets(&s, 12, 8) {
                let got = s.occluded_packet(isa, &rays);
                for (l, r) in rays.iter().enumerate() {
                    let want =
                        l < isa.lanes() && r.as_ref().is_some_and(|r| s.geometry.occluded(r));
                    assert_eq!(got[l], want, "{accel:?} {isa} lane {l}");
                }
            }
        }
    }
}

#[test]
fn images_are_identical_with_packets_on_or_off_and_across_isas() {
    let isas = isas("images");
    for name in shipped() {
        let s = scene(&name, &AccelOptions::default());
        // Pixel centres, SPD's corners, and a 3 x 3 grid of supersamples.
        for (spd, aa) in [(false, 1), (true, 1), (false, 3)] {
            let off = Settings {
                width: Some(37),
                height: Some(29),
                spd,
                aa,
                packets: Packets::Off,
                ..Settings::default()
            };
            let what = format!("{name} spd={spd} aa={aa}");
            assert_same_with_packets(&s, &off, &isas, &what);
        }
    }
}

/// With packets on, the reflection and refraction rays of a tile are traced generation
/// by generation in packets sorted by octant, and each ray's radiance is added to its
/// parent's colour afterwards. Deep trees (depth 12, where mount-s1's glass spheres spawn
/// both rays at every hit), adaptive termination, which prunes some branches and keeps
/// others, and a width that leaves partial tiles at the edge all give the single-ray
/// image and ray counts. At depth 24 mount-s1 spawns about 190 rays per pixel, 6,000 per
/// tile of 32 pixels, beyond the 4,096 a tile holds, so the rest of its trees are traced
/// by the single-ray recursion, and the result is still the same.
#[test]
fn secondary_ray_packets_give_the_single_ray_trees() {
    let isas = isas("secondary rays");
    let cases = [(12, 0.0), (12, 0.05), (3, 0.3), (1, 0.0)];
    let deep = [(24, 0.0)];
    for name in ["mount-s1.nff", "shells-s1.nff", "showcase.nff", "teapot-s1.nff"] {
        let s = scene(name, &AccelOptions::default());
        let deep: &[_] = if name == "mount-s1.nff" { &deep } else { &[] };
        for &(depth, threshold) in cases.iter().chain(deep) {
            let off = Settings {
                width: Some(43),
                height: Some(19),
                depth,
                threshold,
                packets: Packets::Off,
                ..Settings::default()
            };
            let (_, st) = render_with_stats(&s, &off);
            if depth > 1 && threshold == 0.0 {
                assert!(st.rays.reflection > 0, "{name}: no reflection rays");
            }
            let what = format!("{name} depth={depth} threshold={threshold}");
            assert_same_with_packets(&s, &off, &isas, &what);
        }
    }
}

#[test]
fn viewer_passes_are_identical_with_packets_on_or_off() {
    let isas = isas("viewer passes");
    for name in shipped() {
        let s = scene(&name, &AccelOptions::default());
        let cam = s.camera_for(37, 29);
        let off = Settings {
            packets: Packets::Off,
            ..Settings::default()
        };
        let pass = |settings: &Settings, aa: u32| {
            let mut sums = vec![vecexpr::vec3(0.0f32, 0.0, 0.0); 37 * 29];
            let (counts, _) = tracer::render::accumulate_pass(&s, &cam, settings, aa, 0, &mut sums);
            (sums.iter().map(bits).collect::<Vec<_>>(), counts)
        };
        for aa in [1, 2] {
            let reference = pass(&off, aa);
            for &isa in &isas {
                let on = Settings {
                    packets: Packets::On(isa),
                    ..off.clone()
                };
                assert!(
                    pass(&on, aa) == reference,
                    "{name} aa={aa} {isa}: pass differs"
                );
            }
        }
    }
}

/// Packets shade their hits one light at a time, each light's shadow rays as one any-hit
/// packet, where single rays trace each hit's shadow rays in turn with the shadow cache
/// (whose entries stop at eight lights). A scene with 70 lights, some of them hidden from
/// parts of the floor by the spheres, renders the same with packets on or off.
#[test]
fn more_lights_than_a_packet_answers_give_the_same_image() {
    use tracer::scene::desc::MaterialDesc;
    let isas = isas("many lights");
    let mut b = tracer::SceneBuilder::default();
    let matte = b.add_material(MaterialDesc {
        color: [0.8, 0.7, 0.6],
        kd: 0.8,
        ks: 0.0,
        shine: 1.0,
        t: 0.0,
        ior: 1.0,
    });
    let shiny = b.add_material(MaterialDesc {
        color: [0.3, 0.5, 0.9],
        kd: 0.5,
        ks: 0.3,
        shine: 20.0,
        t: 0.0,
        ior: 1.0,
    });
    b.add_polygon(
        vec![
            [-5.0, 0.0, -5.0],
            [-5.0, 0.0, 5.0],
            [5.0, 0.0, 5.0],
            [5.0, 0.0, -5.0],
        ],
        matte,
    );
    for (x, z) in [(-1.2, 0.0), (1.2, 0.3), (0.0, -1.5)] {
        b.add_sphere([x, 0.8, z], 0.8, shiny);
    }
    // Lights on a low ring, so that the spheres shadow different parts of the floor
    // from each.
    for k in 0..70 {
        let a = k as f64 * std::f64::consts::TAU / 70.0;
        b.add_light([4.0 * a.cos(), 1.0 + 0.02 * k as f64, 4.0 * a.sin()], Some([0.02; 3]));
    }
    b.background([0.1, 0.1, 0.2]);
    b.look_at([0.0, 4.0, 7.0], [0.0, 0.5, 0.0], [0.0, 1.0, 0.0], 45.0);
    let s: Scene<f32> = b.build();
    assert_eq!(s.lights.len(), 70);
    let off = Settings {
        width: Some(40),
        height: Some(30),
        packets: Packets::Off,
        ..Settings::default()
    };
    assert_same_with_packets(&s, &off, &isas, "70 lights");
}

#[test]
fn fallbacks_give_the_same_image() {
    let isas = isas("fallback images");
    // Möller–Trumbore triangles and brute force trace each ray of a packet alone; the
    // binary tree is what packets walk, the four-wide one what single rays walk.
    for accel in [
        AccelOptions {
            triangle: TriangleTest::MollerTrumbore,
            ..AccelOptions::default()
        },
        AccelOptions {
            use_bvh: false,
            ..AccelOptions::default()
        },
        AccelOptions {
            wide: false,
            ..AccelOptions::default()
        },
    ] {
        let s = scene("showcase.nff", &accel);
        let off = Settings {
            width: Some(24),
            height: Some(20),
            packets: Packets::Off,
            ..Settings::default()
        };
        let reference = render_with_stats(&s, &off).0;
        for &isa in &isas {
            let on = Settings {
                packets: Packets::On(isa),
                ..off.clone()
            };
            assert!(
                same_image(&render_with_stats(&s, &on).0, &reference),
                "{accel:?} {isa}"
            );
        }
    }
}

#[test]
fn isa_arguments() {
    assert_eq!(Packets::from_args("off", "auto"), Ok(Packets::Off));
    assert_eq!(Packets::from_args("on", "sse2"), Ok(Packets::On(Isa::Sse2)));
    assert_eq!(
        Packets::from_args("on", "auto"),
        Ok(Packets::On(Isa::detect().unwrap()))
    );
    assert_eq!(Packets::from_args("auto", "auto"), Ok(Packets::auto()));
    assert_eq!(
        Packets::from_args("auto", "sse2"),
        Ok(Packets::On(Isa::Sse2))
    );
    assert!(Packets::auto() == Packets::Off || Packets::auto().isa() >= Some(Isa::Avx2));
    assert!(Packets::from_args("on", "avx").is_err());
    assert!(Packets::from_args("maybe", "auto").is_err());
    for isa in Isa::ALL {
        let r = Packets::from_args("on", isa.name());
        if isa.is_available() {
            assert_eq!(r, Ok(Packets::On(isa)));
        } else {
            let e = r.unwrap_err();
            assert!(e.contains("does not support"), "{e}");
        }
    }
}
