//! Generic kernels written once with vecexpr and instantiated by the probes for several
//! scalar types (plain floats and SoA packets).

use vecexpr::{Expr, Mask, Real, Scalar, Vec3};

/// $a b + c d - e$, element-wise, evaluated in one fused loop into `out`.
#[inline(always)]
pub fn abcde<T: Scalar, N: vecexpr::generic_array::ArrayLength>(
    [a, b, c, d, e]: [&vecexpr::Vector<T, N>; 5],
    out: &mut vecexpr::Vector<T, N>,
) {
    out.assign(a * b + c * d - e);
}

/// A 3×3 matrix, given by its columns, times a vector:
/// $M v = c_0 v_x + c_1 v_y + c_2 v_z$, one fused expression.
#[inline(always)]
pub fn mat3_mul<T: Scalar>(cols: &[Vec3<T>; 3], v: &Vec3<T>) -> Vec3<T> {
    ((&cols[0]).scale(v.x()) + (&cols[1]).scale(v.y()) + (&cols[2]).scale(v.z())).eval()
}

/// The mirror direction of `i` about the unit normal `n`, normalised:
/// $\hat R$ with $R = I - 2 N (N \cdot I)$, the secondary-ray step of a Whitted tracer.
#[inline(always)]
pub fn reflect_normalize<T: Scalar>(i: &Vec3<T>, n: &Vec3<T>) -> Vec3<T> {
    i.reflect(n).normalize()
}

/// Nearest intersection distance of the ray $o + t d$ ($t > t_{min}$) with the sphere
/// of centre `center` and radius `radius`, or $+\infty$ for a miss; per lane for
/// packets, with no branch.
///
/// With $oc = o - c$, $a = d \cdot d$, $h = oc \cdot d$ and
/// $k = oc \cdot oc - r^2$, the hits solve $a t^2 + 2 h t + k = 0$:
/// $t = (-h \mp \sqrt{h^2 - a k}) / a$ (the "half b" form of the quadratic, as in
/// Shirley, *Ray Tracing in One Weekend*, section 6.2). The nearer root is taken if it
/// lies beyond $t_{min}$, else the farther one.
#[inline(always)]
pub fn sphere_hit<T: Scalar>(o: &Vec3<T>, d: &Vec3<T>, center: &Vec3<T>, radius: T, t_min: T) -> T {
    let oc = (o - center).eval();
    let a = d.length_squared();
    let h = (&oc).dot(d);
    let k = (&oc).length_squared() - radius * radius;
    let disc = h * h - a * k;
    let hit = disc.ge(T::zero());
    let root = T::select(hit, disc, T::zero()).sqrt();
    let inv_a = a.recip();
    let near = (-h - root) * inv_a;
    let far = (-h + root) * inv_a;
    let t = T::select(near.gt(t_min), near, far);
    let ok = hit.and(t.gt(t_min));
    T::select(ok, t, T::splat(<T::Elem as Real>::INFINITY))
}

#[cfg(test)]
mod tests {
    use super::*;
    use vecexpr::{typenum::U8, vec3, Packet};

    #[test]
    fn sphere_hits_and_misses() {
        let c = vec3(0.0f32, 0.0, -5.0);
        let o = vec3(0.0f32, 0.0, 0.0);
        // Straight at the centre: front face at t = 4.
        assert_eq!(sphere_hit(&o, &vec3(0.0, 0.0, -1.0), &c, 1.0, 1e-4), 4.0);
        // A non-unit direction scales t.
        assert_eq!(sphere_hit(&o, &vec3(0.0, 0.0, -2.0), &c, 1.0, 1e-4), 2.0);
        // Away from the sphere, and beside it.
        assert_eq!(
            sphere_hit(&o, &vec3(0.0, 0.0, 1.0), &c, 1.0, 1e-4),
            f32::INFINITY
        );
        assert_eq!(
            sphere_hit(&o, &vec3(1.0, 0.0, 0.0), &c, 1.0, 1e-4),
            f32::INFINITY
        );
        // From inside: the far root.
        assert_eq!(sphere_hit(&c, &vec3(0.0, 1.0, 0.0), &c, 1.0, 1e-4), 1.0);
        // Packets agree lane by lane with the scalar version.
        type P = Packet<f32, U8>;
        let dirs = [0.0f32, 0.1, -0.1, 0.3, 1.0, -2.0, 0.05, 0.2];
        let d = Vec3::<P>::from_fn(|k| P::from_fn(|l| [dirs[l], 0.0, -1.0][k]));
        let pc = Vec3::<P>::from_fn(|k| P::splat(c[k]));
        let po = Vec3::<P>::splat(P::splat(0.0));
        let t = sphere_hit(&po, &d, &pc, P::splat(1.0), P::splat(1e-4));
        for (l, &x) in dirs.iter().enumerate() {
            assert_eq!(
                t.lane(l),
                sphere_hit(&o, &vec3(x, 0.0, -1.0), &c, 1.0, 1e-4)
            );
        }
    }

    #[test]
    fn mat3_is_column_major() {
        let cols = [
            vec3(1.0f32, 2.0, 3.0),
            vec3(4.0, 5.0, 6.0),
            vec3(7.0, 8.0, 9.0),
        ];
        assert_eq!(mat3_mul(&cols, &vec3(1.0, 0.0, 0.0)), cols[0]);
        assert_eq!(
            mat3_mul(&cols, &vec3(1.0, 1.0, 1.0)),
            vec3(12.0, 15.0, 18.0)
        );
    }
}
