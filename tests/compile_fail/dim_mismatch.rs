// A 3-vector plus a 4-vector: the error names the dimension mismatch and the fix.
use vecexpr::typenum::{U3, U4};
use vecexpr::{Expr, Vector};

fn main() {
    let a = Vector::<f32, U3>::splat(1.0);
    let b = Vector::<f32, U4>::splat(1.0);
    let _ = (&a + &b).eval();
}
