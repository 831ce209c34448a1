//! A Whitted ray tracer built on vecexpr.
//!
//! The pipeline: a scene file is read into a [`scene::desc::SceneDesc`] (plain `f64`
//! data), converted into a [`Scene`] of the chosen precision (primitives plus a BVH), and
//! rendered by [`render()`] into an [`Image`]. Every piece of vector math goes through
//! `vecexpr`, and everything is generic over the scalar (`f32` or `f64`).
//!
//! ```
//! use tracer::{render, Ray, Scene, SceneBuilder, Settings};
//! use tracer::scene::desc::MaterialDesc;
//! use vecexpr::vec3;
//!
//! let mut b = SceneBuilder::default();
//! let red = b.add_material(MaterialDesc::diffuse([1.0, 0.2, 0.2]));
//! b.add_sphere([0.0, 0.0, 0.0], 1.0, red);
//! b.add_light([5.0, 5.0, 5.0], None);
//! b.look_at([0.0, 0.0, 5.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 45.0);
//! let scene: Scene<f32> = b.build();
//!
//! let hit = scene.intersect(&Ray::new(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, -1.0))).unwrap();
//! assert!((hit.t - 4.0).abs() < 1e-5);
//! assert!(scene.occluded(&Ray::new(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, -1.0))));
//!
//! let image = render(&scene, &Settings { width: Some(32), height: Some(32), ..Settings::default() });
//! assert_eq!((image.width, image.height), (32, 32));
//! ```

pub mod arith;
pub mod bvh;
pub mod camera;
pub mod cycles;
pub mod effects;
pub mod float;
pub mod geometry;
pub mod image;
pub mod packets;
pub mod pages;
pub mod ray;
pub mod render;
pub mod scene;
pub mod schedule;
pub mod settings;
pub mod shade;
pub mod stats;
pub mod world;

pub use camera::Camera;
pub use float::Float;
pub use image::Image;
pub use ray::{Hit, Ray};
pub use render::{render, render_with_progress, render_with_stats};
pub use schedule::Progress;
pub use settings::Settings;
pub use stats::RayCounts;
pub use world::{Light, Material, Scene, SceneBuilder};
