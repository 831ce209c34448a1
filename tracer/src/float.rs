//! The precisions the tracer runs in, and which kernels each one has.
//!
//! Everything from the scene to the image is generic over the scalar `T: Float` (`f32` or
//! `f64`). Some kernels exist for `f32` only, because `vecexpr`'s SIMD lane types are
//! `f32` lanes: the ray packets ([`crate::packets`]), the four-triangle test on SSE
//! registers ([`crate::geometry::triangle::Tri4`]) and the renderers specialised per effect
//! set ([`crate::effects`]). Which precision has them is stated by the type:
//! [`Float::AS_F32`] holds a proof of type [`Float::F32`] for `f32`, and `f64`'s proof type
//! is uninhabited, so the `f32`-only code cannot be reached from `f64` code at all. Generic
//! code holding the proof views its `T` data as `f32` data with [`Float::to_f32`] and
//! returns `f32` results as `T` with [`Float::from_f32`] (both are the identity). After
//! monomorphisation the test of `AS_F32` is a constant, so no branch remains.

use vecexpr::Real;

/// A type constructor over the precision (`Scene<T>`, `[Option<Hit<T>>; N]`, ...), for the
/// casts of [`Float`].
pub trait Family {
    /// The type in precision `T`.
    type Of<T: Float>;
}

/// The [`Family`] of the precision itself: `ScalarOf::Of<T>` is `T`, for casting a
/// single value.
pub(crate) struct ScalarOf;
impl Family for ScalarOf {
    type Of<T: Float> = T;
}

/// A precision of the tracer: a [`Real`] that says whether it has the `f32`-only kernels.
pub trait Float: Real {
    /// Proof that `Self` is `f32`: [`IsF32`] for `f32`, the uninhabited [`NotF32`] for
    /// `f64`.
    type F32: Copy + core::fmt::Debug + Send + Sync + 'static;
    /// The proof, for `f32`; `None` for `f64`.
    const AS_F32: Option<Self::F32>;
    /// `x` seen in `f32` (the identity: `Self` is `f32`).
    fn to_f32<F: Family>(proof: Self::F32, x: &F::Of<Self>) -> &F::Of<f32>;
    /// `x` seen in `Self` (the identity: `Self` is `f32`).
    fn from_f32<F: Family>(proof: Self::F32, x: F::Of<f32>) -> F::Of<Self>;
}

/// The proof that a precision is `f32`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IsF32;

/// The proof type of a precision that is not `f32`: it has no values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NotF32 {}

impl Float for f32 {
    type F32 = IsF32;
    const AS_F32: Option<IsF32> = Some(IsF32);
    #[inline(always)]
    fn to_f32<F: Family>(_: IsF32, x: &F::Of<f32>) -> &F::Of<f32> {
        x
    }
    #[inline(always)]
    fn from_f32<F: Family>(_: IsF32, x: F::Of<f32>) -> F::Of<f32> {
        x
    }
}

impl Float for f64 {
    type F32 = NotF32;
    const AS_F32: Option<NotF32> = None;
    #[inline(always)]
    fn to_f32<F: Family>(proof: NotF32, _: &F::Of<f64>) -> &F::Of<f32> {
        match proof {}
    }
    #[inline(always)]
    fn from_f32<F: Family>(proof: NotF32, _: F::Of<f32>) -> F::Of<f64> {
        match proof {}
    }
}
