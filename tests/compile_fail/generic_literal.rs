// A float literal in code generic over the scalar: the error says to write
// `T::splat_f64(..)`.
use vecexpr::generic_array::ArrayLength;
use vecexpr::{Expr, Scalar, Vector};

fn half<T: Scalar, N: ArrayLength>(v: &Vector<T, N>) -> Vector<T, N> {
    (v * 0.5).eval()
}

fn main() {
    let _ = half(&vecexpr::vec3(1.0f32, 2.0, 3.0));
}
