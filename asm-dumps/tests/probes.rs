//! The probes compute what their names say: each agrees with glam or a plain loop.

use asm_dumps::probes::*;
use glam::{Mat3A, Vec3A};
use vecexpr::{vec3, Scalar, Vector};

fn unit(x: f32, y: f32, z: f32) -> [f32; 3] {
    let l = (x * x + y * y + z * z).sqrt();
    [x / l, y / l, z / l]
}

fn close(a: [f32; 3], b: Vec3A) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= 1e-5)
}

#[test]
fn reflect_variants_agree_with_glam() {
    let i = [0.3f32, -0.8, 0.2];
    let n = unit(0.1, 1.0, -0.3);
    let (gi, gn) = (Vec3A::from(i), Vec3A::from(n));
    let mut g = Vec3A::ZERO;
    reflect_glam_vec3a(&gi, &gn, &mut g);
    assert!(close(g.into(), gi - 2.0 * gi.dot(gn) * gn));

    let mut r3 = Vec3F32::zero();
    reflect_f32x3(&i.into(), &n.into(), &mut r3);
    assert!(close(r3.into_array(), g));
    let mut f3 = Vec3F32::zero();
    reflect_fma_f32x3(&i.into(), &n.into(), &mut f3);
    assert!(close(f3.into_array(), g));
    let mut r4 = Vec4F32::zero();
    reflect_f32x4(
        &vec3(i[0], i[1], i[2]).extend(0.0),
        &vec3(n[0], n[1], n[2]).extend(0.0),
        &mut r4,
    );
    assert!(close(r4.truncate().into_array(), g));
    assert_eq!(r4[3], 0.0);
    let mut r64 = Vec3F64::zero();
    let to64 = |v: [f32; 3]| Vector::from(v.map(f64::from));
    reflect_f64x3(&to64(i), &to64(n), &mut r64);
    assert!(close(r64.into_array().map(|x| x as f32), g));

    // Packets: lane l holds the same ray scaled by (l + 1).
    let soa16 = |v: [f32; 3], scale: bool| {
        Soa16::from_fn(|k| P16::from_fn(|l| v[k] * if scale { (l + 1) as f32 } else { 1.0 }))
    };
    let mut p = Soa16::zero();
    reflect_packet16(&soa16(i, true), &soa16(n, false), &mut p);
    let mut q = Soa16::zero();
    reflect_fma_packet16(&soa16(i, true), &soa16(n, false), &mut q);
    let mut p8 = Soa8::zero();
    let soa8 = |v: [f32; 3], scale: bool| {
        Soa8::from_fn(|k| P8::from_fn(|l| v[k] * if scale { (l + 1) as f32 } else { 1.0 }))
    };
    reflect_packet8(&soa8(i, true), &soa8(n, false), &mut p8);
    for l in 0..16 {
        let s = (l + 1) as f32;
        let want = g * s;
        let lane = |v: &Soa16| [v[0].lane(l), v[1].lane(l), v[2].lane(l)].map(|x| x / s);
        assert!(close(lane(&p), want / s), "lane {l}");
        assert!(close(lane(&q), want / s), "lane {l}");
        if l < 8 {
            assert!(close(
                [p8[0].lane(l), p8[1].lane(l), p8[2].lane(l)].map(|x| x / s),
                g
            ));
        }
    }
}

#[test]
fn refract_normalize_and_friends_agree_with_glam() {
    let i = unit(0.5, -1.0, 0.1);
    let n = unit(0.0, 1.0, 0.2);
    let (gi, gn) = (Vec3A::from(i), Vec3A::from(n));
    for eta in [0.7f32, 1.0 / 1.5, 1.5, 2.5] {
        let mut g = Vec3A::ZERO;
        refract_glam_vec3a(&gi, &gn, &eta, &mut g);
        let mut r = Vec3F32::zero();
        refract_f32x3(&i.into(), &n.into(), &eta, &mut r);
        assert!(close(r.into_array(), g), "eta {eta}");
        let mut p = Soa16::zero();
        let soa = |v: [f32; 3]| Soa16::from_fn(|k| P16::splat(v[k]));
        refract_packet16(&soa(i), &soa(n), &P16::splat(eta), &mut p);
        assert!(close([p[0].lane(5), p[1].lane(5), p[2].lane(5)], g));
    }

    let v = [3.0f32, -4.0, 12.0];
    let mut g = Vec3A::ZERO;
    normalize_glam_vec3a(&Vec3A::from(v), &mut g);
    let mut r = Vec3F32::zero();
    normalize_f32x3(&v.into(), &mut r);
    assert!(close(r.into_array(), g));
    let mut p = Soa16::zero();
    normalize_packet16(&Soa16::from_fn(|k| P16::splat(v[k])), &mut p);
    assert!(close([p[0].lane(15), p[1].lane(15), p[2].lane(15)], g));

    let mut g = Vec3A::ZERO;
    reflect_normalize_glam_vec3a(&(gi * 3.0), &gn, &mut g);
    let mut p = Soa16::zero();
    let soa = |v: [f32; 3], s: f32| Soa16::from_fn(|k| P16::splat(v[k] * s));
    reflect_normalize_packet16(&soa(i, 3.0), &soa(n, 1.0), &mut p);
    assert!(close([p[0].lane(0), p[1].lane(0), p[2].lane(0)], g));
    let mut p8 = Soa8::zero();
    let soa8 = |v: [f32; 3], s: f32| Soa8::from_fn(|k| P8::splat(v[k] * s));
    reflect_normalize_packet8(&soa8(i, 3.0), &soa8(n, 1.0), &mut p8);
    assert!(close([p8[0].lane(7), p8[1].lane(7), p8[2].lane(7)], g));
    if vecexpr::simd::Isa::Avx2.is_available() {
        use vecexpr::simd::F32x8;
        let l8 = |v: [f32; 3], s: f32| Lanes8::from_fn(|k| F32x8::splat(v[k] * s));
        let mut l = l8([0.0; 3], 0.0);
        // SAFETY: the CPU has AVX2 and FMA, the probe's target features.
        unsafe { reflect_normalize_f32x8(&l8(i, 3.0), &l8(n, 1.0), &mut l) };
        assert!(close([l[0].lane(3), l[1].lane(3), l[2].lane(3)], g));
    }
    if vecexpr::simd::Isa::Avx512.is_available() {
        use vecexpr::simd::F32x16;
        let l16 = |v: [f32; 3], s: f32| Lanes16::from_fn(|k| F32x16::splat(v[k] * s));
        let mut l = l16([0.0; 3], 0.0);
        // SAFETY: the CPU has AVX-512F, the probe's target features.
        unsafe { reflect_normalize_f32x16(&l16(i, 3.0), &l16(n, 1.0), &mut l) };
        assert!(close([l[0].lane(11), l[1].lane(11), l[2].lane(11)], g));
    }

    let (a, b) = ([1.0f32, 2.0, 3.0], [-2.0f32, 0.5, 4.0]);
    let mut c = Vec3F32::zero();
    cross_f32x3(&a.into(), &b.into(), &mut c);
    let mut gc = Vec3A::ZERO;
    cross_glam_vec3a(&Vec3A::from(a), &Vec3A::from(b), &mut gc);
    assert!(close(c.into_array(), gc));

    let cols = [[1.0f32, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.5]];
    let mut m = Vec3F32::zero();
    mat3_vec3_f32(&cols.map(Vec3F32::from), &b.into(), &mut m);
    let mut gm = Vec3A::ZERO;
    mat3_vec3_glam_mat3a(&Mat3A::from_cols_array_2d(&cols), &Vec3A::from(b), &mut gm);
    assert!(close(m.into_array(), gm));
    let mut mm = Vec3F32::zero();
    mat3_vec3_matrix(&vecexpr::Mat3::from_cols(cols.map(Vec3F32::from)), &b.into(), &mut mm);
    assert_eq!(mm, m);

    // 4×4: vecexpr's Matrix against glam's Mat4, bit for bit (both sum the columns in
    // order, without FMA on the test's build).
    let c4: [[f32; 4]; 4] = core::array::from_fn(|c| core::array::from_fn(|r| (r * 4 + c) as f32 - 6.5));
    let v4 = [1.0f32, -2.0, 0.5, 3.0];
    let m4 = vecexpr::Mat4::from_cols(c4.map(Vec4F32::from));
    let g4 = glam::Mat4::from_cols_array_2d(&c4);
    let mut mv = Vec4F32::zero();
    mat4_vec4_matrix(&m4, &v4.into(), &mut mv);
    let mut gv = glam::Vec4::ZERO;
    mat4_vec4_glam_mat4(&g4, &glam::Vec4::from(v4), &mut gv);
    assert_eq!(mv.into_array(), gv.to_array());
    let mut mp = vecexpr::Mat4::zero();
    mat4_mat4_matrix(&m4, &m4.transpose(), &mut mp);
    let mut gp = glam::Mat4::ZERO;
    mat4_mat4_glam_mat4(&g4, &g4.transpose(), &mut gp);
    for c in 0..4 {
        assert_eq!(mp.col(c).into_array(), gp.col(c).to_array(), "column {c}");
    }
}

#[test]
fn sphere_probes_agree() {
    let o = [0.0f32, 0.0, 0.0];
    let c = [0.0f32, 0.0, -5.0];
    let mut t = 0.0;
    sphere_hit_f32x3(&o.into(), &[0.0, 0.0, -1.0].into(), &c.into(), &1.0, &mut t);
    assert_eq!(t, 4.0);
    let dirs: [f32; 16] = core::array::from_fn(|l| l as f32 * 0.1 - 0.8);
    let d = Soa16::from_fn(|k| P16::from_fn(|l| [dirs[l], 0.0, -1.0][k]));
    let mut tp = P16::splat(0.0);
    let splat = |v: [f32; 3]| Soa16::from_fn(|k| P16::splat(v[k]));
    sphere_hit_packet16(&splat(o), &d, &splat(c), &P16::splat(1.0), &mut tp);
    for (l, &x) in dirs.iter().enumerate() {
        let mut t1 = 0.0;
        sphere_hit_f32x3(&o.into(), &[x, 0.0, -1.0].into(), &c.into(), &1.0, &mut t1);
        assert_eq!(tp.lane(l), t1, "lane {l}");
    }
    assert!(tp.lane(0).is_infinite() && tp.lane(8).is_finite());
}

#[test]
fn long_vector_probes_agree_with_loops() {
    let f = |s: f32| Long1k::from_fn(|i| (i as f32 * s).sin());
    let (a, b, c, d, e) = (f(0.1), f(0.2), f(0.3), f(0.4), f(0.5));
    let mut out = Long1k::zero();
    abcde_f32_1k(&a, &b, &c, &d, &e, &mut out);
    let arr = |v: &Long1k| -> [f32; 1024] { core::array::from_fn(|i| v[i]) };
    let mut hand = [0.0f32; 1024];
    abcde_hand_f32_1k(&arr(&a), &arr(&b), &arr(&c), &arr(&d), &arr(&e), &mut hand);
    assert_eq!(arr(&out), hand);

    let mut y = b;
    axpy_f32_1k(&2.5, &a, &mut y);
    assert!((0..1024).all(|i| y[i] == 2.5 * a[i] + b[i]));

    let mut dot = 0.0;
    dot_f32_1k(&a, &b, &mut dot);
    let naive: f64 = (0..1024).map(|i| f64::from(a[i]) * f64::from(b[i])).sum();
    assert!((f64::from(dot) - naive).abs() < 1e-3, "{dot} vs {naive}");
}

#[test]
fn vec3a_probes_agree_with_glam_and_vector() {
    use vecexpr::Expr;
    let (i, n) = ([0.3f32, -0.8, 0.2], unit(0.1, 1.0, -0.3));
    let (gi, gn) = (Vec3A::from(i), Vec3A::from(n));
    let (vi, vn) = (vecexpr::Vec3A::from(i), vecexpr::Vec3A::from(n));
    let mut r = vecexpr::Vec3A::ZERO;
    reflect_vec3a(&vi, &vn, &mut r);
    assert!(close(r.to_array(), gi.reflect(gn)));
    assert_eq!(r.to_vector(), Vec3F32::from(i).reflect(&Vec3F32::from(n)));
    normalize_vec3a(&(vi * 3.0), &mut r);
    assert!(close(r.to_array(), (gi * 3.0).normalize()));
    reflect_normalize_vec3a(&(vi * 3.0), &vn, &mut r);
    assert!(close(r.to_array(), (gi * 3.0).reflect(gn).normalize()));
    // The robust path: a tiny vector still normalises.
    normalize_vec3a(&vecexpr::Vec3A::new(1e-30, 0.0, 0.0), &mut r);
    assert_eq!(r, vecexpr::Vec3A::X);
    // The plain formula: glam's division, bit for bit.
    let mut f = vecexpr::Vec3A::ZERO;
    normalize_fast_vec3a(&(vi * 3.0), &mut f);
    assert_eq!(f.to_array(), (gi * 3.0).normalize().to_array());
    reflect_normalize_fast_vec3a(&(vi * 3.0), &vn, &mut f);
    assert!(close(f.to_array(), (gi * 3.0).reflect(gn).normalize()));
}
