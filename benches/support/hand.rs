//! Hand-written loops and formulas: what a careful programmer writes without any
//! vector library, the ceiling the others are measured against.

/// `out[i] = a[i] * b[i] + c[i] * d[i] - e[i]`, one loop.
#[inline]
pub fn abcde(a: &[f32], b: &[f32], c: &[f32], d: &[f32], e: &[f32], out: &mut [f32]) {
    let n = out.len();
    let (a, b, c, d, e) = (&a[..n], &b[..n], &c[..n], &d[..n], &e[..n]);
    for i in 0..n {
        out[i] = a[i] * b[i] + c[i] * d[i] - e[i];
    }
}

/// `y[i] += a * x[i]`.
#[inline]
pub fn axpy(a: f32, x: &[f32], y: &mut [f32]) {
    for (y, &x) in y.iter_mut().zip(x) {
        *y += a * x;
    }
}

/// Number of interleaved partial sums of [`sum`] and [`dot`].
pub const LANES: usize = 16;

/// $\sum_i x_i$ with 16 interleaved partial sums, so it vectorises (a single
/// accumulator may not be reordered by the compiler and runs at one add per latency).
#[inline]
pub fn sum<T: vecexpr::Scalar>(x: &[T]) -> T {
    let mut acc = [T::zero(); LANES];
    let chunks = x.chunks_exact(LANES);
    let tail = chunks.remainder();
    for c in chunks {
        for j in 0..LANES {
            acc[j] += c[j];
        }
    }
    for (j, &t) in tail.iter().enumerate() {
        acc[j] += t;
    }
    acc.iter().fold(T::zero(), |s, &a| s + a)
}

/// $\sum_i x_i y_i$ with 16 interleaved partial sums.
#[inline]
pub fn dot(x: &[f32], y: &[f32]) -> f32 {
    let mut acc = [0.0f32; LANES];
    let n = x.len().min(y.len());
    let full = n / LANES * LANES;
    for (cx, cy) in x[..full]
        .chunks_exact(LANES)
        .zip(y[..full].chunks_exact(LANES))
    {
        for j in 0..LANES {
            acc[j] += cx[j] * cy[j];
        }
    }
    for i in full..n {
        acc[i - full] += x[i] * y[i];
    }
    acc.iter().sum()
}

/// Dot product of two 3-vectors.
#[inline(always)]
pub fn dot3(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// $R = I - 2 N (N \cdot I)$.
#[inline(always)]
pub fn reflect3(i: [f32; 3], n: [f32; 3]) -> [f32; 3] {
    let d = dot3(n, i);
    let d2 = d + d;
    [i[0] - n[0] * d2, i[1] - n[1] * d2, i[2] - n[2] * d2]
}

/// $v / \lVert v \rVert$.
#[inline(always)]
pub fn normalize3(v: [f32; 3]) -> [f32; 3] {
    let inv = 1.0 / dot3(v, v).sqrt();
    [v[0] * inv, v[1] * inv, v[2] * inv]
}

/// $a \times b$.
#[inline(always)]
pub fn cross3(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Snell refraction; zero on total internal reflection (written branch-free, so the
/// compiler can vectorise it over a batch).
#[inline(always)]
pub fn refract3(i: [f32; 3], n: [f32; 3], eta: f32) -> [f32; 3] {
    let ni = dot3(n, i);
    let k = 1.0 - eta * eta * (1.0 - ni * ni);
    let ok = k >= 0.0;
    let a = if ok { eta } else { 0.0 };
    let b = if ok {
        eta * ni + k.max(0.0).sqrt()
    } else {
        0.0
    };
    [
        i[0] * a - n[0] * b,
        i[1] * a - n[1] * b,
        i[2] * a - n[2] * b,
    ]
}

/// Column-major 3×3 matrix times vector.
#[inline(always)]
pub fn mat3_mul(cols: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    [0, 1, 2].map(|r| cols[0][r] * v[0] + cols[1][r] * v[1] + cols[2][r] * v[2])
}

/// `a*b + c*d - e` on 3-vectors.
#[inline(always)]
pub fn abcde3(a: [f32; 3], b: [f32; 3], c: [f32; 3], d: [f32; 3], e: [f32; 3]) -> [f32; 3] {
    [0, 1, 2].map(|k| a[k] * b[k] + c[k] * d[k] - e[k])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loops_compute_the_formulas() {
        let x: Vec<f32> = (0..37).map(|i| i as f32).collect();
        let y: Vec<f32> = (0..37).map(|i| (i % 3) as f32).collect();
        let want: f32 = x.iter().zip(&y).map(|(a, b)| a * b).sum();
        assert_eq!(dot(&x, &y), want);
        assert_eq!(sum(&x), 666.0);
        let mut out = vec![0.0; 37];
        abcde(&x, &y, &y, &x, &x, &mut out);
        assert!(out
            .iter()
            .zip(&x)
            .zip(&y)
            .all(|((o, a), b)| *o == 2.0 * a * b - a));
        let mut z = y.clone();
        axpy(2.0, &x, &mut z);
        assert_eq!(z[5], 2.0 * 5.0 + 2.0);
        assert_eq!(reflect3([1.0, -1.0, 0.0], [0.0, 1.0, 0.0]), [1.0, 1.0, 0.0]);
        assert_eq!(cross3([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(normalize3([3.0, 0.0, 4.0]), [0.6, 0.0, 0.8]);
        assert_eq!(
            refract3([0.0, -1.0, 0.0], [0.0, 1.0, 0.0], 1.5),
            [0.0, -1.0, 0.0]
        );
        assert_eq!(refract3([0.8, -0.6, 0.0], [0.0, 1.0, 0.0], 1.5), [0.0; 3]);
        let cols = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]];
        assert_eq!(mat3_mul(&cols, [1.0, 1.0, 1.0]), [12.0, 15.0, 18.0]);
        assert_eq!(
            abcde3([1.0; 3], [2.0; 3], [3.0; 3], [4.0; 3], [5.0; 3]),
            [9.0; 3]
        );
    }
}
