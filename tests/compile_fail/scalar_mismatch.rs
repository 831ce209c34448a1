// An f32 vector plus an f64 vector: the error names the scalar mismatch and the fix.
use vecexpr::{vec3, Expr};

fn main() {
    let a = vec3(1.0f32, 2.0, 3.0);
    let b = vec3(1.0f64, 2.0, 3.0);
    let _ = (&a + &b).eval();
}
