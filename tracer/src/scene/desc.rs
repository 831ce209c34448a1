//! The scene as read from a file: plain `f64` data, before any acceleration structure.
//!
//! Both the NFF and the OBJ reader produce a [`SceneDesc`]; the renderer converts it into
//! a [`crate::Scene`] of the chosen precision.

/// A point or direction in file coordinates.
pub type P3 = [f64; 3];

/// The camera as NFF's `v` block gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    /// Eye position.
    pub from: P3,
    /// Point at the centre of the image.
    pub at: P3,
    /// Up direction (not necessarily perpendicular to the view direction).
    pub up: P3,
    /// Full vertical angle of view in degrees, from the centre of the top pixel row to the
    /// centre of the bottom row.
    pub angle_deg: f64,
    /// Near distance (kept for completeness; rays start at the eye).
    pub hither: f64,
    /// Image width and height in pixels.
    pub resolution: (u32, u32),
}

/// A point light.
#[derive(Clone, Debug, PartialEq)]
pub struct LightDesc {
    /// Position.
    pub position: P3,
    /// Colour if the file gives one (NFF `l x y z r g b`).
    pub color: Option<P3>,
}

/// NFF's material: `f r g b Kd Ks Shine T ior`.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialDesc {
    /// Surface colour.
    pub color: P3,
    /// Diffuse weight.
    pub kd: f64,
    /// Specular and mirror-reflection weight.
    pub ks: f64,
    /// Phong exponent.
    pub shine: f64,
    /// Transmitted fraction.
    pub t: f64,
    /// Index of refraction.
    pub ior: f64,
}

/// One geometric primitive.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// `s`: sphere; a negative radius in the file means the inside is visible, kept here
    /// as `inside_visible` with a positive `radius`.
    Sphere {
        /// Centre.
        center: P3,
        /// Radius (positive).
        radius: f64,
        /// The file gave a negative radius: normals point inward.
        inside_visible: bool,
    },
    /// `c`: a cone or cylinder without caps, from base centre and radius to apex centre
    /// and radius; negative radii mean the inside is visible (kept as magnitudes here).
    Cone {
        /// Base centre.
        base: P3,
        /// Base radius (non-negative).
        base_radius: f64,
        /// Apex centre.
        apex: P3,
        /// Apex radius (non-negative).
        apex_radius: f64,
        /// The file gave negative radii: normals point inward.
        inside_visible: bool,
    },
    /// `p`: a planar polygon, convex or concave, counter-clockwise from the visible side.
    Polygon {
        /// Vertices in order.
        vertices: Vec<P3>,
    },
    /// `pp`: a polygon with a normal per vertex, smooth shaded.
    Patch {
        /// Vertices in order.
        vertices: Vec<P3>,
        /// One normal per vertex (may be zero or unnormalised in bad files).
        normals: Vec<P3>,
    },
}

/// A primitive with its material and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeDesc {
    /// The geometry.
    pub shape: Shape,
    /// Index into [`SceneDesc::materials`].
    pub material: u32,
    /// 1-based line in the source file where the primitive starts.
    pub line: u32,
}

/// A whole scene file.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneDesc {
    /// The camera (NFF `v`; a default framing for OBJ).
    pub camera: CameraDesc,
    /// Background colour (NFF `b`), black if absent.
    pub background: P3,
    /// Point lights.
    pub lights: Vec<LightDesc>,
    /// Materials in order of appearance.
    pub materials: Vec<MaterialDesc>,
    /// Primitives in file order.
    pub shapes: Vec<ShapeDesc>,
}

impl MaterialDesc {
    /// A matte material of the given colour (`Kd = 0.8`, so ambient 0.2).
    pub fn diffuse(color: P3) -> Self {
        Self {
            color,
            kd: 0.8,
            ks: 0.0,
            shine: 0.0,
            t: 0.0,
            ior: 1.0,
        }
    }

    /// A mirror: `Kd = 0.3`, `Ks = 0.7`, highlight exponent 50.
    pub fn mirror(color: P3) -> Self {
        Self {
            color,
            kd: 0.3,
            ks: 0.7,
            shine: 50.0,
            t: 0.0,
            ior: 1.0,
        }
    }

    /// Clear glass: `Kd = 0.05`, `Ks = 0.1`, `T = 0.85`, the given index of refraction.
    pub fn glass(ior: f64) -> Self {
        Self {
            color: [1.0; 3],
            kd: 0.05,
            ks: 0.1,
            shine: 200.0,
            t: 0.85,
            ior,
        }
    }
}
