//! Loads every scene of the full SPD data set (not in the repository) and prints counts
//! and load times. Ignored by default; run it with the data set's `scenes` directory
//! (the one holding `spd/`, `spd-large/`, `spd-obj/`) in `TRACER_SCENE_DATA`:
//!
//! ```text
//! TRACER_SCENE_DATA=/path/to/scenes cargo test --release -p tracer --test integration scene_shared:: -- --ignored --nocapture
//! ```
//!
//! CI (`.ci/run`) runs it this way whenever the data set is at `../shared/scenes`, beside
//! the repository, and prints that it did not run otherwise.

use std::path::{Path, PathBuf};
use std::time::Instant;

use tracer::scene::{load, SceneDesc};

fn data_dir() -> PathBuf {
    PathBuf::from(
        std::env::var_os("TRACER_SCENE_DATA")
            .expect("set TRACER_SCENE_DATA to the directory holding spd/, spd-large/, spd-obj/"),
    )
}

/// Loads every file with one of `extensions` in `dir`, printing a summary line each.
fn load_all(dir: &Path, extensions: &[&str]) -> Vec<(String, SceneDesc)> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            extensions.iter().any(|ext| name.ends_with(ext))
        })
        .collect();
    paths.sort();
    assert!(!paths.is_empty(), "no scenes in {}", dir.display());
    paths
        .into_iter()
        .map(|path| {
            let start = Instant::now();
            let scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
            let seconds = start.elapsed().as_secs_f64();
            let c = scene.shape_counts();
            println!(
                "{:<22} {:>8.3} s  s {:>7} cyl {:>5} cone {:>5} p {:>6} pp {:>6}  lights {} materials {}",
                path.file_name().unwrap().to_string_lossy(),
                seconds,
                c.spheres,
                c.cylinders,
                c.cones,
                c.polygons,
                c.patches,
                scene.lights.len(),
                scene.materials.len()
            );
            (path.file_name().unwrap().to_string_lossy().into_owned(), scene)
        })
        .collect()
}

#[test]
#[ignore = "needs the SPD data set in TRACER_SCENE_DATA"]
fn every_spd_scene_loads() {
    let root = data_dir();
    let nff = load_all(&root.join("spd"), &[".nff"]);
    assert_eq!(nff.len(), 22);
    let large = load_all(&root.join("spd-large"), &[".nff.gz"]);
    let counts = |name: &str| {
        large
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, s)| s.shape_counts())
            .unwrap()
    };
    assert_eq!(counts("balls-s5.nff.gz").spheres, 66_430);
    assert_eq!(counts("balls-s6.nff.gz").spheres, 597_871);
    assert_eq!(counts("tetra-s8.nff.gz").polygons, 65_536);
    assert_eq!(counts("mount-s8.nff.gz").polygons, 131_072);
    assert_eq!(counts("teapot-s40.nff.gz").patches, 102_080);
    assert_eq!(counts("teapot-s40.nff.gz").polygons, 1600);
    for (name, scene) in load_all(&root.join("spd-obj"), &[".obj"]) {
        let c = scene.shape_counts();
        assert_eq!(scene.lights.len(), 1, "{name}");
        assert!(c.polygons + c.patches > 0, "{name}");
    }
}
