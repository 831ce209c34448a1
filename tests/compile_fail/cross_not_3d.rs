// `cross` of two 4-vectors: the error says cross needs 3-vectors and what to do.
use vecexpr::{vec4, Expr};

fn main() {
    let a = vec4(1.0f32, 0.0, 0.0, 0.0);
    let b = vec4(0.0f32, 1.0, 0.0, 0.0);
    let _ = a.cross(&b);
}
