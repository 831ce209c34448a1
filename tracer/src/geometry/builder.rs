//! Building a [`Geometry`] in code, one primitive at a time (the library API, in the
//! manner of Embree's `rtcNewGeometry`/`rtcCommitScene`).

use super::cone::Cone;
use super::plane::Plane;
use super::polygon::triangulate;
use super::sphere::Sphere;
use super::storage::{PrimInfo, Prims, TriangleInfo, MAX_PER_TYPE, NO_SHADING};
use super::triangle::Triangle;
use super::{AccelOptions, Geometry};
use crate::scene::desc::{Shape, ShapeDesc, P3};
use vecexpr::{vec3, Expr, Real, Vec3};

/// Collects primitives, then [`GeometryBuilder::build`] makes the [`Geometry`].
///
/// Every `add_*` call takes the next primitive id (reported as [`crate::Hit::prim_id`]),
/// starting at 0, whether or not the primitive turns out degenerate and is skipped;
/// [`GeometryBuilder::add_mesh`] takes one id per triangle. Degenerate input (zero
/// radius or area, non-finite coordinates, out-of-range mesh indices) is skipped and
/// counted in [`super::GeometryStats::skipped`]; nothing here panics on bad data.
///
/// # Examples
/// ```
/// use tracer::geometry::{AccelOptions, GeometryBuilder};
/// use tracer::Ray;
/// use vecexpr::vec3;
///
/// let geometry = GeometryBuilder::<f32>::new()
///     .add_sphere(vec3(0.0, 0.0, 0.0), 1.0, 0)
///     .add_triangle(vec3(-5.0, -2.0, -5.0), vec3(0.0, -2.0, 5.0), vec3(5.0, -2.0, -5.0), 1)
///     .build(&AccelOptions::default());
/// let hit = geometry.intersect(&Ray::new(vec3(0.0, 0.0, 5.0), vec3(0.0, 0.0, -1.0))).unwrap();
/// assert_eq!((hit.t, hit.prim_id), (4.0, 0));
/// let floor = geometry.intersect(&Ray::new(vec3(0.0, 5.0, 2.0), vec3(0.0, -1.0, 0.0))).unwrap();
/// assert_eq!((floor.t, floor.prim_id, floor.material), (7.0, 1, 1));
/// ```
#[derive(Clone, Debug)]
pub struct GeometryBuilder<T: Real> {
    next_id: u32,
    pub(crate) prims: Prims<T>,
    pub(crate) polygons: usize,
    pub(crate) patches: usize,
    pub(crate) skipped: usize,
}

impl<T: Real> Default for GeometryBuilder<T> {
    fn default() -> Self {
        Self::new()
    }
}

fn to_t<T: Real>(p: &P3) -> Vec3<T> {
    vec3(
        <T as Real>::from_f64(p[0]),
        <T as Real>::from_f64(p[1]),
        <T as Real>::from_f64(p[2]),
    )
}

fn finite<T: Real>(v: &Vec3<T>) -> bool {
    v.iter().all(|x| x.is_finite())
}

impl<T: Real> GeometryBuilder<T> {
    /// An empty builder.
    pub fn new() -> Self {
        Self {
            next_id: 0,
            prims: Prims::default(),
            polygons: 0,
            patches: 0,
            skipped: 0,
        }
    }

    /// The id the next added primitive will get.
    pub fn next_prim_id(&self) -> u32 {
        self.next_id
    }

    /// Makes the next primitive take id `id` (ids after it continue from `id + 1`).
    pub fn set_next_prim_id(&mut self, id: u32) {
        self.next_id = id;
    }

    fn take_id(&mut self) -> u32 {
        let id = self.next_id;
        self.next_id = self.next_id.wrapping_add(1);
        id
    }

    /// Adds a sphere. A negative radius means the inside is visible (normals point in),
    /// as in NFF.
    #[must_use = "the builder is returned by value"]
    pub fn add_sphere(mut self, center: Vec3<T>, radius: T, material: u32) -> Self {
        let id = self.take_id();
        self.push_sphere(id, center, radius.abs(), radius < T::ZERO, material);
        self
    }

    /// Adds a cone or cylinder without caps from the base centre and radius to the apex
    /// centre and radius. A negative radius means the inside is visible.
    #[must_use = "the builder is returned by value"]
    pub fn add_cone(
        mut self,
        base: Vec3<T>,
        base_radius: T,
        apex: Vec3<T>,
        apex_radius: T,
        material: u32,
    ) -> Self {
        let id = self.take_id();
        let inside = base_radius < T::ZERO || apex_radius < T::ZERO;
        self.push_cone(
            id,
            base,
            base_radius.abs(),
            apex,
            apex_radius.abs(),
            inside,
            material,
        );
        self
    }

    /// Adds a triangle, counter-clockwise seen from its front.
    #[must_use = "the builder is returned by value"]
    pub fn add_triangle(mut self, a: Vec3<T>, b: Vec3<T>, c: Vec3<T>, material: u32) -> Self {
        let id = self.take_id();
        self.push_polygon(id, &[a, b, c], None, material);
        self
    }

    /// Adds a planar polygon, convex or concave, counter-clockwise seen from its front;
    /// it is triangulated, and all its triangles report its id.
    #[must_use = "the builder is returned by value"]
    pub fn add_polygon(mut self, vertices: &[Vec3<T>], material: u32) -> Self {
        let id = self.take_id();
        self.polygons += 1;
        self.push_polygon(id, vertices, None, material);
        self
    }

    /// Adds a polygon with one normal per vertex, smooth shaded (NFF `pp`). With a
    /// different number of normals than vertices it is shaded flat.
    #[must_use = "the builder is returned by value"]
    pub fn add_patch(mut self, vertices: &[Vec3<T>], normals: &[Vec3<T>], material: u32) -> Self {
        let id = self.take_id();
        self.patches += 1;
        let normals = (normals.len() == vertices.len()).then_some(normals);
        self.push_polygon(id, vertices, normals, material);
        self
    }

    /// Adds an indexed triangle mesh, optionally with per-vertex normals (one per
    /// position). Each triangle takes its own id, in order. Triangles with an index out
    /// of range are skipped; normals of the wrong count are ignored.
    #[must_use = "the builder is returned by value"]
    pub fn add_mesh(
        mut self,
        positions: &[Vec3<T>],
        indices: &[[u32; 3]],
        normals: Option<&[Vec3<T>]>,
        material: u32,
    ) -> Self {
        let normals = normals.filter(|n| n.len() == positions.len());
        for tri in indices {
            let id = self.take_id();
            let get = |s: &[Vec3<T>]| -> Option<[Vec3<T>; 3]> {
                Some([
                    *s.get(tri[0] as usize)?,
                    *s.get(tri[1] as usize)?,
                    *s.get(tri[2] as usize)?,
                ])
            };
            match get(positions) {
                Some(v) => {
                    let n = normals.and_then(get);
                    self.push_polygon(id, &v, n.as_ref().map(|n| n.as_slice()), material);
                }
                None => self.skipped += 1,
            }
        }
        self
    }

    /// Adds an infinite plane through `point` with front side `normal`. Planes are kept
    /// outside the BVH and tested on every ray.
    #[must_use = "the builder is returned by value"]
    pub fn add_plane(mut self, point: Vec3<T>, normal: Vec3<T>, material: u32) -> Self {
        let id = self.take_id();
        match Plane::new(point, normal) {
            Some(p) if self.prims.planes.len() < MAX_PER_TYPE => {
                self.prims.planes.push(p);
                self.prims.plane_info.push(PrimInfo {
                    prim_id: id,
                    material,
                    inside_visible: false,
                });
            }
            _ => self.skipped += 1,
        }
        self
    }

    /// Adds a parsed primitive, converting its `f64` data to `T`.
    #[must_use = "the builder is returned by value"]
    pub fn add_shape(mut self, shape: &ShapeDesc) -> Self {
        let id = self.take_id();
        self.push_shape(id, shape);
        self
    }

    /// Builds the BVH (per `opts`) and returns the finished geometry.
    pub fn build(self, opts: &AccelOptions) -> Geometry<T>
    where
        T: crate::float::Float,
    {
        Geometry::from_builder(self, opts, std::time::Instant::now())
    }

    /// Reserves room for the primitives `shapes` will add, so that large scenes are not
    /// built by repeated doubling (which would briefly need up to twice the memory).
    pub(crate) fn reserve_for(&mut self, shapes: &[ShapeDesc]) {
        let (mut spheres, mut cones, mut triangles, mut shaded) = (0, 0, 0, 0);
        for s in shapes {
            match &s.shape {
                Shape::Sphere { .. } => spheres += 1,
                Shape::Cone { .. } => cones += 1,
                Shape::Polygon { vertices } => triangles += vertices.len().saturating_sub(2),
                Shape::Patch { vertices, .. } => {
                    triangles += vertices.len().saturating_sub(2);
                    shaded += vertices.len().saturating_sub(2);
                }
            }
        }
        use crate::pages::reserve;
        let p = &mut self.prims;
        reserve(&mut p.spheres, spheres);
        reserve(&mut p.sphere_info, spheres);
        reserve(&mut p.cones, cones);
        reserve(&mut p.cone_info, cones);
        reserve(&mut p.triangles, triangles);
        reserve(&mut p.triangle_info, triangles);
        reserve(&mut p.shading, shaded);
    }

    pub(crate) fn push_shape(&mut self, id: u32, shape: &ShapeDesc) {
        let m = shape.material;
        match &shape.shape {
            Shape::Sphere {
                center,
                radius,
                inside_visible,
            } => self.push_sphere(
                id,
                to_t(center),
                <T as Real>::from_f64(radius.abs()),
                *inside_visible,
                m,
            ),
            Shape::Cone {
                base,
                base_radius,
                apex,
                apex_radius,
                inside_visible,
            } => self.push_cone(
                id,
                to_t(base),
                <T as Real>::from_f64(base_radius.abs()),
                to_t(apex),
                <T as Real>::from_f64(apex_radius.abs()),
                *inside_visible,
                m,
            ),
            Shape::Polygon { vertices } => {
                self.polygons += 1;
                let v: Vec<Vec3<T>> = vertices.iter().map(to_t).collect();
                self.push_polygon(id, &v, None, m);
            }
            Shape::Patch { vertices, normals } => {
                self.patches += 1;
                let v: Vec<Vec3<T>> = vertices.iter().map(to_t).collect();
                let n: Vec<Vec3<T>> = normals.iter().map(to_t).collect();
                let n = (n.len() == v.len()).then_some(n.as_slice());
                self.push_polygon(id, &v, n, m);
            }
        }
    }

    fn push_sphere(
        &mut self,
        id: u32,
        center: Vec3<T>,
        radius: T,
        inside_visible: bool,
        material: u32,
    ) {
        let ok = finite(&center)
            && radius.is_finite()
            && radius > T::ZERO
            && (radius * radius) > T::ZERO
            && self.prims.spheres.len() < MAX_PER_TYPE;
        if !ok {
            self.skipped += 1;
            return;
        }
        self.prims.spheres.push(Sphere { center, radius });
        self.prims.sphere_info.push(PrimInfo {
            prim_id: id,
            material,
            inside_visible,
        });
    }

    #[allow(clippy::too_many_arguments)]
    fn push_cone(
        &mut self,
        id: u32,
        base: Vec3<T>,
        base_radius: T,
        apex: Vec3<T>,
        apex_radius: T,
        inside_visible: bool,
        material: u32,
    ) {
        match Cone::new(base, base_radius, apex, apex_radius) {
            Some(c) if self.prims.cones.len() < MAX_PER_TYPE => {
                self.prims.cones.push(c);
                self.prims.cone_info.push(PrimInfo {
                    prim_id: id,
                    material,
                    inside_visible,
                });
            }
            _ => self.skipped += 1,
        }
    }

    /// Triangulates (in `f64`) and stores the triangles that keep a non-zero area in `T`.
    fn push_polygon(
        &mut self,
        id: u32,
        vertices: &[Vec3<T>],
        normals: Option<&[Vec3<T>]>,
        material: u32,
    ) {
        let v64: Vec<[f64; 3]> = vertices
            .iter()
            .map(|p| [p[0].to_f64(), p[1].to_f64(), p[2].to_f64()])
            .collect();
        let Some(tri) = triangulate(&v64) else {
            self.skipped += 1;
            return;
        };
        let c = |x: f64| <T as Real>::from_f64(x);
        let normal = vec3(c(tri.normal[0]), c(tri.normal[1]), c(tri.normal[2])).normalize();
        let unit = |n: &Vec3<T>| {
            let u = n.normalize();
            if finite(&u) {
                u
            } else {
                Vec3::zero()
            }
        };
        let before = self.prims.triangles.len();
        for (sub, t) in tri.triangles.iter().enumerate() {
            let v = t.map(|i| vertices[i as usize]);
            let triangle = Triangle { v };
            let area = triangle.area_vector().length_squared();
            if !(area > T::ZERO && area.is_finite()) || self.prims.triangles.len() >= MAX_PER_TYPE {
                continue;
            }
            let shading = match normals {
                Some(n) => {
                    self.prims.shading.push(t.map(|i| unit(&n[i as usize])));
                    (self.prims.shading.len() - 1) as u32
                }
                None => NO_SHADING,
            };
            self.prims.triangles.push(triangle);
            self.prims.triangle_info.push(TriangleInfo {
                prim_id: id,
                material,
                sub: sub as u32,
                shading,
                normal,
            });
        }
        if self.prims.triangles.len() == before {
            self.skipped += 1;
        }
    }
}
