//! Hand-written edge cases of vecexpr's arithmetic: zero vectors, NaN propagation through
//! every operation, the NaN-propagating `min`/`max`, signed zeros, infinities, subnormal
//! and huge inputs to `normalize`, and `reflect`/`refract` against hand-computed cases.
//! Each case runs for `f32` and `f64`, and the lane-wise ones also for packets whose
//! lanes mix the cases.

use integration_tests::{lanes, mask_bits, naive};
use vecexpr::typenum::{U0, U16, U2, U3, U4, U8};
use vecexpr::{powi, select, vec3, Expr, MaskExpr, Packet, Real, Scalar, Vec3, Vector};

macro_rules! edges {
    ($m:ident, $e:ident) => {
        mod $m {
            use super::*;

            type E = $e;
            const NAN: E = E::NAN;
            const INF: E = E::INFINITY;
            const EPS: E = E::EPSILON;

            fn is_neg_zero(x: E) -> bool {
                x == 0.0 && x.is_sign_negative()
            }
            fn is_pos_zero(x: E) -> bool {
                x == 0.0 && x.is_sign_positive()
            }
            #[track_caller]
            fn assert_all_nan(v: &Vec3<E>) {
                assert!(v.iter().all(|x| x.is_nan()), "expected all NaN, got {v:?}");
            }
            #[track_caller]
            fn assert_near(got: &Vec3<E>, want: [E; 3], tol: E) {
                assert!(got.approx_eq(&Vector::from(want), tol), "{got:?} vs {want:?} (tol {tol})");
            }

            #[test]
            fn zero_vectors() {
                let z = Vec3::<E>::zero();
                // Normalising the zero vector gives the zero vector (documented), not NaN.
                let n = z.normalize();
                assert!(n.iter().all(|&x| is_pos_zero(x)), "{n:?}");
                let n = vec3(-0.0 as E, 0.0, -0.0).normalize();
                assert!(n.iter().all(|&x| x == 0.0), "{n:?}");
                let mut m = z;
                m.normalize_mut();
                assert_eq!(m, z);
                assert_eq!(Vector::<E, U16>::zero().normalize(), Vector::zero());
                assert_eq!(Vector::<E, vecexpr::typenum::U1000>::zero().normalize(), Vector::zero());
                assert_eq!(z.length(), 0.0);
                assert_eq!(z.length_squared(), 0.0);
                assert_eq!(z.dot(&vec3(1.0, 2.0, 3.0)), 0.0);
                assert_eq!(z.cross(&vec3(1.0, 2.0, 3.0)), z);
                assert_eq!(z.reflect(&vec3(0.0, 1.0, 0.0)), z);
                // A zero normal reflects nothing.
                assert_eq!(vec3(1.0 as E, -1.0, 0.5).reflect(&z), vec3(1.0, -1.0, 0.5));
            }

            #[test]
            fn nan_propagates_through_every_operation() {
                let a = vec3(1.0 as E, NAN, 3.0);
                let b = vec3(2.0 as E, 5.0, -4.0);
                let c = vec3(0.5 as E, 0.25, 8.0);
                let only_middle = |v: Vec3<E>, what: &str| {
                    assert!(!v[0].is_nan() && v[1].is_nan() && !v[2].is_nan(), "{what}: {v:?}");
                };
                only_middle((&a + &b).eval(), "a + b");
                only_middle((&b + &a).eval(), "b + a");
                only_middle((&a - &b).eval(), "a - b");
                only_middle((&b - &a).eval(), "b - a");
                only_middle((&a * &b).eval(), "a * b");
                only_middle((&b / &a).eval(), "b / a");
                only_middle((&a / &b).eval(), "a / b");
                only_middle((-&a).eval(), "-a");
                only_middle((&a).abs().eval(), "abs");
                only_middle((&a).sqrt().abs().eval(), "sqrt");
                only_middle((&a).recip().eval(), "recip");
                only_middle((&a).scale(2.0).eval(), "scale");
                only_middle((2.0 - &a).eval(), "2 - a");
                only_middle(a.mul_add(&b, &c).eval(), "mul_add, NaN factor");
                only_middle(b.mul_add(&a, &c).eval(), "mul_add, NaN second factor");
                only_middle(b.mul_add(&c, &a).eval(), "mul_add, NaN addend");
                only_middle((&a).map(|x| x * 2.0).eval(), "map");
                only_middle((&a * &b + &c * &b - &c).eval(), "deep tree");
                // A NaN scalar operand reaches every element.
                assert_all_nan(&(&b * NAN).eval());
                assert_all_nan(&(NAN + &b).eval());
                // Reductions see the NaN.
                assert!(a.sum().is_nan());
                assert!(a.dot(&b).is_nan());
                assert!(b.dot(&a).is_nan());
                assert!(a.length().is_nan());
                assert!(a.length_squared().is_nan());
                // normalize: any NaN component makes every component NaN (documented).
                assert_all_nan(&a.normalize());
                let mut m = a;
                m.normalize_mut();
                assert_all_nan(&m);
                // cross: the NaN y component reaches the x and z components only.
                let x = a.cross(&b);
                assert!(x[0].is_nan() && !x[1].is_nan() && x[2].is_nan(), "cross {x:?}");
                // reflect: N . I is NaN, so every component is NaN.
                assert_all_nan(&b.reflect(&a));
                assert_all_nan(&a.reflect(&vec3(0.0, 1.0, 0.0)));
                // refract: k is NaN, which is not >= 0, so no refraction.
                assert_eq!(a.refract(&vec3(0.0, 1.0, 0.0), 1.5), None);
                let (_, ok) = vec3(0.0 as E, -1.0, 0.0).refract_masked(&vec3(0.0, 1.0, 0.0), NAN);
                assert!(!ok);
                // Comparisons with NaN are false, and their negation true.
                let m = |mask: Vector<bool, U3>| mask.as_slice().to_vec();
                assert_eq!(m(a.lt(&b).eval()), [true, false, false]);
                assert_eq!(m(a.le(&b).eval()), [true, false, false]);
                assert_eq!(m(a.gt(&b).eval()), [false, false, true]);
                assert_eq!(m(a.ge(&b).eval()), [false, false, true]);
                assert_eq!(m(a.eq_mask(&a).eval()), [true, false, true]);
                assert_eq!(m(a.eq_mask(&a).not().eval()), [false, true, false]);
                // select chooses without arithmetic: a NaN in the other branch is not seen.
                let s = select(a.eq_mask(&a), &a, &b).eval();
                assert_eq!(s, vec3(1.0, 5.0, 3.0));
                only_middle(select(a.eq_mask(&a), &b, &a).eval(), "select NaN branch");
            }

            #[test]
            fn min_max_propagate_nan() {
                // Every minimum and maximum on vectors is NaN where either element is.
                let a = vec3(NAN, 1.0 as E, NAN);
                let b = vec3(2.0 as E, NAN, NAN);
                for m in [a.min(&b).eval(), a.max(&b).eval(), b.min(&a).eval(), b.max(&a).eval()] {
                    assert!(m.iter().all(|x| x.is_nan()), "{m:?}");
                }
                // With a scalar operand too.
                assert!(a.min(0.5).eval()[0].is_nan());
                assert!(a.max(0.5).eval()[0].is_nan());
                assert_eq!(a.max(0.5).eval()[1], 1.0);
                // The reductions: NaN anywhere gives NaN.
                for v in [vec3(NAN, 1.0 as E, 2.0), vec3(1.0 as E, NAN, 2.0), vec3(1.0 as E, 2.0, NAN)] {
                    assert!(v.min_element().is_nan() && v.max_element().is_nan(), "{v:?}");
                    assert!(v.sum().is_nan(), "{v:?}");
                }
                // The x86 rule stays available on scalars: NaN gives the second operand.
                assert_eq!(Scalar::min(NAN, 1.0 as E), 1.0);
                // Infinities order normally.
                let i = vec3(-INF, INF, 0.0);
                assert_eq!(i.min_element(), -INF);
                assert_eq!(i.max_element(), INF);
                assert_eq!(i.min(&vec3(0.0, 0.0, 0.0)).eval(), vec3(-INF, 0.0, 0.0));
                assert!(vec3(INF, -INF, 0.0 as E).sum().is_nan());
            }

            #[test]
            fn signed_zero() {
                let z = vec3(-0.0 as E, 0.0, -0.0);
                let abs = (&z).abs().eval();
                assert!(abs.iter().all(|&x| is_pos_zero(x)), "abs {abs:?}");
                let neg = (-&z).eval();
                assert!(is_pos_zero(neg[0]) && is_neg_zero(neg[1]) && is_pos_zero(neg[2]), "neg {neg:?}");
                // min and max order -0 below +0, whichever side each is on.
                let p = vec3(0.0 as E, -0.0, 0.0);
                for mn in [z.min(&p).eval(), p.min(&z).eval()] {
                    assert!(mn.iter().all(|&x| is_neg_zero(x)), "min {mn:?}");
                }
                for mx in [z.max(&p).eval(), p.max(&z).eval()] {
                    assert!(mx.iter().all(|&x| is_pos_zero(x)), "max {mx:?}");
                }
                // -0 == +0.
                assert!(z.eq_mask(&p).all());
                assert_eq!(z, p);
                // sqrt(-0) = -0, 1 / -0 = -inf, -0 * x keeps the sign rules.
                let s = (&z).sqrt().eval();
                assert!(is_neg_zero(s[0]) && is_pos_zero(s[1]), "sqrt {s:?}");
                assert_eq!((&z).recip().eval(), vec3(-INF, INF, -INF));
                assert!(is_neg_zero((&p * -1.0).eval()[0]));
                // A left-to-right sum of negative zeros stays -0.
                assert!(is_neg_zero(vec3(-0.0 as E, -0.0, -0.0).sum()));
                assert!(is_neg_zero(z.min_element()) && is_pos_zero(z.max_element()));
                assert!(is_neg_zero(vec3(0.0 as E, -0.0, 0.0).min_element()));
            }

            #[test]
            fn infinities() {
                let a = vec3(INF, -INF, 1.0);
                let b = vec3(INF, INF, 0.0);
                let s = (&a + &b).eval();
                assert!(s[0] == INF && s[1].is_nan() && s[2] == 1.0, "{s:?}");
                let d = (&a - &b).eval();
                assert!(d[0].is_nan() && d[1] == -INF, "{d:?}");
                let p = (&a * &b).eval();
                assert!(p[0] == INF && p[1] == -INF && p[2] == 0.0, "{p:?}");
                let q = (&a / &b).eval();
                assert!(q[0].is_nan() && q[1].is_nan() && q[2] == INF, "{q:?}");
                assert!((&a * 0.0).eval()[0].is_nan());
                assert_eq!((&a).recip().eval(), vec3(0.0, -0.0, 1.0));
                assert_eq!(vec3(INF, 4.0 as E, 0.0).sqrt().eval(), vec3(INF, 2.0, 0.0));
                assert!((&a).sqrt().eval()[1].is_nan());
                assert_eq!((&a).abs().eval(), vec3(INF, INF, 1.0));
                // Lengths overflow to infinity; they never become NaN for finite input.
                assert_eq!(vec3(INF, 1.0 as E, 0.0).length(), INF);
                assert_eq!(vec3(E::MAX, E::MAX, 0.0).length(), INF);
                assert_eq!(vec3(E::MAX, E::MAX, 0.0).length_squared(), INF);
                assert_eq!(vec3(-INF, 1.0 as E, 0.0).dot(&vec3(-1.0, 0.0, 0.0)), INF);
                // Infinite components make normalize NaN (documented), all of them.
                assert_all_nan(&vec3(INF, 1.0 as E, 0.0).normalize());
                assert_all_nan(&vec3(0.0 as E, -INF, 0.0).normalize());
                // mul_add overflow and inf - inf inside one rounding.
                assert!(vec3(INF, 0.0 as E, 0.0).mul_add(&vec3(1.0, 0.0, 0.0), &vec3(-INF, 0.0, 0.0)).eval()[0].is_nan());
            }

            #[test]
            fn normalize_extreme_magnitudes() {
                let sub = E::from_bits(1); // smallest subnormal
                let tol = 4.0 * EPS;
                let third = (1.0 as E / 3.0).sqrt();
                assert_eq!(vec3(sub, 0.0, 0.0).normalize(), vec3(1.0, 0.0, 0.0));
                assert_eq!(vec3(0.0, -sub, 0.0).normalize(), vec3(0.0, -1.0, 0.0));
                assert_near(&vec3(sub, sub, sub).normalize(), [third; 3], tol);
                assert_near(&vec3(E::MIN_POSITIVE, 0.0, E::MIN_POSITIVE).normalize(), [0.5f64.sqrt() as E, 0.0, 0.5f64.sqrt() as E], tol);
                assert_near(&vec3(E::MAX, E::MAX, E::MAX).normalize(), [third; 3], tol);
                assert_near(&vec3(E::MAX, -E::MAX, 0.0).normalize(), [0.5f64.sqrt() as E, -(0.5f64.sqrt() as E), 0.0], tol);
                // The squares of these underflow or overflow although the vector is fine.
                let small = <E as Real>::from_f64(if E::MANTISSA_DIGITS == 24 { 1e-30 } else { 1e-300 });
                let big = <E as Real>::from_f64(if E::MANTISSA_DIGITS == 24 { 1e30 } else { 1e300 });
                assert_near(&vec3(3.0 * small, 0.0, 4.0 * small).normalize(), [0.6, 0.0, 0.8], tol);
                assert_near(&vec3(3.0 * big, 0.0, -4.0 * big).normalize(), [0.6, 0.0, -0.8], tol);
                // Mixed magnitudes: the tiny component survives as a tiny, not NaN.
                let v = vec3(big, sub, 0.0).normalize();
                assert_eq!(v[0], 1.0);
                assert!(v[1].is_finite() && v[1] >= 0.0);
                // Long vectors: every element tiny or huge.
                let tiny16 = Vector::<E, U16>::splat(small).normalize();
                assert!(tiny16.iter().all(|&x| (x - 0.25).abs() <= tol), "{tiny16:?}");
                let huge16 = Vector::<E, U16>::splat(-big).normalize();
                assert!(huge16.iter().all(|&x| (x + 0.25).abs() <= tol), "{huge16:?}");
                // normalize_mut agrees on every path.
                for v in [vec3(sub, 0.0, 0.0), vec3(big, big, 0.0), vec3(1.0, 2.0, 2.0), vec3(E::MAX, 0.0, E::MAX)] {
                    let mut m = v;
                    m.normalize_mut();
                    assert_eq!(m, v.normalize());
                }
                // 3-4-5 on the fast path, x * (1 / 5): within one rounding of 0.6 and 0.8.
                assert_near(&vec3(3.0 as E, 0.0, 4.0).normalize(), [0.6, 0.0, 0.8], 2.0 * EPS);
            }

            #[test]
            fn reflect_hand_computed() {
                let up = vec3(0.0 as E, 1.0, 0.0);
                assert_eq!(vec3(1.0 as E, -1.0, 0.0).reflect(&up), vec3(1.0, 1.0, 0.0));
                assert_eq!(vec3(1.0 as E, 2.0, -3.0).reflect(&vec3(0.0, 0.0, 1.0)), vec3(1.0, 2.0, 3.0));
                // Head-on: straight back.
                assert_eq!(vec3(0.0 as E, -1.0, 0.0).reflect(&up), up);
                // Parallel to the surface: unchanged.
                assert_eq!(vec3(1.0 as E, 0.0, 0.0).reflect(&up), vec3(1.0, 0.0, 0.0));
                // The normal's orientation does not matter.
                assert_eq!(vec3(1.0 as E, -1.0, 0.0).reflect(-up), vec3(1.0, 1.0, 0.0));
                // A 45-degree mirror turns +x into -y.
                let h = 0.5f64.sqrt() as E;
                let n = vec3(h, h, 0.0);
                assert_near(&vec3(1.0 as E, 0.0, 0.0).reflect(&n), [0.0, -1.0, 0.0], 4.0 * EPS);
                // Non-unit incident directions scale: R(2 I) = 2 R(I).
                assert_eq!(vec3(2.0 as E, -2.0, 0.0).reflect(&up), vec3(2.0, 2.0, 0.0));
                // Reflecting twice gives the original direction back, and length is kept.
                let i = vec3(0.3 as E, -0.8, 0.52);
                let n = vec3(0.1 as E, 0.9, -0.2).normalize();
                let r = i.reflect(&n);
                assert!((r.length() - i.length()).abs() <= 4.0 * EPS);
                assert_near(&r.reflect(&n), i.into_array(), 8.0 * EPS);
                // R . N = -(I . N).
                assert!((r.dot(&n) + i.dot(&n)).abs() <= 4.0 * EPS);
            }

            #[test]
            fn refract_hand_computed() {
                let up = vec3(0.0 as E, 1.0, 0.0);
                // Normal incidence passes straight through, whatever eta.
                let down = vec3(0.0 as E, -1.0, 0.0);
                for eta in [0.5 as E, 1.0 / 1.5, 1.0, 1.33, 1.5, 2.0] {
                    let t = down.refract(&up, eta).expect("normal incidence refracts");
                    assert_near(&t, [0.0, -1.0, 0.0], 2.0 * EPS);
                }
                assert_eq!(down.refract(&up, 1.5), Some(down));
                // eta = 1 (no interface) passes any direction through.
                for i in [vec3(0.6 as E, -0.8, 0.0), vec3(0.36, -0.48, 0.8), vec3(-0.28, -0.96, 0.0)] {
                    let t = i.refract(&up, 1.0).expect("eta = 1 refracts");
                    assert_near(&t, i.into_array(), 4.0 * EPS);
                }
                // Into glass at 30 degrees: sin t = sin 30 / 1.5 = 1/3 (Snell).
                let (s30, c30) = (0.5 as E, (0.75 as E).sqrt());
                let i = vec3(s30, -c30, 0.0);
                let t = i.refract(&up, 1.0 / 1.5).expect("into a denser medium always refracts");
                assert!((t[0] - 1.0 / 3.0).abs() <= 4.0 * EPS, "{t:?}");
                assert!((t.length() - 1.0).abs() <= 4.0 * EPS);
                assert!(t[1] < 0.0);
                // Out of glass at 60 degrees: 1.5 sin 60 > 1, total internal reflection.
                let i = vec3(c30, -s30, 0.0);
                assert_eq!(i.refract(&up, 1.5), None);
                let (t, ok) = i.refract_masked(&up, 1.5);
                assert!(!ok);
                assert!(t.iter().all(|&x| x == 0.0), "TIR gives the zero vector: {t:?}");
                // Either side of the critical angle for eta = 2 (sin c = 1/2): just inside it
                // the ray leaves almost along the surface; just outside it is reflected.
                let inside = vec3(0.499 as E, -(1.0 - 0.499 * 0.499 as E).sqrt(), 0.0);
                let t = inside.refract(&up, 2.0).expect("inside the critical angle refracts");
                assert!((t[0] - 0.998).abs() <= 16.0 * EPS && t[1] < 0.0 && t[1] > -0.1, "{t:?}");
                let outside = vec3(0.501 as E, -(1.0 - 0.501 * 0.501 as E).sqrt(), 0.0);
                assert_eq!(outside.refract(&up, 2.0), None);
                // Grazing incidence (I perpendicular to N): TIR out of a denser medium, a
                // refracted ray into one, and eta = 1 leaves I unchanged exactly.
                let graze = vec3(1.0 as E, 0.0, 0.0);
                assert_eq!(graze.refract(&up, 1.5), None);
                let t = graze.refract(&up, 1.0 / 1.5).expect("grazing into glass refracts");
                let sin_c = 1.0 as E / 1.5;
                assert_near(&t, [sin_c, -(1.0 - sin_c * sin_c).sqrt(), 0.0], 4.0 * EPS);
                assert_eq!(graze.refract(&up, 1.0), Some(graze));
            }

            #[test]
            fn mul_add_rounds_once_and_is_never_implicit() {
                // (1 + eps)(1 - eps) = 1 - eps^2, which rounds to 1.
                let a = vec3(1.0 + EPS, 1.0, 2.0);
                let b = vec3(1.0 - EPS, 1.0, 3.0);
                let c = vec3(-1.0 as E, 0.0, 1.0);
                let fused = a.mul_add(&b, &c).eval();
                assert_eq!(fused, vec3(-EPS * EPS, 1.0, 7.0));
                let unfused = (&a * &b + &c).eval();
                assert_eq!(unfused, vec3(0.0, 1.0, 7.0));
            }

            #[test]
            fn powi_edges() {
                assert_eq!(powi::<U0, E>(NAN), 1.0);
                assert_eq!(powi::<U0, E>(0.0), 1.0);
                assert!(powi::<U3, E>(NAN).is_nan());
                assert!(is_pos_zero(powi::<U2, E>(-0.0)));
                assert!(is_neg_zero(powi::<U3, E>(-0.0)));
                assert_eq!(powi::<U3, E>(-INF), -INF);
                assert_eq!(powi::<U4, E>(-INF), INF);
                assert_eq!(powi::<U16, E>(E::MAX), INF);
                assert_eq!(powi::<U8, E>(-2.0), 256.0);
            }

            #[test]
            #[should_panic]
            fn index_out_of_range_panics() {
                let v = vec3(1.0 as E, 2.0, 3.0);
                let i = v.as_slice().len();
                let _ = v[i];
            }

            #[test]
            #[should_panic(expected = "out of range")]
            fn unit_out_of_range_panics() {
                let _ = Vec3::<E>::unit(3);
            }

            #[test]
            #[should_panic(expected = "empty vector")]
            fn min_element_of_nothing_panics() {
                let _ = Vector::<E, U0>::zero().min_element();
            }

            #[test]
            fn empty_vector_sums_to_zero() {
                let v = Vector::<E, U0>::zero();
                assert_eq!(v.sum(), 0.0);
                assert_eq!(v.dot(&v), 0.0);
                assert_eq!(v.length(), 0.0);
                // A vector without elements normalises to itself.
                assert_eq!(v.normalize(), v);
                let mut m = v;
                m.normalize_mut();
                assert_eq!(m, v);
            }
        }
    };
}

edges!(f32_edges, f32);
edges!(f64_edges, f64);

/// Packets treat every lane on its own: lanes that are zero, tiny, huge, NaN or ordinary
/// next to each other each get their own answer.
#[test]
fn packet_lanes_are_independent() {
    type P = Packet<f32, U4>;
    let sub = f32::from_bits(1);
    // Lane 0 zero, lane 1 subnormal, lane 2 huge, lane 3 ordinary (3-4-5).
    let v = Vector::<P, U3>::from([
        P::from_fn(|l| [0.0, sub, 1e30, 3.0][l]),
        P::from_fn(|l| [0.0, 0.0, 1e30, 0.0][l]),
        P::from_fn(|l| [0.0, 0.0, 0.0, 4.0][l]),
    ]);
    let n = lanes(&v.normalize());
    let h = core::f32::consts::FRAC_1_SQRT_2;
    let want = [
        [0.0, 1.0, h, 0.6], // x of lanes 0..4
        [0.0, 0.0, h, 0.0],
        [0.0, 0.0, 0.0, 0.8],
    ];
    for l in 0..4 {
        for c in 0..3 {
            let got = n[l * 3 + c];
            assert!(
                (got - want[c][l]).abs() <= 4.0 * f32::EPSILON,
                "lane {l} component {c}: {got}"
            );
        }
    }
    // A NaN lane stays NaN and does not leak into the others.
    let w = Vector::<P, U3>::from([
        P::from_fn(|l| if l == 2 { f32::NAN } else { 1.0 }),
        P::splat(0.0),
        P::splat(0.0),
    ]);
    let n = w.normalize();
    for l in 0..4 {
        assert_eq!(n[0].lane(l).is_nan(), l == 2);
    }

    // min/max rule per lane.
    let a = P::from_fn(|l| [f32::NAN, 1.0, -0.0, 5.0][l]);
    let b = P::from_fn(|l| [2.0, f32::NAN, 0.0, 4.0][l]);
    let mn = Scalar::min(a, b);
    assert_eq!(mn.lane(0), 2.0);
    assert!(mn.lane(1).is_nan());
    assert!(mn.lane(2) == 0.0 && mn.lane(2).is_sign_positive());
    assert_eq!(mn.lane(3), 4.0);
    // The NaN-propagating minimum and maximum per lane, as vectors use them.
    let mn = Scalar::minimum(a, b);
    assert!(mn.lane(0).is_nan() && mn.lane(1).is_nan());
    assert!(mn.lane(2) == 0.0 && mn.lane(2).is_sign_negative());
    assert_eq!(mn.lane(3), 4.0);
    let mx = Scalar::maximum(a, b);
    assert!(mx.lane(0).is_nan() && mx.lane(1).is_nan());
    assert!(mx.lane(2) == 0.0 && mx.lane(2).is_sign_positive());
    assert_eq!(mx.lane(3), 5.0);
    assert!(a.reduce_min().is_nan() && a.reduce_max().is_nan());
    assert_eq!(P::from_fn(|l| [3.0, -0.0, 0.0, 1.0][l]).reduce_min().to_bits(), (-0.0f32).to_bits());

    // refract_masked: lane 0 at normal incidence, lane 1 grazing out of glass (TIR), lane
    // 2 at 60 degrees out of glass (TIR), lane 3 at 60 degrees into glass.
    type Q = Packet<f64, U4>;
    let (s60, c60) = (0.75f64.sqrt(), 0.5);
    let i = Vector::<Q, U3>::from([
        Q::from_fn(|l| [0.0, 1.0, s60, s60][l]),
        Q::from_fn(|l| [-1.0, 0.0, -c60, -c60][l]),
        Q::splat(0.0),
    ]);
    let n = Vector::<Q, U3>::from([Q::splat(0.0), Q::splat(1.0), Q::splat(0.0)]);
    let eta = Q::from_fn(|l| [1.5, 1.5, 1.5, 1.0 / 1.5][l]);
    let (t, ok) = i.refract_masked(&n, eta);
    assert_eq!(mask_bits(ok), [true, false, false, true]);
    let t = lanes(&t);
    assert_eq!(&t[0..3], &[0.0, -1.0, 0.0]);
    assert!(
        t[3..9].iter().all(|&x| x == 0.0),
        "TIR lanes must be zero: {t:?}"
    );
    // Lane 3 obeys Snell: sin t = sin i / 1.5.
    let t3 = &t[9..12];
    assert!((t3[0] - s60 / 1.5).abs() < 1e-15);
    assert!((naive::length(t3) - 1.0).abs() < 1e-15);

    // Comparisons and select per lane.
    let x = Vector::<P, U2>::from([a, b]);
    let y = Vector::<P, U2>::from([b, a]);
    let sel = select(x.lt(&y), &x, &y).eval();
    assert_eq!(sel[0].lane(3), 4.0);
    assert!(sel[0].lane(0) == 2.0 && sel[1].lane(0).is_nan());
    let wide = Vector::<Packet<f32, U8>, U2>::splat(Packet::splat(1.0));
    assert!(wide.eq_mask(&wide).all());
}
