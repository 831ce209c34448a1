//! The slab test of one ray against the four child boxes of a wide node: lane `i`
//! computes exactly what the binary tree's [`TraversalRay::hit_box`] computes for child
//! `i` (the conservative test of Ize 2013). In `f32` on x86-64 the four lanes are one SSE
//! register; otherwise `vecexpr`'s plain-array packets of four.
//!
//! # Why the formula is written out here
//! The other box tests call the one source of the formula,
//! [`slab`](crate::bvh::traverse::slab). This one writes
//! its operations out, in the same order: calling `slab` on the plain-array packets,
//! with the same operations, compiled to slower code: single rays (`--packets off`) on
//! balls-s4 at 128 x 128 ran 168.1 M instructions (callgrind, whole run) instead of
//! 152.9 M, +10 %. Even written out, the plain-array form depends on how the optimiser
//! sees the lanes, which differs between the instantiations of the walk; hence the SSE
//! form for `f32` ([`Box4Ray::hit_bits`]). The test against the scalar test below
//! (`packet_test_matches_the_scalar_test`) keeps the forms in step.

use super::{Node4, Node8, WideNode, WIDTH, WIDTH8};
use crate::bvh::traverse::TraversalRay;
use crate::float::{Family, Float, ScalarOf};
use vecexpr::typenum::U4;
use vecexpr::{Mask, Packet, Real, Scalar};

type P4<T> = Packet<T, U4>;

impl<T: Float> TraversalRay<T> {
    /// The slab test of [`TraversalRay::hit_box`] for the four children of `node` at
    /// once: per lane, whether the ray overlaps the box within `(t_min, t_max]`
    /// (conservatively) and the entry distance.
    #[inline(always)]
    pub fn hit_box4(&self, node: &Node4, t_max: T) -> ([bool; WIDTH], [T; WIDTH]) {
        let (bits, t_near) = self.hit_box4_bits(node, t_max);
        (core::array::from_fn(|i| bits & (1 << i) != 0), t_near)
    }

    /// [`TraversalRay::hit_box4`] with the hit lanes as bits (`1 << lane`), which the
    /// traversal branches on once instead of once per lane. (The traversal prepares
    /// the ray once, [`Box4Ray::new`], and tests every node with [`Box4Ray::hit_bits`].)
    #[inline(always)]
    pub fn hit_box4_bits(&self, node: &Node4, t_max: T) -> (u32, [T; WIDTH]) {
        Box4Ray::new(self).hit_bits(node, t_max)
    }
}

/// A [`TraversalRay`] prepared for the four-wide box tests of one traversal: its
/// values splatted into lanes and its near-plane side per axis as an index, once per
/// traversal instead of once per node. (Per node, the splats and the index arithmetic
/// of the near and far planes were about a third of the box test's instructions.)
pub struct Box4Ray<T: Real> {
    origin: [P4<T>; 3],
    inv_dir: [P4<T>; 3],
    inv_far: [P4<T>; 3],
    t_min: P4<T>,
    slack: T,
    /// Per axis, the byte offset in a [`Node4`] of the near planes' row
    /// `bounds[side][axis]` (`side` 1, `hi`, where the direction is negative) and of
    /// the far planes' row ([`plane`]).
    near: [usize; 3],
    far: [usize; 3],
}

/// Bytes of one row `bounds[side][axis]` of a [`WideNode<W>`].
const fn row_bytes<const W: usize>() -> usize {
    core::mem::size_of::<[f32; W]>()
}

/// The byte offset of row `bounds[side][axis]` in a [`WideNode<W>`] (`side` 0 or 1,
/// `axis` below 3): `bounds` is the first field of the `repr(C)` node.
const fn row_offset<const W: usize>(side: usize, axis: usize) -> usize {
    (side * 3 + axis) * row_bytes::<W>()
}

const _: () = assert!(core::mem::offset_of!(Node4, bounds) == 0);
const _: () = assert!(core::mem::offset_of!(Node8, bounds) == 0);

/// Row `bounds[side][axis]` of `node`, from its byte offset `row_offset(side, axis)`.
/// (An offset held per ray saves the index arithmetic of `node.bounds[side][axis]`,
/// two instructions a row, twelve a node.)
#[inline(always)]
fn plane<const W: usize>(node: &WideNode<W>, offset: usize) -> &[f32; W] {
    debug_assert!(offset.is_multiple_of(row_bytes::<W>()) && offset <= row_offset::<W>(1, 2));
    // SAFETY: `offset` is `row_offset::<W>(side, axis)` with `side < 2` and `axis < 3`
    // (the only offsets `Box4Ray::new` and `Box8Ray::new` make, and their fields are
    // private), so it is the byte offset of `node.bounds[side][axis]`, an aligned
    // `[f32; W]` inside `*node`: `WideNode` is `repr(C)` with
    // `bounds: [[[f32; W]; 3]; 2]` first. The reference borrows `node`.
    unsafe {
        &*(node as *const WideNode<W>)
            .cast::<u8>()
            .add(offset)
            .cast::<[f32; W]>()
    }
}

/// The box test of one ray against the `W` children of a node, as the single-ray walk
/// ([`Bvh::traverse4`](crate::bvh::Bvh::traverse4)) calls it: the hit lanes as bits and
/// each lane's entry distance.
pub trait NodeTest<T, const W: usize> {
    /// Which children of `node` the ray overlaps within `(t_min, t_max]`
    /// (conservatively), as bits `1 << lane`, and their entry distances.
    fn node_hits(&self, node: &WideNode<W>, t_max: T) -> (u32, [T; W]);
}

impl<T: Float> NodeTest<T, WIDTH> for Box4Ray<T> {
    #[inline(always)]
    fn node_hits(&self, node: &Node4, t_max: T) -> (u32, [T; WIDTH]) {
        self.hit_bits(node, t_max)
    }
}

impl<T: Float> Box4Ray<T> {
    /// The prepared form of `ray`.
    #[inline(always)]
    pub fn new(ray: &TraversalRay<T>) -> Self {
        let side = ray.neg.map(usize::from);
        Self {
            origin: ray.origin.map(P4::<T>::splat),
            inv_dir: ray.inv_dir.map(P4::<T>::splat),
            inv_far: ray.inv_far.map(P4::<T>::splat),
            t_min: P4::<T>::splat(ray.t_min),
            slack: ray.slack,
            near: [0, 1, 2].map(|a| row_offset::<WIDTH>(side[a], a)),
            far: [0, 1, 2].map(|a| row_offset::<WIDTH>(1 - side[a], a)),
        }
    }

    /// The slab test of [`TraversalRay::hit_box`] for the four children of `node` at
    /// once: the hit lanes as bits (`1 << lane`) and each lane's entry distance.
    ///
    /// In `f32` on x86-64 the lanes are one SSE register ([`vecexpr::simd::F32x4`]);
    /// elsewhere `vecexpr`'s plain-array packets. (In the any-hit walk of
    /// [`crate::world::Scene::occluded`] the optimiser turned the plain-array form into
    /// single-lane loads, shuffles and a lane-by-lane rebuild of the masks; the register
    /// form took teapot-s12's shadow rays from 1,112 to 704 instructions a ray.)
    #[inline(always)]
    pub fn hit_bits(&self, node: &Node4, t_max: T) -> (u32, [T; WIDTH]) {
        #[cfg(target_arch = "x86_64")]
        if let Some(p) = T::AS_F32 {
            let ray = T::to_f32::<Box4RayOf>(p, self);
            let t_max = *T::to_f32::<ScalarOf>(p, &t_max);
            return T::from_f32::<BitsOf<WIDTH>>(p, ray.hit_bits_sse(node, t_max));
        }
        self.hit_bits_packets(node, t_max)
    }

    /// [`Box4Ray::hit_bits`] over `vecexpr`'s plain-array packets.
    #[inline(always)]
    fn hit_bits_packets(&self, node: &Node4, t_max: T) -> (u32, [T; WIDTH]) {
        let lanes = |v: &[f32; WIDTH]| P4::<T>::from_fn(|i| T::from_f64(f64::from(v[i])));
        let mut t_near = self.t_min;
        let mut t_far = P4::<T>::splat(t_max * self.slack);
        for a in 0..3 {
            let near = lanes(plane(node, self.near[a]));
            let far = lanes(plane(node, self.far[a]));
            let o = self.origin[a];
            // The operations of `slab`, written out (see the module docs).
            let tn = (near - o) * self.inv_dir[a];
            let tf = (far - o) * self.inv_far[a];
            // minps/maxps rule per lane: a NaN `tn`/`tf` leaves the running value.
            t_near = Scalar::max(tn, t_near);
            t_far = Scalar::min(tf, t_far);
        }
        let hit = t_near.le(t_far);
        let mut bits = 0;
        for i in 0..WIDTH {
            bits |= (hit.test(i) as u32) << i;
        }
        (bits, core::array::from_fn(|i| t_near.lane(i)))
    }
}

#[cfg(target_arch = "x86_64")]
impl Box4Ray<f32> {
    /// [`Box4Ray::hit_bits`] on SSE registers: the same operations in the same order
    /// as [`Box4Ray::hit_bits_packets`], and `minps`/`maxps` are the NaN rule of
    /// [`Scalar::min`]/[`Scalar::max`], so every lane is bit for bit the same.
    #[inline(always)]
    fn hit_bits_sse(&self, node: &Node4, t_max: f32) -> (u32, [f32; WIDTH]) {
        use vecexpr::simd::{SimdF32, SimdMask};
        type S = vecexpr::simd::F32x4;
        let reg = |p: &P4<f32>| S::load(p.as_slice());
        let mut t_near = reg(&self.t_min);
        let mut t_far = S::splat(t_max * self.slack);
        for a in 0..3 {
            let near = S::load(plane(node, self.near[a]));
            let far = S::load(plane(node, self.far[a]));
            let o = reg(&self.origin[a]);
            let tn = (near - o) * reg(&self.inv_dir[a]);
            let tf = (far - o) * reg(&self.inv_far[a]);
            t_near = Scalar::max(tn, t_near);
            t_far = Scalar::min(tf, t_far);
        }
        let bits = t_near.le(t_far).bitmask();
        let mut tn = [0.0; WIDTH];
        t_near.store(&mut tn);
        (bits, tn)
    }
}

/// A [`TraversalRay`] prepared for the eight-wide box tests of one traversal, as
/// [`Box4Ray`] is for the four-wide ones, in AVX registers.
///
/// Only `f32` rays have it (the proof `T::F32`), and it must only be made and used
/// where the CPU has AVX2, inside code compiled for it: [`Bvh::traverse8`] says so.
///
/// [`Bvh::traverse8`]: crate::bvh::Bvh::traverse8
#[cfg(target_arch = "x86_64")]
pub struct Box8Ray<T: Float> {
    proof: T::F32,
    origin: [F32x8; 3],
    inv_dir: [F32x8; 3],
    inv_far: [F32x8; 3],
    t_min: F32x8,
    slack: f32,
    /// As [`Box4Ray`]'s, over the rows of a [`Node8`].
    near: [usize; 3],
    far: [usize; 3],
}

#[cfg(target_arch = "x86_64")]
use vecexpr::simd::F32x8;

/// Each component of `v` in all eight lanes. Written out rather than through
/// `array::map`, which the compiler may leave out of line, compiled for the baseline and
/// calling the broadcast intrinsic there instead of inlining it into the AVX2 walk.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn splat3(v: [f32; 3]) -> [F32x8; 3] {
    [F32x8::splat(v[0]), F32x8::splat(v[1]), F32x8::splat(v[2])]
}

#[cfg(target_arch = "x86_64")]
impl<T: Float> Box8Ray<T> {
    /// The prepared form of `ray` (`proof` that `T` is `f32`).
    #[inline(always)]
    pub fn new(proof: T::F32, ray: &TraversalRay<T>) -> Self {
        use vecexpr::Scalar;
        let ray = T::to_f32::<TraversalRayOf>(proof, ray);
        let side = ray.neg.map(usize::from);
        Self {
            proof,
            origin: splat3(ray.origin),
            inv_dir: splat3(ray.inv_dir),
            inv_far: splat3(ray.inv_far),
            t_min: F32x8::splat(ray.t_min),
            slack: ray.slack,
            near: [0, 1, 2].map(|a| row_offset::<WIDTH8>(side[a], a)),
            far: [0, 1, 2].map(|a| row_offset::<WIDTH8>(1 - side[a], a)),
        }
    }
}

#[cfg(target_arch = "x86_64")]
impl<T: Float> NodeTest<T, WIDTH8> for Box8Ray<T> {
    /// The slab test of [`TraversalRay::hit_box`] for the eight children of `node`:
    /// the operations of [`Box4Ray::hit_bits`] in the same order, lane by lane, so each
    /// child gets the same answer and entry distance as in the four-wide tree.
    #[inline(always)]
    fn node_hits(&self, node: &Node8, t_max: T) -> (u32, [T; WIDTH8]) {
        use vecexpr::simd::{SimdF32, SimdMask};
        let t_max = *T::to_f32::<ScalarOf>(self.proof, &t_max);
        let mut t_near = self.t_min;
        let mut t_far = F32x8::splat(t_max * self.slack);
        for a in 0..3 {
            let near = F32x8::load(plane(node, self.near[a]));
            let far = F32x8::load(plane(node, self.far[a]));
            let o = self.origin[a];
            let tn = (near - o) * self.inv_dir[a];
            let tf = (far - o) * self.inv_far[a];
            t_near = Scalar::max(tn, t_near);
            t_far = Scalar::min(tf, t_far);
        }
        let bits = t_near.le(t_far).bitmask();
        let mut tn = [0.0; WIDTH8];
        t_near.store(&mut tn);
        T::from_f32::<BitsOf<WIDTH8>>(self.proof, (bits, tn))
    }
}

struct TraversalRayOf;
impl Family for TraversalRayOf {
    type Of<T: Float> = TraversalRay<T>;
}

/// [`Family`]s of the types [`Box4Ray::hit_bits`] views as `f32`.
struct Box4RayOf;
impl Family for Box4RayOf {
    type Of<T: Float> = Box4Ray<T>;
}
/// The hit bits and entry distances of a `W`-wide box test.
struct BitsOf<const W: usize>;
impl<const W: usize> Family for BitsOf<W> {
    type Of<T: Float> = (u32, [T; W]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use vecexpr::vec3;

    #[test]
    fn packet_test_matches_the_scalar_test() {
        let boxes = [
            [[0.0f32, 0.0, 0.0], [1.0, 1.0, 1.0]],
            [[2.0, -1.0, 0.0], [3.0, 1.0, 0.0]],
            [[-5.0, -5.0, -5.0], [-4.0, -4.0, -4.0]],
            [[0.0, 0.5, -1.0], [0.0, 0.5, 1.0]],
        ];
        let mut node = Node4::EMPTY;
        for (i, b) in boxes.iter().enumerate() {
            node.set(i, b, i as u32, 1);
        }
        for (o, d) in [
            (vec3(-1.0f32, 0.5, 0.5), vec3(1.0, 0.0, 0.0)),
            (vec3(-1.0, 0.5, 0.0), vec3(1.0, 0.0, 0.0)),
            (vec3(0.0, 0.5, -2.0), vec3(0.0, 0.0, 1.0)),
            (vec3(10.0, 10.0, 10.0), vec3(-1.0, -1.0, -1.0)),
        ] {
            let r = TraversalRay::new(&o, &d, 0.0);
            for t_max in [f32::INFINITY, 1.5] {
                let (hit, tn) = r.hit_box4(&node, t_max);
                for (i, b) in boxes.iter().enumerate() {
                    let scalar = r.hit_box(b, t_max);
                    assert_eq!(scalar.is_some(), hit[i], "{o:?} {d:?} box {i}");
                    if let Some(t) = scalar {
                        assert_eq!(t, tn[i]);
                    }
                }
            }
        }
        let r = TraversalRay::new(&vec3(0.0f64, 0.0, 0.0), &vec3(1.0, 1.0, 1.0), 0.0);
        assert_eq!(r.hit_box4(&Node4::EMPTY, f64::INFINITY).0, [false; 4]);
    }
}
