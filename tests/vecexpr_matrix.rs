//! Matrices against a naive reference: plain nested loops over `Vec<Vec<f64>>` (rows of
//! columns written out by hand), products summed left to right. In `f64` vecexpr must
//! match the reference bit for bit (same operations in the same order); in `f32` within
//! the rounding bound of the sum, against the reference computed in `f64` from the same
//! inputs. Packets must match, lane by lane, the `f64` matrices of their lanes.

use crate::prop;

use proptest::prelude::*;
use vecexpr::generic_array::ArrayLength;
use vecexpr::typenum::{U1, U2, U3, U4, U5};
use vecexpr::{vec2, vec3, Mat3, Mat4, MatExpr, Matrix, Packet, Scalar, Vector};

/// A row-major reference matrix.
type Ref = Vec<Vec<f64>>;

/// `a * b` with every element summed left to right.
fn ref_mul(a: &Ref, b: &Ref) -> Ref {
    let (n, k, p) = (a.len(), b.len(), b[0].len());
    assert_eq!(a[0].len(), k);
    (0..n)
        .map(|r| {
            (0..p)
                .map(|c| {
                    let mut s = a[r][0] * b[0][c];
                    for j in 1..k {
                        s += a[r][j] * b[j][c];
                    }
                    s
                })
                .collect()
        })
        .collect()
}

/// The reference of a matrix built from row-major data.
fn ref_of(rows: usize, cols: usize, data: &[f64]) -> Ref {
    (0..rows)
        .map(|r| data[r * cols..][..cols].to_vec())
        .collect()
}

/// A vecexpr matrix from row-major data.
fn mat<T: Copy, R: ArrayLength, C: ArrayLength>(data: &[f64], f: impl Fn(f64) -> T) -> Matrix<T, R, C> {
    Matrix::from_fn(|r, c| f(data[r * C::USIZE + c]))
}

/// Asserts that `m` is the reference, bit for bit.
#[track_caller]
fn assert_exact<R: ArrayLength, C: ArrayLength>(m: &Matrix<f64, R, C>, want: &Ref, what: &str) {
    for (r, row) in want.iter().enumerate() {
        for (c, &w) in row.iter().enumerate() {
            let g = m[(r, c)];
            assert!(
                g.to_bits() == w.to_bits() || (g.is_nan() && w.is_nan()),
                "{what}: element ({r}, {c}) is {g:e}, the reference {w:e}\n{m}"
            );
        }
    }
}

/// `f32` result within the bound of a sum of `k` products: each of the two orders is
/// within `k * eps * sum |terms|` of the exact value (Higham, Accuracy and Stability of
/// Numerical Algorithms, 2nd ed., section 3.1), plus the rounding of the inputs, which
/// the reference sees exactly.
#[track_caller]
fn assert_close_f32<R: ArrayLength, C: ArrayLength>(m: &Matrix<f32, R, C>, want: &Ref, abs: &Ref, k: usize) {
    for (r, row) in want.iter().enumerate() {
        for (c, &w) in row.iter().enumerate() {
            let g = f64::from(m[(r, c)]);
            let tol = (k as f64 + 2.0) * f64::from(f32::EPSILON) * abs[r][c] + 1e-30;
            assert!((g - w).abs() <= tol, "({r}, {c}): {g:e} vs {w:e} (tolerance {tol:e})");
        }
    }
}

/// Elements in [-100, 100) with a few exact small integers, zeros of both signs.
fn elems(n: usize) -> impl Strategy<Value = Vec<f64>> + Send {
    let e = prop_oneof![
        6 => -100.0f64..100.0,
        2 => (-4i32..5).prop_map(f64::from),
        1 => Just(-0.0f64),
    ];
    proptest::collection::vec(e, n)
}

/// `A (R×K) * B (K×P)` and `A * x` for one choice of sizes, in `f64` and `f32`.
fn check_products<R: ArrayLength, K: ArrayLength, P: ArrayLength>(d: &[f64]) {
    let (r, k, p) = (R::USIZE, K::USIZE, P::USIZE);
    let (da, rest) = d.split_at(r * k);
    let (db, dx) = rest.split_at(k * p);
    let dx = &dx[..k];
    let (ra, rb) = (ref_of(r, k, da), ref_of(k, p, db));
    let rx: Ref = dx.iter().map(|&x| vec![x]).collect();

    // f64: bit for bit.
    let a: Matrix<f64, R, K> = mat(da, |x| x);
    let b: Matrix<f64, K, P> = mat(db, |x| x);
    let x = Vector::<f64, K>::from_slice(dx).unwrap();
    assert_exact(&(&a * &b), &ref_mul(&ra, &rb), "a * b");
    let ax = &a * &x;
    let want = ref_mul(&ra, &rx);
    for i in 0..r {
        assert_eq!(ax[i].to_bits(), want[i][0].to_bits(), "(a * x)[{i}]");
    }
    // Owned operands and lazy operands on either side give the same.
    assert_eq!(a.clone() * x.clone(), ax);
    assert_eq!(&a * (&x * 1.0), ax);
    assert_eq!((&a * 1.0) * &x, ax);
    assert_eq!(a.clone() * b.clone(), &a * &b);
    assert_eq!((&a + &a) * &b, (&a * 2.0).eval() * &b);
    // (A B)^T = B^T A^T, exactly: the same products summed in the same order.
    assert_eq!((&a * &b).transpose(), &b.transpose() * &a.transpose());
    assert_eq!(a.transpose().transpose(), a);

    // f32: within the rounding bound of the f64 reference of the rounded inputs.
    let round = |v: &[f64]| -> Vec<f64> { v.iter().map(|&x| f64::from(x as f32)).collect() };
    let (ra32, rb32) = (ref_of(r, k, &round(da)), ref_of(k, p, &round(db)));
    let abs = |m: &Ref| -> Ref { m.iter().map(|row| row.iter().map(|x| x.abs()).collect()).collect() };
    let a32: Matrix<f32, R, K> = mat(da, |x| x as f32);
    let b32: Matrix<f32, K, P> = mat(db, |x| x as f32);
    assert_close_f32(&(&a32 * &b32), &ref_mul(&ra32, &rb32), &ref_mul(&abs(&ra32), &abs(&rb32)), k);
}

/// Element-wise expressions, bit for bit against the same operations in `f64`.
fn check_elementwise<R: ArrayLength, C: ArrayLength>(d: &[f64]) {
    let n = R::USIZE * C::USIZE;
    let a: Matrix<f64, R, C> = mat(&d[..n], |x| x);
    let b: Matrix<f64, R, C> = mat(&d[n..2 * n], |x| x);
    let c: Matrix<f64, R, C> = mat(&d[2 * n..3 * n], |x| x);
    let s = d[3 * n];
    let got = ((&a + &b) * s - &c / 3.0 + 2.0 * -&a).eval();
    let want = Matrix::<f64, R, C>::from_fn(|i, j| (a[(i, j)] + b[(i, j)]) * s - c[(i, j)] / 3.0 + 2.0 * -a[(i, j)]);
    assert_exact(&got, &ref_of(R::USIZE, C::USIZE, &row_major(&want)), "element-wise tree");
    // Owned and borrowed operands are the same leaves.
    assert_eq!((a.clone() - b.clone()).eval(), (&a - &b).eval());
    assert!(got.approx_eq(&want, 0.0));
}

fn row_major<R: ArrayLength, C: ArrayLength>(m: &Matrix<f64, R, C>) -> Vec<f64> {
    (0..R::USIZE)
        .flat_map(|r| (0..C::USIZE).map(move |c| (r, c)))
        .map(|rc| m[rc])
        .collect()
}

#[test]
fn products_match_the_reference() {
    prop::check(200, elems(64), |d| check_products::<U3, U3, U3>(&d));
    prop::check(200, elems(64), |d| check_products::<U4, U4, U4>(&d));
    prop::check(100, elems(64), |d| check_products::<U2, U3, U4>(&d));
    prop::check(100, elems(64), |d| check_products::<U5, U2, U1>(&d));
    prop::check(100, elems(64), |d| check_products::<U1, U5, U3>(&d));
}

#[test]
fn element_wise_matches_the_reference() {
    prop::check(200, elems(64), |d| check_elementwise::<U3, U3>(&d));
    prop::check(100, elems(64), |d| check_elementwise::<U2, U5>(&d));
}

#[test]
fn packets_are_their_lanes() {
    type Q = Packet<f64, U4>;
    prop::check(100, elems(4 * (9 + 9 + 3)), |d| {
        let lane = |l: usize| &d[l * 21..][..21];
        let a = Mat3::<Q>::from_fn(|r, c| Q::from_fn(|l| lane(l)[r * 3 + c]));
        let b = Mat3::<Q>::from_fn(|r, c| Q::from_fn(|l| lane(l)[9 + r * 3 + c]));
        let x = Vector::<Q, U3>::from_fn(|i| Q::from_fn(|l| lane(l)[18 + i]));
        let (ab, ax) = (&a * &b, &a * &x);
        for l in 0..4 {
            let (ra, rb) = (ref_of(3, 3, &lane(l)[..9]), ref_of(3, 3, &lane(l)[9..18]));
            let rx: Ref = lane(l)[18..].iter().map(|&v| vec![v]).collect();
            let (want, wantx) = (ref_mul(&ra, &rb), ref_mul(&ra, &rx));
            for r in 0..3 {
                assert_eq!(ax[r].lane(l).to_bits(), wantx[r][0].to_bits());
                for c in 0..3 {
                    assert_eq!(ab[(r, c)].lane(l).to_bits(), want[r][c].to_bits());
                }
            }
        }
    });
}

#[test]
fn construction_indexing_and_display() {
    let m = Matrix::from_rows([vec3(1.0f32, 2.0, 3.0), vec3(4.0, 5.0, 6.0)]);
    let t = Matrix::from_cols([vec2(1.0f32, 4.0), vec2(2.0, 5.0), vec2(3.0, 6.0)]);
    assert_eq!(m, t);
    assert_eq!((Matrix::<f32, U2, U3>::ROWS, Matrix::<f32, U2, U3>::COLS), (2, 3));
    assert_eq!(m[(0, 2)], 3.0);
    assert_eq!(m.row(1), vec3(4.0, 5.0, 6.0));
    assert_eq!(*m.col(1), vec2(2.0, 5.0));
    let mut n = m;
    n[(1, 1)] = -5.0;
    n.col_mut(0)[0] = 0.5;
    assert_eq!(format!("{n}"), "[[0.5, 2, 3], [4, -5, 6]]");
    assert_eq!(format!("{n:.1}"), "[[0.5, 2.0, 3.0], [4.0, -5.0, 6.0]]");
    assert_eq!(format!("{n:?}"), "[[0.5, 2.0, 3.0], [4.0, -5.0, 6.0]]");
    // Column-major storage: the layout of [[T; R]; C].
    assert_eq!(core::mem::size_of::<Matrix<f32, U2, U3>>(), 24);
    // SAFETY: `Matrix<f32, U2, U3>` is `repr(transparent)` over a generic array of three
    // `Vector<f32, U2>`, each `repr(transparent)` over `[f32; 2]`: the layout of
    // `[[f32; 2]; 3]`, which any bit pattern inhabits.
    let raw: [[f32; 2]; 3] = unsafe { core::mem::transmute(m) };
    assert_eq!(raw, [[1.0, 4.0], [2.0, 5.0], [3.0, 6.0]]);
    let two = Mat4::<f64>::from_fn(|r, c| if r == c { 2.0 } else { 0.0 });
    assert_eq!((Mat4::<f64>::identity() * 2.0).eval(), two);
    assert_eq!((2.0 * &Mat4::<f64>::identity()).eval(), two);
    assert_eq!(Mat3::<f32>::zero(), Mat3::default());
}
