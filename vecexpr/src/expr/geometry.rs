//! Geometric kernels on evaluated vectors: the bodies behind `normalize`, `cross`,
//! `reflect` and `refract` of [`Expr`]. Each takes its inputs already evaluated, so a
//! child expression is computed once however often the formula uses it.

use super::{Dim3, Expr};
use crate::scalar::{Mask, Real, Scalar};
use crate::vector::Vector;
use generic_array::ArrayLength;

/// $v / \lVert v \rVert$, with the zero vector mapped to itself and no spurious
/// overflow or underflow (see [`Expr::normalize`]).
#[inline(always)]
pub(crate) fn normalize<T: Scalar, N: ArrayLength>(v: Vector<T, N>) -> Vector<T, N> {
    // No elements: nothing to scale (and no largest magnitude for the slow path).
    if N::USIZE == 0 {
        return v;
    }
    let l2 = (&v).length_squared();
    // Fast path: the squared length is a normal, finite number in every lane.
    let min = T::splat(<T::Elem as Real>::MIN_POSITIVE);
    let max = T::splat(<T::Elem as Real>::MAX);
    let fast = l2.ge(min).and(l2.le(max));
    if T::INLINE_SLOW_PATHS {
        // Explicit SIMD lanes: the slow path stays in the caller (compiled for its
        // instruction set) and replaces only the lanes that need it, so every lane is
        // what the scalar `normalize` gives for that lane's vector.
        let unit = (&v).scale(l2.sqrt().recip()).eval();
        if fast.all() {
            return unit;
        }
        let mut out = rescale(v, l2);
        for (o, &u) in out.iter_mut().zip(unit.iter()) {
            *o = T::select(fast, u, *o);
        }
        return out;
    }
    if fast.all() {
        return (&v).scale(l2.sqrt().recip()).eval();
    }
    normalize_rescaled(v, l2)
}

/// Slow path of [`normalize`], out of line for the whole value.
#[cold]
#[inline(never)]
fn normalize_rescaled<T: Scalar, N: ArrayLength>(v: Vector<T, N>, l2: T) -> Vector<T, N> {
    rescale(v, l2)
}

/// The rescaling of [`normalize`]: divide by the largest magnitude first so the squared
/// length lies in $[1, N]$, then normalise. Lanes whose largest magnitude is zero give
/// zero.
#[inline(always)]
fn rescale<T: Scalar, N: ArrayLength>(v: Vector<T, N>, l2: T) -> Vector<T, N> {
    // The largest magnitude by the one-instruction `Scalar::max` rule, not the
    // NaN-propagating `max_element`: a NaN component is taken care of just below.
    let m = crate::assign::fold1(|i| v[i].abs(), N::USIZE, Scalar::max);
    let zero = T::zero();
    // A NaN component makes l2 NaN but may be skipped by max; keep it NaN.
    let m = T::select(l2.is_nan_mask(), l2, m);
    let is_zero = m.eq_mask(zero);
    let m_safe = T::select(is_zero, T::one(), m);
    let s = (&v).map(|x| x / m_safe).eval();
    let inv = (&s).length_squared().sqrt().recip();
    (&s).map(|x| T::select(is_zero, zero, x * inv)).eval()
}

/// $a \times b = (a_y b_z - a_z b_y,\; a_z b_x - a_x b_z,\; a_x b_y - a_y b_x)$.
#[inline(always)]
pub(crate) fn cross<T: Scalar, N: Dim3>(a: Vector<T, N>, b: Vector<T, N>) -> Vector<T, N> {
    let (a, b) = (a.as_slice(), b.as_slice());
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    // `Dim3` holds only for U3, so `c` fills the vector exactly.
    Vector::from_fn(|i| c[i])
}

/// $R = I - 2 N (N \cdot I)$.
#[inline(always)]
pub(crate) fn reflect<T: Scalar, N: ArrayLength>(i: Vector<T, N>, n: Vector<T, N>) -> Vector<T, N> {
    let d = (&n).dot(&i);
    (&i - (&n).scale(d + d)).eval()
}

/// Snell refraction; returns the direction (zero where totally internally reflected)
/// and the mask of lanes that refracted.
#[inline(always)]
pub(crate) fn refract<T: Scalar, N: ArrayLength>(
    i: Vector<T, N>,
    n: Vector<T, N>,
    eta: T,
) -> (Vector<T, N>, T::Mask) {
    let ni = (&n).dot(&i);
    let one = T::one();
    // k = 1 - eta^2 (1 - (N.I)^2)
    let k = one - eta * eta * (one - ni * ni);
    let ok = k.ge(T::zero());
    let root = T::select(ok, k, T::zero()).sqrt();
    let a = T::select(ok, eta, T::zero());
    let b = T::select(ok, eta * ni + root, T::zero());
    // T = eta I - (eta (N.I) + sqrt(k)) N
    let t = ((&i).scale(a) - (&n).scale(b)).eval();
    (t, ok)
}

#[cfg(test)]
mod tests {
    use crate::{vec3, Expr};

    #[test]
    fn normalize_extremes() {
        let tiny = vec3(1e-30f32, 0.0, 0.0).normalize();
        assert_eq!(tiny, vec3(1.0, 0.0, 0.0));
        let huge = vec3(1e30f32, 1e30, 0.0).normalize();
        assert!((huge[0] - core::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6);
        let sub = vec3(f32::from_bits(1), 0.0, 0.0).normalize();
        assert_eq!(sub, vec3(1.0, 0.0, 0.0));
        assert_eq!(vec3(0.0f64, -0.0, 0.0).normalize(), vec3(0.0, 0.0, 0.0));
        assert!(vec3(f32::NAN, 0.0, 0.0).normalize()[0].is_nan());
    }
}
