//! Optional approximate arithmetic in shading, to measure what exactness costs.
//!
//! [`Arith::default()`] is exact and computes bit for bit what the shading code always
//! computed. Each flag swaps one kind of operation in [`crate::shade`] for a cheaper or
//! differently rounded one:
//!
//! - `rsqrt`: unit vectors (light directions, reflected and refracted ray directions) by
//!   [`Expr::normalize_approx`] (a magic-constant reciprocal square root plus one Newton
//!   step, relative length error up to about 1.8e-3) instead of a square root and a
//!   division;
//! - `int_pow`: the Phong highlight $(R \cdot V)^n$ with $n$ rounded to the nearest integer
//!   and raised by repeated squaring ([`pow_int`]) instead of `powf`;
//! - `fma`: fused multiply-adds in the shading dot products, the light's mirror direction
//!   and the colour accumulation. Without hardware FMA (see [`HARDWARE_FMA`]) each one is
//!   a library call.

use vecexpr::{Expr, Real, Vec3};

/// Whether this build has hardware fused multiply-add (`-C target-cpu=x86-64-v3` or newer
/// on x86-64). Without it `mul_add` is a call into the maths library.
pub const HARDWARE_FMA: bool = cfg!(target_feature = "fma");

/// Which approximations shading uses; the default is exact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Arith {
    /// Approximate reciprocal square root (one Newton step) in normalisation.
    pub rsqrt: bool,
    /// Phong exponent rounded to an integer and raised by squaring, not `powf`.
    pub int_pow: bool,
    /// Fused multiply-add in shading dot products and colour sums.
    pub fma: bool,
}

impl Arith {
    /// Exact arithmetic (the default).
    pub const EXACT: Self = Self {
        rsqrt: false,
        int_pow: false,
        fma: false,
    };

    /// Is every flag off?
    pub fn is_exact(&self) -> bool {
        *self == Self::EXACT
    }

    /// A short name: `exact`, or the flags joined by `+` (`rsqrt+int-pow+fma`).
    pub fn label(&self) -> String {
        let names: Vec<&str> = [
            (self.rsqrt, "rsqrt"),
            (self.int_pow, "int-pow"),
            (self.fma, "fma"),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, n)| *n)
        .collect();
        if names.is_empty() {
            "exact".to_string()
        } else {
            names.join("+")
        }
    }

    /// $v / \lVert v \rVert$.
    #[inline(always)]
    pub fn normalize<T: Real>(&self, v: &Vec3<T>) -> Vec3<T> {
        if self.rsqrt {
            v.normalize_approx()
        } else {
            v.normalize()
        }
    }

    /// The unit vector along `v` and the length of `v`.
    #[inline(always)]
    pub fn unit_and_length<T: Real>(&self, v: &Vec3<T>) -> (Vec3<T>, T) {
        if self.rsqrt {
            let l2 = self.dot(v, v);
            let r = l2.rsqrt_approx();
            (v.scale(r).eval(), l2 * r)
        } else {
            let len = if self.fma {
                self.dot(v, v).sqrt()
            } else {
                v.length()
            };
            (v.scale(len.recip()).eval(), len)
        }
    }

    /// $a \cdot b$.
    #[inline(always)]
    pub fn dot<T: Real>(&self, a: &Vec3<T>, b: &Vec3<T>) -> T {
        if self.fma {
            a[2].mul_add(b[2], a[1].mul_add(b[1], a[0] * b[0]))
        } else {
            a.dot(b)
        }
    }

    /// The mirror of `i` about the unit normal `n`: $I - 2 N (N \cdot I)$.
    #[inline(always)]
    pub fn reflect<T: Real>(&self, i: &Vec3<T>, n: &Vec3<T>) -> Vec3<T> {
        if self.fma {
            let d = self.dot(n, i);
            n.mul_add(-(d + d), i).eval()
        } else {
            i.reflect(n)
        }
    }

    /// `acc += v * s`.
    #[inline(always)]
    pub fn add_scaled<T: Real>(&self, acc: &mut Vec3<T>, v: &Vec3<T>, s: T) {
        if self.fma {
            *acc = v.mul_add(s, &*acc).eval();
        } else {
            *acc += v.scale(s);
        }
    }

    /// $x^e$: `powf`, or with `int_pow` $x^{\mathrm{round}(e)}$ by squaring (exponents
    /// that are negative, not finite or above $2^{16}$ still use `powf`).
    #[inline(always)]
    pub fn pow<T: Real>(&self, x: T, e: T) -> T {
        if self.int_pow {
            let n = e.to_f64().round();
            if (0.0..=65536.0).contains(&n) {
                return pow_int(x, n as u32);
            }
        }
        x.powf(e)
    }
}

/// $x^n$ by binary exponentiation (square and multiply, Knuth TAOCP vol. 2, 4.6.3):
/// about $2 \log_2 n$ multiplications.
#[inline]
pub fn pow_int<T: Real>(mut x: T, mut n: u32) -> T {
    let mut acc = T::ONE;
    while n > 0 {
        if n & 1 == 1 {
            acc *= x;
        }
        n >>= 1;
        if n > 0 {
            x *= x;
        }
    }
    acc
}
