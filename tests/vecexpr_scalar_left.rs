//! A plain float on the left of an operator: `2.0 * &v` compiles wherever `&v * 2.0`
//! does (vectors of `f32`, `f64`, their packets and the SIMD lanes; borrowed, owned and
//! expression operands), and computes the same, operand order included for `-` and `/`.

use vecexpr::typenum::{U3, U4, U8};
use vecexpr::{vec3, Expr, Packet, Scalar, Vector};

/// `s op v` against the same operation with the scalar broadcast by hand, for every
/// operator, with a borrowed, an owned and an expression right operand.
macro_rules! scalar_left_case {
    ($t:ty, $s:expr, $v:expr) => {{
        let s = $s;
        let v: Vector<$t, U3> = $v;
        let sv = Vector::<$t, U3>::splat(<$t as Scalar>::splat(s));
        assert_eq!((s * &v).eval(), (&sv * &v).eval());
        assert_eq!((s + &v).eval(), (&sv + &v).eval());
        assert_eq!((s - &v).eval(), (&sv - &v).eval());
        assert_eq!((s / &v).eval(), (&sv / &v).eval());
        // Commutative products, bit for bit.
        assert_eq!((s * &v).eval(), (&v * s).eval());
        assert_eq!((s * v).eval(), (v * s).eval());
        assert_eq!((s * (&v + &v)).eval(), ((&v + &v) * s).eval());
        assert_eq!((s * (&v).abs().sqrt() - &v).eval(), ((&v).abs().sqrt() * s - &v).eval());
    }};
}

#[test]
fn plain_vectors() {
    scalar_left_case!(f32, 2.0f32, vec3(1.0, -2.5, 3.0));
    scalar_left_case!(f64, 0.25f64, vec3(1.0, -2.5, 3.0));
    // Unsuffixed literals take the vector's float.
    let v = vec3(1.0f32, 2.0, 3.0);
    assert_eq!((2.0 * &v).eval(), vec3(2.0, 4.0, 6.0));
    let w = vec3(1.0f64, 2.0, 3.0);
    assert_eq!((1.0 - &w).eval(), vec3(0.0, -1.0, -2.0));
}

#[test]
fn packet_vectors() {
    type P8 = Packet<f32, U8>;
    type Q4 = Packet<f64, U4>;
    scalar_left_case!(P8, 2.0f32, Vector::from_fn(|c| P8::from_fn(|l| (c * 8 + l) as f32 - 7.5)));
    scalar_left_case!(Q4, 3.0f64, Vector::from_fn(|c| Q4::from_fn(|l| (c * 4 + l) as f64 + 0.5)));
    // Unsuffixed literals, borrowed and owned.
    let v = Vector::<P8, U3>::splat(P8::splat(3.0));
    assert_eq!((2.0 * &v).eval(), Vector::splat(P8::splat(6.0)));
    assert_eq!((2.0 * v).eval(), (&v * 2.0).eval());
    let q = Vector::<Q4, U3>::splat(Q4::splat(3.0));
    assert_eq!((2.0 * &q).eval(), Vector::splat(Q4::splat(6.0)));
}

#[cfg(target_arch = "x86_64")]
#[test]
fn simd_lane_vectors() {
    use vecexpr::simd::F32x4;
    scalar_left_case!(F32x4, 2.0f32, Vector::from_fn(|c| F32x4::from_array([c as f32, 1.0, -2.0, 0.5])));
    let v = Vector::<F32x4, U3>::splat(F32x4::splat(1.5));
    assert_eq!((2.0 * &v).eval(), Vector::splat(F32x4::splat(3.0)));
}
