// A 3×3 matrix times a 2-vector: the error names the inner dimensions of the product.
use vecexpr::{vec2, Mat3};

fn main() {
    let m = Mat3::<f32>::identity();
    let _ = &m * &vec2(1.0f32, 2.0);
}
