//! One name per type: the crate root and `vecexpr::simd` can both be glob-imported.
//! The array packets are `PacketF32x8` and friends, the SIMD registers `F32x8` and
//! friends; a clash would make every use below ambiguous (an error), and an ambiguous
//! glob re-export would be a warning, denied here.
#![deny(warnings)]

use vecexpr::simd::*;
use vecexpr::typenum::{U3, U8};
use vecexpr::*;

#[test]
fn root_and_simd_globs_do_not_clash() {
    // The array packets of the root.
    let p: Vector<PacketF32x8, U3> = Vector::splat(PacketF32x8::splat(2.0));
    assert_eq!(p.sum(), PacketF32x8::splat(6.0));
    assert_eq!(PacketF32x4::LANES, 4);
    assert_eq!(PacketF32x16::LANES, 16);
    assert_eq!(PacketF64x4::LANES, 4);
    assert_eq!(PacketF64x8::LANES, 8);
    let _: Packet<f32, U8> = PacketF32x8::splat(1.0);
    // The registers of `simd`, x86-64 only; the rest of `simd` is everywhere.
    #[cfg(target_arch = "x86_64")]
    {
        let l = F32x4::splat(1.5);
        assert_eq!(l.lane(3), 1.5);
        assert_eq!(<F32x8 as Scalar>::LANES, 8);
        assert_eq!(<F32x16 as Scalar>::LANES, 16);
        let _: Option<M32x4> = None;
    }
    assert!(Isa::ALL.len() == 3);
    let _ = vec3(1.0f32, 2.0, 3.0).dot(&vec3(1.0, 1.0, 1.0));
}
