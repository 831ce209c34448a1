//! Rays and hit records, generic over the scalar precision.

use vecexpr::{Real, Vec3};

/// A ray $o + t d$ for $t \in (t_{min}, t_{max})$. `dir` need not be unit length, but
/// the tracer always passes unit directions so `t` is a distance.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
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

// `Ray<f32>` is eight `f32`s in a row: `Vec3` is `repr(transparent)` over `[f32; 3]`.
const _: () = {
    assert!(core::mem::size_of::<Ray<f32>>() == 32);
    assert!(core::mem::align_of::<Ray<f32>>() == 4);
    assert!(core::mem::offset_of!(Ray<f32>, dir) == 12);
    assert!(core::mem::offset_of!(Ray<f32>, t_min) == 24);
    assert!(core::mem::offset_of!(Ray<f32>, t_max) == 28);
};

impl Ray<f32> {
    /// The ray as its eight values: origin, direction, `t_min`, `t_max` (for loading
    /// rays into SIMD lanes, [`vecexpr::simd::SimdF32::transpose8`]).
    #[inline(always)]
    pub fn values(&self) -> &[f32; 8] {
        // SAFETY: `Ray<f32>` is `repr(C)` with fields origin (`Vec3<f32>`, which is
        // `repr(transparent)` over `[f32; 3]`), dir (the same), `t_min` and `t_max`: 32
        // bytes of eight `f32`s without padding, aligned as `f32` (the assertions above),
        // so it has the layout of `[f32; 8]`. The reference borrows `self`.
        unsafe { &*(self as *const Self).cast::<[f32; 8]>() }
    }
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
