//! Specialised renderers: the effect set derived from each scene, and for every shipped
//! scene (the SPD scenes at size 1 and the showcase) the same image bit for bit and the
//! same ray counts from every renderer that can draw it as from the general one.

use std::path::{Path, PathBuf};
use tracer::effects::{self, EffectSet, EffectsMode};
use tracer::geometry::AccelOptions;
use tracer::render::{render_with_effects, render_with_stats, RenderStats, Settings};
use tracer::scene::desc::MaterialDesc;
use tracer::{Image, Scene, SceneBuilder};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn load(name: &str) -> Scene<f32> {
    let desc = tracer::scene::load(&scenes_dir().join(name)).unwrap();
    Scene::from_desc(&desc, &AccelOptions::default())
}

/// Every `.nff` in `tracer/scenes`.
fn shipped() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(scenes_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".nff"))
        .collect();
    v.sort();
    assert!(
        v.len() >= 13,
        "the twelve SPD scenes at size 1 and the showcase"
    );
    v
}

fn small(w: u32, h: u32) -> Settings {
    Settings {
        width: Some(w),
        height: Some(h),
        ..Settings::default()
    }
}

/// The settings each scene is rendered with: default shading, SPD rules, supersampling
/// with adaptive termination, local shading only.
fn variants() -> Vec<(&'static str, Settings)> {
    vec![
        ("default", small(37, 29)),
        (
            "spd",
            Settings {
                spd: true,
                ..small(24, 24)
            },
        ),
        (
            "aa2 threshold",
            Settings {
                aa: 2,
                threshold: 0.3,
                ..small(20, 16)
            },
        ),
        (
            "depth 1",
            Settings {
                depth: 1,
                ..small(24, 24)
            },
        ),
    ]
}

fn assert_same(what: &str, (a, sa): &(Image, RenderStats), (b, sb): &(Image, RenderStats)) {
    assert_eq!((a.width, a.height), (b.width, b.height), "{what}");
    let differing = a
        .pixels
        .iter()
        .flatten()
        .zip(b.pixels.iter().flatten())
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count();
    assert_eq!(
        differing, 0,
        "{what}: channels differ from the general renderer"
    );
    assert_eq!(sa.rays, sb.rays, "{what}: ray counts differ");
}

#[test]
fn every_renderer_matches_the_general_one_bit_for_bit() {
    let mut specialised = 0;
    for name in shipped() {
        let scene = load(&name);
        for (label, settings) in variants() {
            let what = format!("{name} ({label})");
            let general = render_with_stats(
                &scene,
                &Settings {
                    effects: EffectsMode::All,
                    ..settings.clone()
                },
            );
            assert!(general.1.effects.general, "{what}");
            let auto = render_with_stats(&scene, &settings);
            assert_same(&format!("{what} auto"), &auto, &general);
            let required = auto.1.effects.required;
            assert!(auto.1.effects.renderer.contains(required), "{what}");
            specialised += usize::from(!auto.1.effects.general);
            // Every other instance that contains the required effects, too.
            for &bits in effects::INSTANCES {
                let set = EffectSet::from_bits(bits);
                if set.contains(required) && !set.is_general() {
                    let r = render_with_effects(&scene, &settings, set);
                    assert_eq!(r.1.effects.renderer, set);
                    assert_same(&format!("{what} as {:?}", set.names()), &r, &general);
                }
            }
        }
    }
    // With default settings, SPD rules or depth 1, no SPD scene needs the general
    // renderer.
    assert!(specialised >= 36, "only {specialised} specialised renders");
}

#[test]
fn effect_sets_of_the_spd_scenes() {
    let expect: &[(&str, &[&str])] = &[
        ("tetra-s1.nff", &["shadows", "triangles"]),
        ("tree-s1.nff", &["shadows", "spheres", "triangles", "cones"]),
        (
            "balls-s1.nff",
            &["shadows", "specular", "reflection", "spheres", "triangles"],
        ),
        (
            "gears-s1.nff",
            &[
                "shadows",
                "specular",
                "reflection",
                "refraction",
                "triangles",
            ],
        ),
        (
            "mount-s1.nff",
            &[
                "shadows",
                "specular",
                "reflection",
                "refraction",
                "spheres",
                "triangles",
            ],
        ),
        (
            "teapot-s1.nff",
            &["shadows", "specular", "reflection", "triangles"],
        ),
    ];
    // Every SPD scene has an exact table entry but gears, whose own renderer measured
    // slower than the general one: it runs the renderer of mount's effects, which adds
    // spheres (and so the general per-primitive dispatch) to the same effects.
    let exact = |name: &str, need: EffectSet| {
        if name.starts_with("gears") {
            EffectSet::from_bits(need.bits() | effects::SPHERES)
        } else {
            need
        }
    };
    for name in shipped().iter().filter(|n| n.ends_with("-s1.nff")) {
        let need = EffectSet::required(&load(name), &Settings::default());
        assert_eq!(
            effects::choose(need),
            exact(name, need),
            "{name}: no exact table entry"
        );
    }
    for (name, names) in expect {
        let scene = load(name);
        let s = Settings::default();
        let need = EffectSet::required(&scene, &s);
        assert_eq!(need.names(), *names, "{name}");
        // The table has an exact entry for each (gears: see above).
        assert_eq!(effects::choose(need), exact(name, need), "{name}");
        // Depth 1 drops the secondary rays, supersampling and a threshold are settings.
        let local = EffectSet::required(
            &scene,
            &Settings {
                depth: 1,
                ..s.clone()
            },
        );
        assert!(!local.contains(EffectSet::from_bits(effects::REFLECTION)));
        assert!(!local.contains(EffectSet::from_bits(effects::REFRACTION)));
        let aa = EffectSet::required(&scene, &Settings { aa: 3, ..s.clone() });
        assert!(aa.contains(EffectSet::from_bits(effects::SUPERSAMPLING)));
        let spd = EffectSet::required(
            &scene,
            &Settings {
                aa: 3,
                spd: true,
                ..s
            },
        );
        assert_eq!(spd, need, "{name}: SPD mode has one ray per corner");
    }
}

#[test]
fn dark_lights_and_matte_surfaces_need_no_shadows_or_highlights() {
    let mut b = SceneBuilder::default();
    let m = b.add_material(MaterialDesc::diffuse([1.0, 0.5, 0.5]));
    b.add_sphere([0.0, 0.0, 0.0], 1.0, m);
    b.add_light([5.0, 5.0, 5.0], Some([0.0, 0.0, 0.0]));
    let scene: Scene<f32> = b.build();
    let s = small(16, 16);
    assert_eq!(EffectSet::required(&scene, &s).names(), ["spheres"]);
    let general = render_with_stats(
        &scene,
        &Settings {
            effects: EffectsMode::All,
            ..s.clone()
        },
    );
    let auto = render_with_stats(&scene, &s);
    assert_same("dark light", &auto, &general);
    assert_eq!(auto.1.rays.shadow, 0, "no shadow ray toward a dark light");

    let mut b = SceneBuilder::default();
    let g = b.add_material(MaterialDesc::glass(1.5));
    b.add_sphere([0.0, 0.0, 0.0], 1.0, g);
    b.add_light([5.0, 5.0, 5.0], None);
    let scene: Scene<f32> = b.build();
    let t = Settings {
        threshold: 0.65,
        ..small(16, 16)
    };
    let need = EffectSet::required(&scene, &t);
    assert!(need.contains(EffectSet::from_bits(effects::ADAPTIVE)));
    assert!(effects::choose(need).is_general());
    // Reflection weights (0.1) and the third refraction (0.85^3) fall below 0.65.
    let adaptive = render_with_stats(&scene, &t).1.rays;
    let full = render_with_stats(&scene, &small(16, 16)).1.rays;
    assert!(adaptive.refraction < full.refraction && adaptive.reflection < full.reflection);
    assert!(adaptive.refraction > 0);
}

/// Adaptive termination traces a secondary ray only while the product of the weights
/// along its path reaches the threshold: between two facing mirrors of K_s = 0.5, a
/// threshold of 0.1 lets every eye ray bounce three times (path weights 0.5, 0.25 and
/// 0.125; the fourth, 0.0625, is dropped), where depth 10 alone allows nine.
#[test]
fn adaptive_termination_follows_the_product_of_the_weights() {
    let mut b = SceneBuilder::default();
    let mirror = b.add_material(MaterialDesc {
        color: [1.0; 3],
        kd: 0.0,
        ks: 0.5,
        shine: 1.0,
        t: 0.0,
        ior: 1.0,
    });
    for z in [-1.0, 1.0] {
        let v = [
            [-100.0, -100.0, z],
            [100.0, -100.0, z],
            [100.0, 100.0, z],
            [-100.0, 100.0, z],
        ];
        b.add_polygon(v.to_vec(), mirror);
    }
    b.look_at([0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0], 30.0);
    let scene: Scene<f32> = b.build();
    let pixels = 8 * 8;
    for (threshold, bounces) in [(0.1, 3), (0.3, 1), (0.0, 9)] {
        let s = Settings {
            depth: 10,
            threshold,
            ..small(8, 8)
        };
        let rays = render_with_stats(&scene, &s).1.rays;
        assert_eq!(rays.eye, pixels, "threshold {threshold}");
        assert_eq!(rays.reflection, bounces * pixels, "threshold {threshold}");
    }
}

#[test]
#[should_panic(expected = "cannot render")]
fn a_renderer_without_a_needed_effect_is_refused() {
    let scene = load("balls-s1.nff");
    let set = EffectSet::from_bits(effects::MATTE_TRIANGLES);
    let _ = render_with_effects(&scene, &small(8, 8), set);
}
