//! Compile-time computation: integer powers unrolled through typenum, in the spirit of
//! C++ template metaprogramming (the Phong exponent $(R \cdot V)^n$ with `n` known at
//! compile time costs about $\log_2 n$ multiplications and no loop or call).

use crate::scalar::Scalar;
use typenum::{Bit, UInt, UTerm, Unsigned};

/// $x^E$ for a typenum exponent `E`, by binary exponentiation unrolled at compile time.
///
/// `E = UInt<H, B>` is `2·H + B`, so $x^E = (x^H)^2 \cdot x^B$; the recursion over the
/// bits of `E` is resolved by the type checker, leaving straight-line multiplications.
///
/// # Examples
/// ```
/// use vecexpr::{powi, typenum::{U0, U5, U20}};
/// assert_eq!(powi::<U5, f32>(2.0), 32.0);
/// assert_eq!(powi::<U0, f64>(7.0), 1.0);
/// assert_eq!(powi::<U20, f64>(0.5), 0.5f64.powi(20));
/// ```
#[inline(always)]
pub fn powi<E: Pow, T: Scalar>(x: T) -> T {
    E::pow(x)
}

/// Exponents usable with [`powi`]: every typenum unsigned integer.
pub trait Pow: Unsigned {
    /// $x^{Self}$.
    fn pow<T: Scalar>(x: T) -> T;
}

impl Pow for UTerm {
    #[inline(always)]
    fn pow<T: Scalar>(_x: T) -> T {
        T::one()
    }
}

impl<H: Pow, B: Bit> Pow for UInt<H, B> {
    #[inline(always)]
    fn pow<T: Scalar>(x: T) -> T {
        // The most significant bit ends the recursion without a multiplication by one.
        let h = if H::USIZE == 0 {
            None
        } else {
            let p = H::pow(x);
            Some(p * p)
        };
        match (h, B::BOOL) {
            (None, true) => x,
            (None, false) => T::one(),
            (Some(h), true) => h * x,
            (Some(h), false) => h,
        }
    }
}
