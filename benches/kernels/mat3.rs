//! A 3×3 matrix (the same for every vector) times 3-vectors; and `vecexpr::Matrix`
//! against glam and nalgebra on 4×4 matrix-vector and matrix-matrix products (group
//! `mat4`).

use crate::{Batch, P16, P8, V3};
use benches::config::{self, AOS, SOA16, SOA8};
use benches::data::Pcg32;
use benches::eager::Eager;
use benches::hand;
use benches::run::{batch, single, soa};
use criterion::{Criterion, Throughput};
use ultraviolet::{f32x8, Mat3x8, Vec3x8};
use vecexpr::typenum::U3;
use vecexpr::typenum::U4;
use vecexpr::{Expr, Mat3, Mat4, Scalar, Vector};

/// $M v = c_0 v_x + c_1 v_y + c_2 v_z$ with vecexpr: one fused expression.
#[inline(always)]
fn vx_mul<T: Scalar>(m: &[Vector<T, U3>; 3], v: &Vector<T, U3>) -> Vector<T, U3> {
    ((&m[0]).scale(v[0]) + (&m[1]).scale(v[1]) + (&m[2]).scale(v[2])).eval()
}

/// The criterion group `mat3`.
pub fn bench(c: &mut Criterion) {
    let mut g = config::group(c, "mat3");
    let mut rng = Pcg32::new(9);
    let cols: [[f32; 3]; 3] = core::array::from_fn(|_| rng.vec3s(1)[0]);
    let v = Batch::random(&mut rng, config::BATCH);

    let m_vx = cols.map(V3::from);
    let m_mat = Mat3::from_cols(cols.map(V3::from));
    let m_eager = cols.map(|c| Eager::from_fn(|k| c[k]));
    let m_glam = glam::Mat3::from_cols_array_2d(&cols);
    let m_glam_a = glam::Mat3A::from_cols_array_2d(&cols);
    let m_na = nalgebra::Matrix3::from_columns(&cols.map(nalgebra::Vector3::from));
    let m_p8 = cols.map(|c| Vector::<P8, U3>::from_fn(|k| P8::splat(c[k])));
    let m_p16 = cols.map(|c| Vector::<P16, U3>::from_fn(|k| P16::splat(c[k])));
    let m_e8 = cols.map(|c| Eager::<P8, U3>::from_fn(|k| P8::splat(c[k])));
    let col8 =
        |c: [f32; 3]| Vec3x8::new(f32x8::splat(c[0]), f32x8::splat(c[1]), f32x8::splat(c[2]));
    let m_uv = Mat3x8::new(col8(cols[0]), col8(cols[1]), col8(cols[2]));

    single(&mut g, "vecexpr", "3", v.vx[0], v.vx[0], |a, _| {
        vx_mul(&m_vx, a)
    });
    single(&mut g, "vecexpr_matrix", "3", v.vx[0], v.vx[0], |a, _| {
        &m_mat * a
    });
    single(&mut g, "eager", "3", v.eager[0], v.eager[0], |a, _| {
        Eager::mat3_mul(&m_eager, a)
    });
    single(&mut g, "hand", "3", v.arr[0], v.arr[0], |a, _| {
        hand::mat3_mul(&cols, *a)
    });
    single(&mut g, "glam_vec3", "3", v.glam3[0], v.glam3[0], |a, _| {
        m_glam * *a
    });
    single(
        &mut g,
        "glam_vec3a",
        "3",
        v.glam3a[0],
        v.glam3a[0],
        |a, _| m_glam_a * *a,
    );
    single(&mut g, "nalgebra", "3", v.na[0], v.na[0], |a, _| m_na * a);

    g.throughput(Throughput::Elements(config::BATCH as u64));
    batch(&mut g, "vecexpr", AOS, &v.vx, &v.vx, |a, _| {
        vx_mul(&m_vx, a)
    });
    batch(&mut g, "vecexpr_matrix", AOS, &v.vx, &v.vx, |a, _| {
        &m_mat * a
    });
    batch(&mut g, "eager", AOS, &v.eager, &v.eager, |a, _| {
        Eager::mat3_mul(&m_eager, a)
    });
    batch(&mut g, "hand", AOS, &v.arr, &v.arr, |a, _| {
        hand::mat3_mul(&cols, *a)
    });
    batch(&mut g, "glam_vec3", AOS, &v.glam3, &v.glam3, |a, _| {
        m_glam * *a
    });
    batch(&mut g, "glam_vec3a", AOS, &v.glam3a, &v.glam3a, |a, _| {
        m_glam_a * *a
    });
    batch(&mut g, "nalgebra", AOS, &v.na, &v.na, |a, _| m_na * a);
    batch(&mut g, "vecexpr", SOA8, &v.p8, &v.p8, |a, _| {
        vx_mul(&m_p8, a)
    });
    batch(&mut g, "eager", SOA8, &v.e8, &v.e8, |a, _| {
        Eager::mat3_mul(&m_e8, a)
    });
    soa(&mut g, "hand", SOA8, &v.soa, &v.soa, |a, _| {
        hand::mat3_mul(&cols, a)
    });
    batch(&mut g, "ultraviolet", SOA8, &v.uv, &v.uv, |a, _| m_uv * *a);
    batch(&mut g, "vecexpr", SOA16, &v.p16, &v.p16, |a, _| {
        vx_mul(&m_p16, a)
    });
    g.finish();
}

/// The criterion group `mat4`: one 4×4 matrix times 4-vectors (`4`: one product,
/// `aos4096`: a batch) and times another 4×4 matrix (`4x4`), vecexpr's `Matrix` against
/// glam's `Mat4` and nalgebra's `Matrix4`.
pub fn bench4(c: &mut Criterion) {
    let mut g = config::group(c, "mat4");
    let mut rng = Pcg32::new(11);
    let mut vec4s = |n: usize| -> Vec<[f32; 4]> {
        let (a, b) = (rng.vec3s(n), rng.vec(n));
        a.iter()
            .zip(b)
            .map(|(a, w)| [a[0], a[1], a[2], w])
            .collect()
    };
    let cols: [[f32; 4]; 4] = vec4s(4).try_into().expect("four columns");
    let cols_b: [[f32; 4]; 4] = vec4s(4).try_into().expect("four columns");
    let v = vec4s(config::BATCH);

    type V4 = Vector<f32, U4>;
    let m_vx = Mat4::from_cols(cols.map(V4::from));
    let m_vx_b = Mat4::from_cols(cols_b.map(V4::from));
    let m_glam = glam::Mat4::from_cols_array_2d(&cols);
    let m_glam_b = glam::Mat4::from_cols_array_2d(&cols_b);
    let m_na = nalgebra::Matrix4::from_columns(&cols.map(nalgebra::Vector4::from));
    let m_na_b = nalgebra::Matrix4::from_columns(&cols_b.map(nalgebra::Vector4::from));
    let v_vx: Vec<V4> = v.iter().map(|&x| V4::from(x)).collect();
    let v_glam: Vec<glam::Vec4> = v.iter().map(|&x| glam::Vec4::from(x)).collect();
    let v_na: Vec<nalgebra::Vector4<f32>> = v.iter().map(|&x| nalgebra::Vector4::from(x)).collect();

    single(&mut g, "vecexpr_matrix", "4", v_vx[0], v_vx[0], |a, _| {
        &m_vx * a
    });
    single(&mut g, "glam", "4", v_glam[0], v_glam[0], |a, _| {
        m_glam * *a
    });
    single(&mut g, "nalgebra", "4", v_na[0], v_na[0], |a, _| m_na * a);
    single(&mut g, "vecexpr_matrix", "4x4", m_vx, m_vx_b, |a, b| a * b);
    single(&mut g, "glam", "4x4", m_glam, m_glam_b, |a, b| *a * *b);
    single(&mut g, "nalgebra", "4x4", m_na, m_na_b, |a, b| a * b);

    g.throughput(Throughput::Elements(config::BATCH as u64));
    batch(&mut g, "vecexpr_matrix", AOS, &v_vx, &v_vx, |a, _| {
        &m_vx * a
    });
    batch(&mut g, "glam", AOS, &v_glam, &v_glam, |a, _| m_glam * *a);
    batch(&mut g, "nalgebra", AOS, &v_na, &v_na, |a, _| m_na * a);
    g.finish();
}
