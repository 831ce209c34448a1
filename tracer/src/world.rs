//! The renderable scene: camera, lights, materials and geometry in one precision.
//!
//! A scene file is read into a [`crate::scene::SceneDesc`]: plain `f64` data as the file
//! gives it, with no acceleration structure. [`Scene::from_desc`] (or a
//! [`SceneBuilder`] in code) turns it into a [`Scene`] in the tracer's precision `T`,
//! with the lights' intensities and the materials' Whitted weights derived and the
//! primitives and their BVH built ([`Geometry`]): what the renderer reads.
//!
//! # How NFF's material maps onto the Whitted model
//! NFF gives `f r g b Kd Ks Shine T ior`. With surface colour $C$:
//! - ambient: $K_a I_a C$ with $I_a = 1$ and $K_a = \max(0, 1 - K_d - K_s - T)$, the
//!   convention of SPD's own POV-Ray exporter (a matte `Kd = 0.8` surface gets 0.2
//!   ambient, a mirror with `Kd + Ks = 1` none);
//! - diffuse: $K_d C I_l (L \cdot N)$ per visible light;
//! - specular highlight: $K_s I_l (R \cdot V)^{Shine}$ per visible light, white;
//! - mirror reflection: $K_r = K_s$, untinted;
//! - refraction: $K_t = T$, filtered by the surface colour, with index `ior` (an `ior`
//!   of 0 is read as 1).
//!
//! Lights without a colour have intensity $1/\sqrt{n}$ for $n$ lights (so the total stays
//! moderate as lights are added, as the SPD exporters do); a coloured light uses its
//! colour as intensity.

use crate::float::Float;
use crate::geometry::{AccelOptions, Geometry, Intersection, MAX_LANES};
use crate::ray::{Hit, Ray};
use crate::scene::desc::{CameraDesc, LightDesc, MaterialDesc, SceneDesc, Shape, ShapeDesc, P3};
use crate::Camera;
use vecexpr::simd::Isa;
use vecexpr::{vec3, Real, Vec3};

/// A surface material in the tracer's precision (see the module docs for the mapping).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material<T: Real> {
    /// Surface colour $C$.
    pub color: Vec3<T>,
    /// Ambient weight $K_a$.
    pub ka: T,
    /// Diffuse weight $K_d$.
    pub kd: T,
    /// Specular highlight and mirror weight $K_s$.
    pub ks: T,
    /// Phong exponent.
    pub shine: T,
    /// Transmitted fraction $K_t$.
    pub kt: T,
    /// Index of refraction (1 for opaque materials).
    pub ior: T,
}

impl<T: Real> Material<T> {
    /// From NFF's `f` line values.
    pub fn from_desc(m: &MaterialDesc) -> Self {
        let c = |x: f64| T::from_f64(x);
        let ka = (1.0 - m.kd - m.ks - m.t).max(0.0);
        // The secondary rays carry K_r = K_s and K_t, and total internal reflection moves
        // K_t onto the reflection ray: with K_s + K_t > 1 a surface would return more light
        // than reaches it. Such materials (none in the SPD scenes) are scaled to sum to 1.
        let sum = m.ks + m.t;
        let (ks, kt) = if sum > 1.0 {
            (m.ks / sum, m.t / sum)
        } else {
            (m.ks, m.t)
        };
        Self {
            color: vec3(c(m.color[0]), c(m.color[1]), c(m.color[2])),
            ka: c(ka),
            kd: c(m.kd),
            ks: c(ks),
            shine: c(m.shine),
            kt: c(kt),
            ior: if m.ior > 0.0 { c(m.ior) } else { T::ONE },
        }
    }
}

/// A point light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light<T: Real> {
    /// Position.
    pub position: Vec3<T>,
    /// Intensity per channel.
    pub intensity: Vec3<T>,
}

/// Everything needed to render: camera, lights, materials, background and geometry.
pub struct Scene<T: Real> {
    /// The camera from the file (resolution may be overridden at render time).
    pub camera: CameraDesc,
    /// Background colour for rays that escape.
    pub background: Vec3<T>,
    /// Point lights.
    pub lights: Vec<Light<T>>,
    /// Materials, indexed by [`Hit::material`].
    pub materials: Vec<Material<T>>,
    /// Primitives and their acceleration structure.
    pub geometry: Geometry<T>,
}

fn v3<T: Real>(p: &P3) -> Vec3<T> {
    vec3(T::from_f64(p[0]), T::from_f64(p[1]), T::from_f64(p[2]))
}

impl<T: Float> Scene<T> {
    /// Converts a parsed scene to this precision and builds its BVH.
    pub fn from_desc(desc: &SceneDesc, accel: &AccelOptions) -> Self {
        let n = desc.lights.len().max(1) as f64;
        let default_intensity = 1.0 / n.sqrt();
        let lights = desc
            .lights
            .iter()
            .map(|l: &LightDesc| Light {
                position: v3(&l.position),
                intensity: v3(&l.color.unwrap_or([default_intensity; 3])),
            })
            .collect();
        let mut materials: Vec<Material<T>> =
            desc.materials.iter().map(Material::from_desc).collect();
        if materials.is_empty() {
            materials.push(Material::from_desc(&MaterialDesc::diffuse([1.0; 3])));
        }
        Self {
            camera: desc.camera.clone(),
            background: v3(&desc.background),
            lights,
            materials,
            geometry: Geometry::build(&desc.shapes, accel),
        }
    }

    /// The closest hit along `ray` within its `(t_min, t_max)`.
    #[inline]
    pub fn intersect(&self, ray: &Ray<T>) -> Option<Hit<T>> {
        self.geometry.intersect(ray)
    }

    /// The closest hit along `ray` without its hit record ([`Geometry::cast`]): the
    /// distance, barycentrics and primitive; [`Scene::hit`] completes it.
    #[inline]
    pub fn cast(&self, ray: &Ray<T>) -> Option<Intersection<T>> {
        self.geometry.cast(ray)
    }

    /// The full hit record of what [`Scene::cast`] found for `ray` ([`Geometry::hit`]).
    #[inline]
    pub fn hit(&self, ray: &Ray<T>, found: &Intersection<T>) -> Hit<T> {
        self.geometry.hit(ray, found)
    }

    /// Is anything hit along `ray` within its `(t_min, t_max)`? (Any hit, early exit.)
    #[inline]
    pub fn occluded(&self, ray: &Ray<T>) -> bool {
        self.geometry.occluded(ray)
    }

    /// [`Scene::intersect`] compiled for the primitive kinds in `KINDS` (see
    /// [`Geometry::intersect_kinds`]).
    #[inline]
    pub fn intersect_kinds<const KINDS: u32>(&self, ray: &Ray<T>) -> Option<Hit<T>> {
        self.geometry.intersect_kinds::<KINDS>(ray)
    }

    /// The camera for an image of `width` x `height`.
    pub fn camera_for(&self, width: u32, height: u32) -> Camera<T> {
        Camera::new(&self.camera, width, height)
    }
}

impl Scene<f32> {
    /// The closest hits of a packet of rays ([`Geometry::intersect_packet`]).
    ///
    /// # Panics
    /// If the CPU lacks `isa` or off x86-64.
    pub fn intersect_packet(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
    ) -> [Option<Hit<f32>>; MAX_LANES] {
        self.geometry.intersect_packet(isa, rays)
    }

    /// The closest hits of a packet of rays without their hit records
    /// ([`Geometry::cast_packet`]).
    ///
    /// # Panics
    /// If the CPU lacks `isa` or off x86-64.
    pub fn cast_packet(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
    ) -> [Option<Intersection<f32>>; MAX_LANES] {
        self.geometry.cast_packet(isa, rays)
    }

    /// [`Scene::cast_packet`] into `out` ([`Geometry::cast_packet_into`]): the first
    /// [`Isa::lanes`] entries are written.
    ///
    /// # Panics
    /// If the CPU lacks `isa` or off x86-64.
    #[inline]
    pub fn cast_packet_into(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
        out: &mut [Option<Intersection<f32>>; MAX_LANES],
    ) {
        self.geometry.cast_packet_into(isa, rays, out);
    }

    /// Whether each ray of a packet is blocked ([`Geometry::occluded_packet`]).
    ///
    /// # Panics
    /// If the CPU lacks `isa` or off x86-64.
    pub fn occluded_packet(
        &self,
        isa: Isa,
        rays: &[Option<Ray<f32>>; MAX_LANES],
    ) -> [bool; MAX_LANES] {
        self.geometry.occluded_packet(isa, rays)
    }
}

/// Builds a scene in code: materials, primitives, lights and camera, then
/// [`SceneBuilder::build`] for a precision.
#[derive(Clone, Debug)]
pub struct SceneBuilder {
    desc: SceneDesc,
    accel: AccelOptions,
}

impl Default for SceneBuilder {
    fn default() -> Self {
        Self {
            desc: SceneDesc {
                camera: CameraDesc {
                    from: [0.0, 0.0, 10.0],
                    at: [0.0; 3],
                    up: [0.0, 1.0, 0.0],
                    angle_deg: 45.0,
                    hither: 0.0,
                    resolution: (512, 512),
                },
                background: [0.0; 3],
                lights: Vec::new(),
                materials: Vec::new(),
                shapes: Vec::new(),
            },
            accel: AccelOptions::default(),
        }
    }
}

impl SceneBuilder {
    /// Adds a material and returns its index.
    pub fn add_material(&mut self, m: MaterialDesc) -> u32 {
        self.desc.materials.push(m);
        (self.desc.materials.len() - 1) as u32
    }

    fn push(&mut self, shape: Shape, material: u32) -> u32 {
        self.desc.shapes.push(ShapeDesc {
            shape,
            material,
            line: 0,
        });
        (self.desc.shapes.len() - 1) as u32
    }

    /// Adds a sphere; returns its primitive id.
    pub fn add_sphere(&mut self, center: P3, radius: f64, material: u32) -> u32 {
        self.push(
            Shape::Sphere {
                center,
                radius,
                inside_visible: false,
            },
            material,
        )
    }

    /// Adds a triangle (counter-clockwise seen from its front); returns its primitive id.
    pub fn add_triangle(&mut self, a: P3, b: P3, c: P3, material: u32) -> u32 {
        self.add_polygon(vec![a, b, c], material)
    }

    /// Adds a planar polygon, convex or concave; returns its primitive id.
    pub fn add_polygon(&mut self, vertices: Vec<P3>, material: u32) -> u32 {
        self.push(Shape::Polygon { vertices }, material)
    }

    /// Adds a triangle mesh with optional per-vertex normals; returns the id of its first
    /// triangle (the others follow in order).
    pub fn add_mesh(
        &mut self,
        positions: &[P3],
        triangles: &[[u32; 3]],
        normals: Option<&[P3]>,
        material: u32,
    ) -> u32 {
        let first = self.desc.shapes.len() as u32;
        for t in triangles {
            let vertices = t.iter().map(|&i| positions[i as usize]).collect();
            let shape = match normals {
                Some(n) => Shape::Patch {
                    vertices,
                    normals: t.iter().map(|&i| n[i as usize]).collect(),
                },
                None => Shape::Polygon { vertices },
            };
            self.push(shape, material);
        }
        first
    }

    /// Adds a cone or cylinder without caps.
    pub fn add_cone(
        &mut self,
        base: P3,
        base_radius: f64,
        apex: P3,
        apex_radius: f64,
        material: u32,
    ) -> u32 {
        self.push(
            Shape::Cone {
                base,
                base_radius,
                apex,
                apex_radius,
                inside_visible: false,
            },
            material,
        )
    }

    /// Adds a point light (`None`: the default intensity $1/\sqrt{n}$).
    pub fn add_light(&mut self, position: P3, color: Option<P3>) {
        self.desc.lights.push(LightDesc { position, color });
    }

    /// Sets the background colour.
    pub fn background(&mut self, color: P3) {
        self.desc.background = color;
    }

    /// Places the camera (vertical angle of view in degrees).
    pub fn look_at(&mut self, from: P3, at: P3, up: P3, angle_deg: f64) {
        self.desc.camera.from = from;
        self.desc.camera.at = at;
        self.desc.camera.up = up;
        self.desc.camera.angle_deg = angle_deg;
    }

    /// Sets the acceleration options (BVH or brute force, triangle test).
    pub fn accel(&mut self, accel: AccelOptions) {
        self.accel = accel;
    }

    /// The scene description built so far.
    pub fn desc(&self) -> &SceneDesc {
        &self.desc
    }

    /// Builds the scene in precision `T`.
    pub fn build<T: Float>(&self) -> Scene<T> {
        Scene::from_desc(&self.desc, &self.accel)
    }
}
