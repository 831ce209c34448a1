//! Eager vectors: the conventional operator-overloading design in which every operator
//! computes its whole result into a new vector at once. `a*b + c*d - e` therefore
//! builds three temporaries before the final one, each in its own loop.
//!
//! [`Eager`] stores its elements inline in a [`GenericArray`] (the thesis's fixed-size
//! eager vector: temporaries live on the stack, so after inlining LLVM may still fuse
//! small ones). [`EagerHeap`] allocates each result on the heap, as `std::valarray` or a
//! dynamic vector library does; it is the eager baseline for long vectors, which do not
//! fit on the stack.

use core::ops::{Add, Mul, Sub};
use generic_array::{ArrayLength, GenericArray};
use typenum::U3;
use vecexpr::{Real, Scalar};

/// A fixed-size eager vector of `N` elements of `T`, stored inline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eager<T: Copy, N: ArrayLength>(pub GenericArray<T, N>)
where
    GenericArray<T, N>: Copy;

impl<T: Scalar, N: ArrayLength> Eager<T, N>
where
    GenericArray<T, N>: Copy,
{
    /// A vector whose element `i` is `f(i)`.
    #[inline]
    pub fn from_fn(f: impl FnMut(usize) -> T) -> Self {
        Self(GenericArray::from_iter((0..N::USIZE).map(f)))
    }

    /// Element-wise combination into a new vector (the one loop of every operator).
    #[inline]
    fn zip(&self, rhs: &Self, f: impl Fn(T, T) -> T) -> Self {
        Self::from_fn(|i| f(self.0[i], rhs.0[i]))
    }

    /// `self * s` into a new vector.
    #[inline]
    pub fn scale(&self, s: T) -> Self {
        Self::from_fn(|i| self.0[i] * s)
    }

    /// $\sum_i x_i y_i$: the element-wise product is materialised first, then summed.
    #[inline]
    pub fn dot(&self, rhs: &Self) -> T {
        let p = self * rhs;
        let mut acc = p.0[0];
        for &x in &p.0[1..] {
            acc += x;
        }
        acc
    }

    /// $x / \lVert x \rVert$ (no zero check, like glam's `normalize`).
    #[inline]
    pub fn normalize(&self) -> Self {
        self.scale(self.dot(self).sqrt().recip())
    }

    /// $R = I - 2 N (N \cdot I)$, each operator a temporary.
    #[inline]
    pub fn reflect(&self, n: &Self) -> Self {
        let d = n.dot(self);
        self - &n.scale(d + d)
    }

    /// Snell refraction with $\eta$; zero on total internal reflection.
    #[inline]
    pub fn refract(&self, n: &Self, eta: T) -> Self {
        let ni = n.dot(self);
        let one = T::one();
        let k = one - eta * eta * (one - ni * ni);
        let ok = k.ge(T::zero());
        let a = T::select(ok, eta, T::zero());
        let b = T::select(ok, eta * ni + T::select(ok, k, T::zero()).sqrt(), T::zero());
        &self.scale(a) - &n.scale(b)
    }
}

impl<T: Scalar> Eager<T, U3>
where
    GenericArray<T, U3>: Copy,
{
    /// Cross product.
    #[inline]
    pub fn cross(&self, b: &Self) -> Self {
        let (a, b) = (&self.0, &b.0);
        Self::from_fn(|i| match i {
            0 => a[1] * b[2] - a[2] * b[1],
            1 => a[2] * b[0] - a[0] * b[2],
            _ => a[0] * b[1] - a[1] * b[0],
        })
    }

    /// The 3×3 matrix with columns `cols` times `v`: $c_0 v_x + c_1 v_y + c_2 v_z$,
    /// each product and sum a temporary.
    #[inline]
    pub fn mat3_mul(cols: &[Self; 3], v: &Self) -> Self {
        &(&cols[0].scale(v.0[0]) + &cols[1].scale(v.0[1])) + &cols[2].scale(v.0[2])
    }
}

macro_rules! eager_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<T: Scalar, N: ArrayLength> $tr<&Eager<T, N>> for &Eager<T, N>
        where
            GenericArray<T, N>: Copy,
        {
            type Output = Eager<T, N>;
            #[inline]
            fn $f(self, rhs: &Eager<T, N>) -> Eager<T, N> {
                self.zip(rhs, |a, b| a $op b)
            }
        }
        impl<T: Scalar> $tr<&EagerHeap<T>> for &EagerHeap<T> {
            type Output = EagerHeap<T>;
            #[inline]
            fn $f(self, rhs: &EagerHeap<T>) -> EagerHeap<T> {
                assert_eq!(self.0.len(), rhs.0.len(), "length mismatch");
                EagerHeap(self.0.iter().zip(&rhs.0).map(|(&a, &b)| a $op b).collect())
            }
        }
    };
}
eager_op!(Add, add, +);
eager_op!(Sub, sub, -);
eager_op!(Mul, mul, *);

/// A heap-allocated eager vector: every operator allocates its result.
#[derive(Clone, Debug, PartialEq)]
pub struct EagerHeap<T>(pub Vec<T>);

impl<T: Scalar> EagerHeap<T> {
    /// `self * s` into a new allocation.
    #[inline]
    pub fn scale(&self, s: T) -> Self {
        Self(self.0.iter().map(|&a| a * s).collect())
    }

    /// $\sum_i x_i y_i$: the product vector is materialised, then summed with the same
    /// 16 interleaved partial sums as the hand-written loop.
    #[inline]
    pub fn dot(&self, rhs: &Self) -> T {
        crate::hand::sum(&(self * rhs).0)
    }
}

/// `f32` conversion helpers for building inputs.
pub trait FromF32: Sized {
    /// From three `f32` components.
    fn from3(v: [f32; 3]) -> Self;
}

impl<T: Real> FromF32 for Eager<T, U3> {
    fn from3(v: [f32; 3]) -> Self {
        Self::from_fn(|i| <T as Real>::from_f64(f64::from(v[i])))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vecexpr::{vec3, Expr};

    #[test]
    fn eager_matches_vecexpr() {
        let i = [0.3f32, -0.9, 0.1];
        let n = {
            let l = (0.01f32 + 1.0 + 0.04).sqrt();
            [0.1 / l, 1.0 / l, -0.2 / l]
        };
        let (ei, en) = (Eager::<f32, U3>::from3(i), Eager::<f32, U3>::from3(n));
        let (vi, vn) = (vec3(i[0], i[1], i[2]), vec3(n[0], n[1], n[2]));
        assert_eq!(ei.reflect(&en).0.as_slice(), vi.reflect(&vn).as_slice());
        assert_eq!(ei.cross(&en).0.as_slice(), vi.cross(&vn).as_slice());
        let r = ei.refract(&en, 0.8);
        let t = vi.refract_masked(&vn, 0.8).0;
        for k in 0..3 {
            assert!((r.0[k] - t[k]).abs() < 1e-6);
        }
        let h = EagerHeap(vec![1.0f32, 2.0, 3.0]);
        assert_eq!((&(&h * &h) + &h.scale(2.0)).0, vec![3.0, 8.0, 15.0]);
        assert_eq!(h.dot(&h), 14.0);
    }
}
