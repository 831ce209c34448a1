//! The slab test of one ray against the four child boxes of a wide node, over `vecexpr`
//! packets of four lanes: lane `i` computes exactly what the binary tree's
//! [`TraversalRay::hit_box`] computes for child `i` (the conservative test of Ize 2013).
//!
//! # Why the formula is written out here
//! The other box tests call the one source of the formula,
//! [`slab`](crate::bvh::traverse::slab). This one writes
//! its operations out, in the same order: it runs on `vecexpr`'s plain-array packets
//! (`Packet<T, U4>`, for `f32` and `f64` alike), whose code depends on how the
//! optimiser sees the lanes, and calling `slab` here, with the same operations,
//! compiled to slower code: single rays (`--packets off`) on balls-s4 at 128 x 128 ran
//! 168.1 M instructions (callgrind, whole run) instead of 152.9 M, +10 %. The test
//! against the scalar test below (`packet_test_matches_the_scalar_test`) keeps the two
//! in step.

use super::{Node4, WIDTH};
use crate::bvh::traverse::TraversalRay;
use vecexpr::typenum::U4;
use vecexpr::{Mask, Packet, Real, Scalar};

type P4<T> = Packet<T, U4>;

impl<T: Real> TraversalRay<T> {
    /// The slab test of [`TraversalRay::hit_box`] for the four children of `node` at
    /// once: per lane, whether the ray overlaps the box within `(t_min, t_max]`
    /// (conservatively) and the entry distance.
    #[inline(always)]
    pub fn hit_box4(&self, node: &Node4, t_max: T) -> ([bool; WIDTH], [T; WIDTH]) {
        let (bits, t_near) = self.hit_box4_bits(node, t_max);
        (core::array::from_fn(|i| bits & (1 << i) != 0), t_near)
    }

    /// [`TraversalRay::hit_box4`] with the hit lanes as bits (`1 << lane`), which the
    /// traversal branches on once instead of once per lane.
    #[inline(always)]
    pub fn hit_box4_bits(&self, node: &Node4, t_max: T) -> (u32, [T; WIDTH]) {
        let lanes = |v: &[f32; WIDTH]| P4::<T>::from_fn(|i| T::from_f64(f64::from(v[i])));
        let mut t_near = P4::<T>::splat(self.t_min);
        let mut t_far = P4::<T>::splat(t_max * self.slack);
        for a in 0..3 {
            let n = self.neg[a] as usize;
            let near = lanes(&node.bounds[n][a]);
            let far = lanes(&node.bounds[1 - n][a]);
            let o = P4::<T>::splat(self.origin[a]);
            let inv = P4::<T>::splat(self.inv_dir[a]);
            // The operations of `slab`, written out (see the module docs).
            let tn = (near - o) * inv;
            let tf = (far - o) * P4::<T>::splat(self.inv_far[a]);
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
