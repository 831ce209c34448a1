//! Rays and hit records, generic over the scalar precision.

use vecexpr::{Real, Vec3};

/// A ray $o + t d$ for $t \in (t_{min}, t_{max})$. `dir` need not be unit length, but
/// the tracer always passes unit directions so `t` is a distance.
#[derive(Clone, Copy, Debug)]
pub struct Ray<T: Real> {
    /// Origin $o$.
    pub origin: Vec3<T>,
    /// Direction $d$.
    pub dir: Vec3<T>,
    /// Smallest accepted parameter (exclusive).
    pub t_min: T,
    /// Largest accepted parameter (exclusive).
    pub t_max: T,
}

impl<T: Real> Ray<T> {
    /// A ray over $(0, \infty)$.
    #[inline]
    pub fn new(origin: Vec3<T>, dir: Vec3<T>) -> Self {
        Self {
            origin,
            dir,
            t_min: T::ZERO,
            t_max: T::INFINITY,
        }
    }

    /// The point $o + t d$.
    #[inline]
    pub fn at(&self, t: T) -> Vec3<T> {
        use vecexpr::Expr;
        (&self.origin + (&self.dir).scale(t)).eval()
    }
}

/// The closest intersection of a ray with the scene.
#[derive(Clone, Copy, Debug)]
pub struct Hit<T: Real> {
    /// Ray parameter of the hit.
    pub t: T,
    /// The hit point.
    pub point: Vec3<T>,
    /// Unit geometric normal of the surface, in the primitive's own orientation
    /// (outward for spheres and cones, by the vertex winding for polygons); not flipped
    /// toward the ray.
    pub geometric_normal: Vec3<T>,
    /// Unit shading normal (interpolated for `pp` patches and OBJ vertex normals, else
    /// the geometric normal), in the same hemisphere as `geometric_normal`.
    pub shading_normal: Vec3<T>,
    /// Index of the primitive in input order (one per NFF primitive or OBJ face).
    pub prim_id: u32,
    /// Index of the material.
    pub material: u32,
}
