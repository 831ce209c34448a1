//! Spawning secondary rays without self-intersection.
//!
//! C. Wächter, N. Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray
//! Tracing Gems (2019), chapter 6. A computed hit point lies within a few hundred ulps of
//! the true surface *in each coordinate*, because the kernels reconstruct it from
//! barycentrics (triangles) or project it back onto the surface (spheres, cones, planes)
//! instead of evaluating $o + t d$. So the new origin is moved along the geometric normal
//! by an integer number of ulps per coordinate, `256 n_i` (truncated), which is scale
//! invariant: it is as safe at $10^5$ as at $10^{-3}$. Near zero the ulp becomes
//! arbitrarily small while the error of a point reconstructed from vertices far from zero
//! does not, so coordinates with $|p_i| < 1/32$ get a fixed absolute offset instead,
//! `n_i / 65536` in `f32`.
//!
//! The constants are the paper's, for `f32`. In `f64` the ulp count is the same (the
//! kernels' error in ulps does not depend on the width) and the absolute offset near zero
//! is scaled by the ratio of the two machine epsilons, $2^{-29}$.

use vecexpr::{Real, Vec3};

/// Below this magnitude a coordinate is offset by an absolute amount (RTG ch. 6 `origin()`).
const ORIGIN: f64 = 1.0 / 32.0;
/// Absolute offset per unit of normal for `f32` near zero (RTG ch. 6 `float_scale()`).
const FLOAT_SCALE_F32: f64 = 1.0 / 65536.0;
/// Ulps of offset per unit of normal (RTG ch. 6 `int_scale()`).
const INT_SCALE: f64 = 256.0;

/// Moves `x` by `k` ulps toward $+\infty$ if `k > 0`, toward $-\infty$ if `k < 0`, by
/// adding `k` to the magnitude bits (which walks across binades exactly). For finite `x`
/// with $|x| \ge$ [`ORIGIN`] (normal, so the step cannot cross zero) the result is that
/// value; for any other `x` it is meaningless but defined, and [`offset_ray`] discards
/// it.
#[inline(always)]
fn step_ulps<T: Real>(x: T, k: i32) -> T {
    // Plain casts through the IEEE layouts of f32 and f64; T is one of the two and the
    // branch is resolved at compile time.
    let k = if x < T::ZERO { k.wrapping_neg() } else { k };
    if T::MANTISSA_DIGITS == f32::MANTISSA_DIGITS {
        let b = (x.to_f64() as f32).to_bits();
        <T as Real>::from_f64(f64::from(f32::from_bits(b.wrapping_add_signed(k))))
    } else {
        let b = x.to_f64().to_bits();
        <T as Real>::from_f64(f64::from_bits(b.wrapping_add_signed(i64::from(k))))
    }
}

/// The origin for a ray leaving the surface at `p` in direction `dir`: `p` moved along
/// the unit geometric normal `n` (either orientation) to the side `dir` points into
/// (Wächter and Binder, Ray Tracing Gems ch. 6; the side chosen by the new direction as
/// pbrt-v4's `OffsetRayOrigin` does).
///
/// Choosing the side by the outgoing direction rather than by the incoming ray matters at
/// grazing hits: there the computed hit can land on either side of the tangent point, so
/// the incoming ray's side is noise, while the spawned ray's own direction is not.
/// Non-finite coordinates stay non-finite, so a ray from a broken hit is rejected by the
/// intersection kernels rather than started somewhere arbitrary.
///
/// # Examples
/// ```
/// use tracer::geometry::offset_ray;
/// use vecexpr::vec3;
///
/// let p = vec3(1.0e5f32, 0.0, 2.0);
/// let n = vec3(1.0, 0.0, 0.0);
/// // 256 ulps of 1e5 in x (about 2), nothing in y and z.
/// let out = offset_ray(&p, &n, &vec3(0.6, 0.8, 0.0));
/// assert_eq!(out[0], f32::from_bits(p[0].to_bits() + 256));
/// assert_eq!((out[1], out[2]), (0.0, 2.0));
/// // A ray going the other way starts on the other side.
/// let into = offset_ray(&p, &n, &vec3(-0.6, 0.8, 0.0));
/// assert_eq!(into[0], f32::from_bits(p[0].to_bits() - 256));
/// ```
#[inline]
pub fn offset_ray<T: Real>(p: &Vec3<T>, n: &Vec3<T>, dir: &Vec3<T>) -> Vec3<T> {
    let side = if leaves_behind(n, dir) {
        -T::ONE
    } else {
        T::ONE
    };
    let origin = <T as Real>::from_f64(ORIGIN);
    let float_scale =
        <T as Real>::from_f64(FLOAT_SCALE_F32 * (T::EPSILON.to_f64() / f64::from(f32::EPSILON)));
    let int_scale = <T as Real>::from_f64(INT_SCALE);
    let mut out = *p;
    for i in 0..3 {
        let (x, ni) = (p[i], side * n[i]);
        // Both offsets are computed and one selected, without a branch: which one a
        // coordinate takes varies from hit to hit.
        // Near zero, or NaN/inf (arithmetic keeps it non-finite): an absolute offset.
        let near = x + float_scale * ni;
        // Elsewhere `k` ulps, truncated toward zero as the paper's int conversion
        // (saturating, so a non-finite `ni`, whose result is discarded, stays defined).
        let k = (int_scale * ni).to_f64() as i32;
        let stepped = step_ulps(x, k);
        let use_near = x.abs() < origin || !x.is_finite() || !ni.is_finite();
        out[i] = if use_near { near } else { stepped };
    }
    out
}

/// Does `dir` point to the side opposite to `n`? The one thing [`offset_ray`] reads from
/// the direction.
#[inline(always)]
fn leaves_behind<T: Real>(n: &Vec3<T>, dir: &Vec3<T>) -> bool {
    n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2] < T::ZERO
}

/// [`offset_ray`]`(p, n, dir)` given `front = offset_ray(p, n, n)`, the origin of rays
/// leaving on the side `n` points to: the direction only picks the side, so a ray on
/// that side starts at `front` and only one into the other side computes its origin.
/// The same value as [`offset_ray`], bit for bit.
#[inline(always)]
pub fn offset_ray_from<T: Real>(
    p: &Vec3<T>,
    n: &Vec3<T>,
    front: &Vec3<T>,
    dir: &Vec3<T>,
) -> Vec3<T> {
    if leaves_behind(n, dir) {
        offset_ray(p, n, dir)
    } else {
        *front
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vecexpr::vec3;

    #[test]
    fn moves_by_ulps_along_the_normal() {
        let p = vec3(-3.0f32, 1.0e5, 0.01);
        let s = 0.5f32.sqrt();
        let n = vec3(s, -s, 0.0);
        let q = offset_ray(&p, &n, &n);
        // 256 * 0.7071 = 181 ulps: toward +inf in x (magnitude down for a negative
        // value), toward -inf in y.
        assert_eq!(q[0].to_bits(), (-3.0f32).to_bits() - 181);
        assert_eq!(q[1].to_bits(), 1.0e5f32.to_bits() - 181);
        assert_eq!(q[2], 0.01);
        assert!(q[0] > p[0] && q[1] < p[1]);
    }

    #[test]
    fn absolute_offset_near_zero_and_binade_crossing() {
        let n = vec3(0.0, 0.0, -1.0);
        let q = offset_ray(&vec3(0.0f64, -0.0, 1.0e-3), &n, &n);
        assert_eq!(q[2], 1.0e-3 - 2f64.powi(-45));
        // One ulp below 2: the step walks into the next binade by integer bits.
        let x = 2.0f32.next_down();
        let n = vec3(1.0, 0.0, 0.0);
        let q = offset_ray(&vec3(x, 1.0, 1.0), &n, &n);
        assert_eq!(q[0].to_bits(), x.to_bits() + 256);
        assert!(q[0] > 2.0);
    }

    #[test]
    fn non_finite_input_stays_non_finite() {
        let n = vec3(0.0, 1.0, 0.0);
        let q = offset_ray(&vec3(f32::NAN, 1.0, f32::INFINITY), &n, &n);
        assert!(q[0].is_nan() && q[2].is_infinite());
        let n = vec3(f32::NAN, 0.0, 0.0);
        let q = offset_ray(&vec3(1.0f32, 1.0, 1.0), &n, &n);
        assert!(q[0].is_nan());
    }

    #[test]
    fn the_front_origin_serves_every_direction_on_its_side() {
        let dirs = [
            vec3(0.6f32, 0.8, 0.0),
            vec3(-0.6, 0.8, 0.0),
            vec3(0.0, 0.0, 1.0),
            vec3(0.0, -1.0, 0.0),
            vec3(f32::NAN, 0.0, 0.0),
        ];
        for p in [vec3(1.0e5f32, 0.01, -3.0), vec3(0.0, 2.0, 1.0e-3)] {
            for n in [vec3(0.0f32, 1.0, 0.0), vec3(0.6, 0.0, -0.8)] {
                let front = offset_ray(&p, &n, &n);
                for d in &dirs {
                    let a = offset_ray(&p, &n, d);
                    let b = offset_ray_from(&p, &n, &front, d);
                    let bits = |v: &Vec3<f32>| [0, 1, 2].map(|i| v[i].to_bits());
                    assert_eq!(bits(&a), bits(&b), "{p:?} {n:?} {d:?}");
                }
            }
        }
    }
}
