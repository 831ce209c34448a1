//! Every lane operation against the scalar `f32` result, lane by lane and bit for bit,
//! for each instruction set the CPU has.

// Tables of (name, result, reference) and lane-indexed comparisons read best as they are.
#![allow(clippy::type_complexity, clippy::needless_range_loop)]

use super::*;
use crate::{select, vec3, Expr, Vec3};

/// Awkward values: signed zeros, infinities, NaN, subnormals, extremes, ordinary numbers.
const SPECIAL: [f32; 16] = [
    0.0,
    -0.0,
    1.0,
    -1.5,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NAN,
    1.0e-40,
    -3.0e38,
    f32::MAX,
    f32::MIN_POSITIVE,
    0.1,
    7.25,
    -2.0,
    1.0e20,
    -1.0e-20,
];

/// A deterministic pseudo-random float (xorshift), sometimes a special value.
fn rnd(state: &mut u32) -> f32 {
    *state ^= *state << 13;
    *state ^= *state >> 17;
    *state ^= *state << 5;
    match *state % 8 {
        0 => SPECIAL[(*state >> 8) as usize % SPECIAL.len()],
        _ => ((*state >> 8) as f32 / (1u32 << 24) as f32 - 0.5) * 200.0,
    }
}

/// Same bits, or both NaN (the payload of a NaN result is not specified).
fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn lanes<S: SimdF32>(v: S) -> Vec<f32> {
    let mut out = vec![0.0; S::LANES];
    v.store(&mut out);
    out
}

fn mask_lanes<M: SimdMask>(m: M) -> Vec<bool> {
    (0..M::LANES).map(|i| m.test(i)).collect()
}

struct CheckOps;

impl Kernel for CheckOps {
    type Output = usize;
    fn run<S: SimdF32>(self) -> usize {
        let n = S::LANES;
        let mut state = 0x1234_5678u32 ^ n as u32;
        let mut checked = 0;
        // The special values against each other (every pair across the lanes), then random.
        for round in 0..300 {
            let (xa, xb, xc): (Vec<f32>, Vec<f32>, Vec<f32>) = if round < SPECIAL.len() {
                let r = round;
                (
                    (0..n).map(|_| SPECIAL[r]).collect(),
                    (0..n).map(|i| SPECIAL[i % SPECIAL.len()]).collect(),
                    (0..n).map(|i| SPECIAL[(i + r) % SPECIAL.len()]).collect(),
                )
            } else {
                (
                    (0..n).map(|_| rnd(&mut state)).collect(),
                    (0..n).map(|_| rnd(&mut state)).collect(),
                    (0..n).map(|_| rnd(&mut state)).collect(),
                )
            };
            let (a, b, c) = (S::load(&xa), S::load(&xb), S::load(&xc));
            assert!(lanes(a)
                .iter()
                .zip(&xa)
                .all(|(x, y)| x.to_bits() == y.to_bits()));
            let binary: [(&str, S, fn(f32, f32) -> f32); 8] = [
                ("add", a + b, |x, y| x + y),
                ("sub", a - b, |x, y| x - y),
                ("mul", a * b, |x, y| x * y),
                ("div", a / b, |x, y| x / y),
                ("min", Scalar::min(a, b), Scalar::min),
                ("max", Scalar::max(a, b), Scalar::max),
                ("minimum", Scalar::minimum(a, b), Scalar::minimum),
                ("maximum", Scalar::maximum(a, b), Scalar::maximum),
            ];
            for (name, v, f) in binary {
                for (i, got) in lanes(v).into_iter().enumerate() {
                    let want = f(xa[i], xb[i]);
                    assert!(
                        same(got, want),
                        "{:?} {name}({}, {}) = {got}, scalar {want}",
                        S::ISA,
                        xa[i],
                        xb[i]
                    );
                }
            }
            let mut acc = a;
            acc += b;
            acc *= c;
            acc -= a;
            acc /= b;
            let unary: [(&str, S, fn(f32, f32, f32) -> f32); 6] = [
                ("neg", -a, |x, _, _| -x),
                ("abs", Scalar::abs(a), |x, _, _| x.abs()),
                ("sqrt", Scalar::sqrt(a), |x, _, _| x.sqrt()),
                ("recip", Scalar::recip(a), |x, _, _| 1.0 / x),
                ("copysign", a.copysign(b), |x, y, _| x.copysign(y)),
                ("assign ops", acc, |x, y, z| ((x + y) * z - x) / y),
            ];
            for (name, v, f) in unary {
                for (i, got) in lanes(v).into_iter().enumerate() {
                    let want = f(xa[i], xb[i], xc[i]);
                    // -x and |x| and copysign are exact bit operations, NaN included.
                    let ok = if matches!(name, "neg" | "abs" | "copysign") {
                        got.to_bits() == want.to_bits()
                    } else {
                        same(got, want)
                    };
                    assert!(
                        ok,
                        "{:?} {name}({}, {}) = {got}, scalar {want}",
                        S::ISA,
                        xa[i],
                        xb[i]
                    );
                }
            }
            for (i, got) in lanes(a.mul_add(b, c)).into_iter().enumerate() {
                let want = xa[i].mul_add(xb[i], xc[i]);
                assert!(same(got, want), "{:?} mul_add lane {i}", S::ISA);
            }
            let cmps: [(&str, S::Mask, fn(f32, f32) -> bool); 7] = [
                ("lt", a.lt(b), |x, y| x < y),
                ("le", a.le(b), |x, y| x <= y),
                ("gt", a.gt(b), |x, y| x > y),
                ("ge", a.ge(b), |x, y| x >= y),
                ("eq", a.eq_mask(b), |x, y| x == y),
                ("finite", a.is_finite_mask(), |x, _| x.is_finite()),
                ("nan", a.is_nan_mask(), |x, _| x.is_nan()),
            ];
            for (name, m, f) in cmps {
                let want: Vec<bool> = (0..n).map(|i| f(xa[i], xb[i])).collect();
                assert_eq!(mask_lanes(m), want, "{:?} {name} {xa:?} {xb:?}", S::ISA);
                let bits = m.bitmask();
                assert_eq!(S::Mask::from_bitmask(bits), m);
                // `Debug` (and `PartialEq` above) read the lanes without intrinsics.
                assert_eq!(format!("{m:?}"), format!("{want:?}"));
                for i in 0..n {
                    assert_eq!(bits >> i & 1 != 0, want[i]);
                }
                assert_eq!(m.any(), want.iter().any(|&w| w));
                assert_eq!(m.all(), want.iter().all(|&w| w));
                let sel = lanes(S::select(m, a, b));
                for i in 0..n {
                    let w = if want[i] { xa[i] } else { xb[i] };
                    assert_eq!(
                        sel[i].to_bits(),
                        w.to_bits(),
                        "{:?} select lane {i}",
                        S::ISA
                    );
                }
            }
            let (m1, m2) = (a.lt(b), b.le(c));
            let (l1, l2) = (mask_lanes(m1), mask_lanes(m2));
            let and: Vec<bool> = (0..n).map(|i| l1[i] & l2[i]).collect();
            let or: Vec<bool> = (0..n).map(|i| l1[i] | l2[i]).collect();
            let not: Vec<bool> = l1.iter().map(|&x| !x).collect();
            assert_eq!(mask_lanes(m1.and(m2)), and);
            assert_eq!(mask_lanes(m1.or(m2)), or);
            assert_eq!(mask_lanes(m1.not()), not);
            for i in 0..n {
                assert_eq!(a.lane(i).to_bits(), xa[i].to_bits());
            }
            assert_eq!(format!("{a:?}"), format!("{xa:?}"));
            let has_nan = xa.iter().any(|x| x.is_nan());
            assert_eq!(a == S::load(&xa), !has_nan, "{:?} eq {xa:?}", S::ISA);
            checked += 1;
        }
        // Constructors.
        assert!(lanes(S::splat(2.5)).iter().all(|&x| x == 2.5));
        assert!(lanes(S::default()).iter().all(|&x| x.to_bits() == 0));
        assert!(S::Mask::splat_bool(true).all() && !S::Mask::splat_bool(false).any());
        assert_eq!(S::Mask::splat_bool(true).bitmask(), (1u32 << n) - 1);
        checked
    }
}

/// The expression templates on SoA packets of 3-vectors: every lane equals the scalar
/// expression on that lane's vectors, bit for bit.
struct CheckVectors;

impl Kernel for CheckVectors {
    type Output = ();
    fn run<S: SimdF32>(self) {
        let n = S::LANES;
        let mut state = 0x9e37_79b9u32;
        let gen = |st: &mut u32| -> Vec<f32> {
            (0..n)
                .map(|_| {
                    let x = rnd(st);
                    if x.is_finite() {
                        x
                    } else {
                        0.5
                    }
                })
                .collect()
        };
        for _ in 0..50 {
            let comps: Vec<Vec<f32>> = (0..6).map(|_| gen(&mut state)).collect();
            let pa: Vec3<S> = vec3(S::load(&comps[0]), S::load(&comps[1]), S::load(&comps[2]));
            let pb: Vec3<S> = vec3(S::load(&comps[3]), S::load(&comps[4]), S::load(&comps[5]));
            let dot = pa.dot(&pb);
            let cross = pa.cross(&pb);
            let expr = (&pa * S::splat(2.0) + &pb - &pa * &pb).eval();
            let norm = pa.normalize();
            let sel = select(pa.lt(&pb), &pa, &pb).eval();
            let len = pb.length();
            // `normalize` rescales only the lanes whose squared length is not a normal
            // number, so every lane is the scalar result, on either path.
            for i in 0..n {
                let a = vec3(comps[0][i], comps[1][i], comps[2][i]);
                let b = vec3(comps[3][i], comps[4][i], comps[5][i]);
                assert!(same(dot.lane(i), a.dot(&b)), "{:?} dot", S::ISA);
                let c = a.cross(&b);
                let e = (&a * 2.0f32 + &b - &a * &b).eval();
                let nm = a.normalize();
                for k in 0..3 {
                    assert!(same(cross[k].lane(i), c[k]), "{:?} cross", S::ISA);
                    assert!(same(expr[k].lane(i), e[k]), "{:?} expression", S::ISA);
                    assert!(same(norm[k].lane(i), nm[k]), "{:?} normalize", S::ISA);
                    let s = if a[k] < b[k] { a[k] } else { b[k] };
                    assert!(same(sel[k].lane(i), s), "{:?} select", S::ISA);
                }
                assert!(same(len.lane(i), b.length()), "{:?} length", S::ISA);
            }
        }
    }
}

/// `normalize` on packets that mix ordinary vectors with ones that need the rescaling
/// path (zero, tiny, huge, subnormal) or give NaN (infinite, NaN components): every lane,
/// ordinary ones included, is bit for bit the scalar `normalize` of that lane's vector,
/// and the rescaling runs inside the dispatched function (`INLINE_SLOW_PATHS`).
struct CheckNormalizeSlowPath;

impl Kernel for CheckNormalizeSlowPath {
    type Output = usize;
    fn run<S: SimdF32>(self) -> usize {
        assert!(S::INLINE_SLOW_PATHS && !<f32 as Scalar>::INLINE_SLOW_PATHS);
        let n = S::LANES;
        let odd: [[f32; 3]; 8] = [
            [0.0, 0.0, 0.0],
            [-0.0, 0.0, -0.0],
            [1.0e-30, 0.0, -2.0e-30],
            [3.0e30, -1.0e30, 2.0e30],
            [f32::from_bits(1), 0.0, f32::from_bits(3)],
            [f32::MAX, f32::MAX, 1.0],
            [f32::INFINITY, 1.0, 0.0],
            [f32::NAN, 0.0, 1.0],
        ];
        let mut state = 0x2545_f491u32;
        let mut slow_packets = 0;
        for round in 0..64 {
            // Lane i is odd vector `(i + round) % 8` where bit i of the round's pattern is
            // set, an ordinary random vector otherwise; round 0 is all ordinary.
            let pattern = if round == 0 {
                0
            } else {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                state | 1
            };
            let v: Vec<[f32; 3]> = (0..n)
                .map(|i| {
                    if pattern >> (i % 32) & 1 != 0 {
                        odd[(i + round) % odd.len()]
                    } else {
                        // Components of moderate magnitude: a normal squared length.
                        [0, 1, 2].map(|_| {
                            let x = rnd(&mut state);
                            if (1.0e-3..1.0e3).contains(&x.abs()) {
                                x
                            } else {
                                -0.75
                            }
                        })
                    }
                })
                .collect();
            let comp = |k: usize| -> Vec<f32> { v.iter().map(|p| p[k]).collect() };
            let p: Vec3<S> = vec3(S::load(&comp(0)), S::load(&comp(1)), S::load(&comp(2)));
            let l2 = p.length_squared();
            let needs_slow = (0..n).any(|i| !(f32::MIN_POSITIVE..=f32::MAX).contains(&l2.lane(i)));
            slow_packets += usize::from(needs_slow);
            let got = p.normalize();
            for (i, w) in v.iter().enumerate() {
                let want = vec3(w[0], w[1], w[2]).normalize();
                for k in 0..3 {
                    assert!(
                        same(got[k].lane(i), want[k]),
                        "{:?} normalize {w:?} lane {i}: {} vs scalar {}",
                        S::ISA,
                        got[k].lane(i),
                        want[k]
                    );
                }
            }
        }
        slow_packets
    }
}

/// The instruction sets the CPU reports, read here from CPUID through `std` rather than
/// through [`Isa::is_available`]: SSE2 (always on x86-64), AVX2 with FMA, AVX-512F.
fn cpu_isas() -> Vec<Isa> {
    let mut v = vec![Isa::Sse2];
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        v.push(Isa::Avx2);
    }
    if std::arch::is_x86_feature_detected!("avx512f") {
        v.push(Isa::Avx512);
    }
    v
}

/// Runs `check` for every instruction set the CPU has, then writes one line naming the
/// ones that ran and the ones that did not, straight to stderr so it shows in every test
/// log (the harness captures only `print!`/`eprint!`). Returns the instruction sets run.
fn for_each_isa(test: &str, mut check: impl FnMut(Isa)) -> Vec<Isa> {
    use std::io::Write;
    let ran = Isa::available();
    for &isa in &ran {
        check(isa);
    }
    let names = |v: &[Isa]| v.iter().map(|i| i.name()).collect::<Vec<_>>().join(" ");
    let missing: Vec<Isa> = Isa::ALL.into_iter().filter(|i| !ran.contains(i)).collect();
    let mut line = format!("simd {test}: ran {}", names(&ran));
    if !missing.is_empty() {
        line += &format!(
            "; not run: {} (the CPU lacks it; its kernels are checked by assembly only, \
             asm-dumps)",
            names(&missing)
        );
    }
    let _ = writeln!(std::io::stderr(), "{line}");
    ran
}

#[test]
fn lane_ops_match_scalar_for_every_available_isa() {
    let ran = for_each_isa("lane ops", |isa| {
        assert_eq!(isa.dispatch(CheckOps), 300, "{isa}");
        isa.dispatch(CheckVectors);
    });
    assert_eq!(ran, cpu_isas());
}

/// `reduce_min` and `reduce_max` against a scan of the lanes, on random lanes without
/// NaN (whose result is unspecified), with the extreme in every position.
struct CheckReduce;

impl Kernel for CheckReduce {
    type Output = usize;
    fn run<S: SimdF32>(self) -> usize {
        let mut state = 0x9e37_79b9u32;
        let mut checked = 0;
        for _ in 0..200 {
            let mut a = [0.0f32; 16];
            for x in a.iter_mut().take(S::LANES) {
                *x = loop {
                    let v = rnd(&mut state);
                    if !v.is_nan() {
                        break v;
                    }
                };
            }
            let v = S::load(&a);
            let lo = a[..S::LANES].iter().copied().fold(f32::INFINITY, f32::min);
            let hi = a[..S::LANES]
                .iter()
                .copied()
                .fold(f32::NEG_INFINITY, f32::max);
            // Signed zeros compare equal: the lane returned may be either.
            assert_eq!(v.reduce_min(), lo, "{a:?}");
            assert_eq!(v.reduce_max(), hi, "{a:?}");
            checked += 1;
        }
        checked
    }
}

/// `transpose8` against the records it was given, lane by lane and bit for bit.
struct CheckTranspose;

impl Kernel for CheckTranspose {
    type Output = usize;
    fn run<S: SimdF32>(self) -> usize {
        let mut state = 0x1234_5678u32;
        let mut checked = 0;
        for _ in 0..50 {
            let recs: Vec<[f32; 8]> = (0..S::LANES)
                .map(|_| core::array::from_fn(|_| rnd(&mut state)))
                .collect();
            let refs: Vec<&[f32; 8]> = recs.iter().collect();
            let rows = S::transpose8(&refs);
            for (k, row) in rows.iter().enumerate() {
                for (l, x) in lanes(*row).into_iter().enumerate() {
                    assert!(same(x, recs[l][k]), "value {k} of record {l}");
                    checked += 1;
                }
            }
        }
        checked
    }
}

#[test]
fn transpose_puts_record_values_in_lanes() {
    let ran = for_each_isa("transpose", |isa| {
        assert_eq!(isa.dispatch(CheckTranspose), 50 * 8 * isa.lanes(), "{isa}");
    });
    assert_eq!(ran, cpu_isas());
}

#[test]
fn reductions_find_the_extreme_lane() {
    let ran = for_each_isa("reductions", |isa| {
        assert_eq!(isa.dispatch(CheckReduce), 200, "{isa}");
    });
    assert_eq!(ran, cpu_isas());
}

#[test]
fn normalize_rescales_only_the_lanes_that_need_it() {
    let ran = for_each_isa("normalize", |isa| {
        // Every round but the first has at least one odd lane.
        assert_eq!(isa.dispatch(CheckNormalizeSlowPath), 63, "{isa}");
    });
    assert_eq!(ran, cpu_isas());
}

/// The instruction sets the tests run are exactly those the CPU has: none is skipped
/// that could run, and SSE2 always runs.
#[test]
fn tested_isas_are_the_cpus() {
    assert_eq!(Isa::available(), cpu_isas());
    assert_eq!(Isa::available()[0], Isa::Sse2);
}

#[test]
fn detection_and_names() {
    let best = Isa::detect().expect("x86-64 has SSE2");
    assert!(best.is_available());
    assert_eq!(Isa::available().last(), Some(&best));
    for isa in Isa::ALL {
        assert_eq!(Isa::from_name(isa.name()), Some(isa));
        assert_eq!(isa.to_string(), isa.name());
    }
    assert_eq!(Isa::from_name("avx"), None);
    assert_eq!(Isa::Avx512.lanes(), 16);
}

#[test]
fn the_inherent_array_conversions_round_trip() {
    let a: [f32; 4] = core::array::from_fn(|i| i as f32 - 1.5);
    assert_eq!(F32x4::from_array(a).to_array(), a);
    if Isa::Avx2.is_available() {
        let a: [f32; 8] = core::array::from_fn(|i| i as f32 * 0.25);
        assert_eq!(F32x8::from_array(a).to_array(), a);
    }
    if Isa::Avx512.is_available() {
        let a: [f32; 16] = core::array::from_fn(|i| -(i as f32));
        assert_eq!(F32x16::from_array(a).to_array(), a);
        assert_eq!(
            format!("{:?}", F32x16::from_array(a).lt(F32x16::splat(-7.5)))
                .matches("true")
                .count(),
            8
        );
    }
}

/// A prefetch is a hint: on valid, dangling and null addresses alike it returns and
/// changes nothing.
#[test]
fn prefetch_never_faults_and_changes_nothing() {
    let data = [1.0f32, 2.0, 3.0, 4.0];
    super::prefetch(data.as_ptr());
    super::prefetch(core::ptr::null::<f32>());
    super::prefetch(usize::MAX as *const u8);
    assert_eq!(data, [1.0, 2.0, 3.0, 4.0]);
}
