//! Size and alignment of vecexpr's types: vectors and packets are exactly their elements
//! (no header, no padding), and expression nodes are no bigger than the references and
//! scalars they hold (operations are zero-sized type parameters).

use core::mem::{align_of, size_of, size_of_val};
use vecexpr::op::{AddOp, MulOp, NegOp, SqrtOp};
use vecexpr::typenum::{U1000, U16, U3, U4, U8};
use vecexpr::{
    vec3, Binary, Expr, PacketF32x16, PacketF32x4, PacketF32x8, PacketF64x4, PacketF64x8, Packet, PacketMask, Splat, Unary, Vec3,
    Vec4, Vector,
};

#[test]
fn plain_vectors_are_arrays() {
    assert_eq!(size_of::<Vector<f32, U3>>(), 12);
    assert_eq!(align_of::<Vector<f32, U3>>(), 4);
    assert_eq!(size_of::<Vec3<f64>>(), 24);
    assert_eq!(align_of::<Vec3<f64>>(), 8);
    assert_eq!(size_of::<Vec4<f32>>(), 16);
    assert_eq!(size_of::<Vector<f32, U1000>>(), 4000);
    assert_eq!(size_of::<Vector<f64, U16>>(), 128);
}

#[test]
fn packets_are_their_lanes() {
    assert_eq!(size_of::<PacketF32x4>(), 16);
    assert_eq!(size_of::<PacketF32x8>(), 32);
    assert_eq!(size_of::<PacketF32x16>(), 64);
    assert_eq!(size_of::<Packet<f32, U16>>(), 64);
    assert_eq!(size_of::<PacketF64x4>(), 32);
    assert_eq!(size_of::<PacketF64x8>(), 64);
    // Packets are not over-aligned: they are plain arrays, loaded with unaligned moves.
    assert_eq!(align_of::<PacketF32x16>(), 4);
    assert_eq!(align_of::<PacketF64x8>(), 8);
    // A mask has one lane-sized word per lane.
    assert_eq!(size_of::<PacketMask<f32, U8>>(), 32);
    assert_eq!(size_of::<PacketMask<f64, U4>>(), 32);
    // SoA vectors of packets: one packet per component.
    assert_eq!(size_of::<Vector<PacketF32x8, U3>>(), 96);
    assert_eq!(size_of::<Vector<PacketF32x16, U3>>(), 192);
    assert_eq!(size_of::<Vector<PacketF64x4, U4>>(), 128);
}

/// Every scalar type and dimension of the property tests: `Vector<T, N>` is `[T; N]`.
macro_rules! layout_case {
    ($m:ident, $t:ty, $e:ty, $n:ty, $k:literal, $kind:ident) => {
        #[test]
        fn $m() {
            assert_eq!(size_of::<Vector<$t, $n>>(), $k * size_of::<$t>());
            assert_eq!(size_of::<Vector<$t, $n>>(), size_of::<[$t; $k]>());
            assert_eq!(align_of::<Vector<$t, $n>>(), align_of::<$e>());
            assert_eq!(size_of::<$t>(), <$t as vecexpr::Scalar>::LANES * size_of::<$e>());
        }
    };
}

integration_tests::for_each_case!(layout_case);

#[test]
fn expression_nodes_hold_only_their_operands() {
    let a = vec3(1.0f32, 2.0, 3.0);
    let b = vec3(4.0f32, 5.0, 6.0);
    let ptr = size_of::<&Vec3<f32>>();
    // The operation is a zero-sized type parameter.
    assert_eq!(size_of::<AddOp>(), 0);
    assert_eq!(size_of::<NegOp>(), 0);
    let sum = &a + &b;
    assert_eq!(size_of_val(&sum), 2 * ptr);
    assert_eq!(size_of::<Binary<&Vec3<f32>, &Vec3<f32>, MulOp>>(), 2 * ptr);
    assert_eq!(size_of::<Unary<&Vec3<f32>, SqrtOp>>(), ptr);
    assert_eq!(size_of::<Splat<f32, U3>>(), 4);
    assert_eq!(size_of::<Splat<PacketF32x16, U3>>(), 64);
    let tree = &a * &b + &a * 2.0f32 - &b;
    // (a*b) + (a*2) - b: two references, a reference beside a padded f32, a reference.
    let scaled = size_of::<Binary<&Vec3<f32>, Splat<f32, U3>, MulOp>>();
    assert_eq!(size_of_val(&tree), 2 * ptr + scaled + ptr);
    assert_eq!(tree.eval(), vec3(2.0, 9.0, 18.0));
    // Copy-able vectors stay Copy, and so do nodes over references.
    let c = a;
    let s2 = sum;
    assert_eq!((c + s2.eval()).eval(), vec3(6.0, 9.0, 12.0));
    assert_eq!(sum.eval(), s2.eval());
}
