//! Ordered stack traversal with a conservative slab test.
//!
//! At an interior node both children's boxes are tested; if both are hit the nearer
//! one (by entry distance) is visited first and the farther one is pushed with its
//! entry distance, so that it is skipped on pop once a closer hit is known. The stack
//! is a fixed array on the call stack: no allocation per ray.
//!
//! # Robustness
//! The slab test follows T. Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013: with the
//! inverse direction precomputed, the exit distance is enlarged by the factor
//! $s = 1 + 2\gamma_3$, $\gamma_n = n u / (1 - n u)$ with $u$ the unit roundoff of `T`,
//! which bounds the rounding error of $(b - o) / d$ so a box the ray truly touches is
//! never rejected. The factor is folded into the inverse direction of the far planes
//! (`inv_far` $= \mathrm{fl}(\mathrm{fl}(1/d)\, s)$) and into `t_max`, instead of
//! multiplying the smallest exit distance afterwards, which took a multiplication off the
//! chain of dependent operations from one node to the next. The error budget is the
//! same: the computed exit distance $\mathrm{fl}(\mathrm{fl}(b - o)\,\mathrm{inv\_far})$
//! carries five roundings of at most $u$ each (subtraction, reciprocal, $s$ itself, its
//! product with the reciprocal, the last product), as the exit distance multiplied
//! afterwards did (subtraction, reciprocal, product, $s$, product with $s$), and
//! $(1 + 2\gamma_3)(1 - u)^5 > 1$. The same factor is applied when a pushed node's
//! entry distance is compared with the closest hit. The near and far plane of each axis are chosen by the sign of
//! the direction, and the running `max`/`min` are written so that a NaN slab distance
//! (a zero direction component with the origin on the plane, $0 \cdot \infty$) is
//! ignored instead of rejecting the box.

use super::node::Node;
use super::wide::Leaf;
use super::Bvh;
use vecexpr::{Real, Scalar, Vec3};

/// Entries of the traversal stack: at most one pending node per level, and the builder
/// keeps every leaf within [`super::build::MAX_DEPTH`] levels of the root. Small, because
/// the array is zeroed on every query.
pub const STACK_SIZE: usize = super::build::MAX_DEPTH;

/// $\gamma_n = n u / (1 - n u)$ for the unit roundoff $u = \epsilon / 2$ of `T` (pbrt-v4
/// `gamma`, from Higham's error analysis).
#[inline(always)]
pub fn gamma<T: Real>(n: u32) -> T {
    let nu = T::from_i32(n as i32) * T::EPSILON * <T as Real>::from_f64(0.5);
    nu / (T::ONE - nu)
}

/// The factor $1 + 2\gamma_3$ on exit distances of [`TraversalRay`] (see the module
/// docs).
#[inline(always)]
pub fn slack<T: Real>() -> T {
    T::ONE + <T as Real>::from_f64(2.0) * gamma::<T>(3)
}

/// A ray prepared for box tests: origin, inverse direction and its signs.
#[derive(Clone, Copy, Debug)]
pub struct TraversalRay<T: Real> {
    /// Origin.
    pub origin: [T; 3],
    /// $1/d$ per axis ($\pm\infty$ for a zero component).
    pub inv_dir: [T; 3],
    /// Is the direction negative on this axis (so the near plane is `hi`)?
    pub neg: [bool; 3],
    /// Smallest accepted parameter.
    pub t_min: T,
    /// $1 + 2\gamma_3$.
    pub slack: T,
    /// `inv_dir` times `slack`: the far planes' distances are computed with it (see
    /// the module docs).
    pub inv_far: [T; 3],
}

impl<T: Real> TraversalRay<T> {
    /// Prepares `origin + t dir` for `t > t_min`.
    #[inline(always)]
    pub fn new(origin: &Vec3<T>, dir: &Vec3<T>, t_min: T) -> Self {
        let inv_dir = [dir[0].recip(), dir[1].recip(), dir[2].recip()];
        let slack = slack::<T>();
        Self {
            origin: [origin[0], origin[1], origin[2]],
            inv_dir,
            // 1/-0 = -inf, so a negative zero also picks `hi` as its near plane.
            neg: inv_dir.map(|x| x < T::ZERO),
            t_min,
            slack,
            inv_far: inv_dir.map(|x| x * slack),
        }
    }

    /// Entry distance into the box if the ray overlaps it within `(t_min, t_max]`
    /// (conservatively), else `None`.
    #[inline(always)]
    pub fn hit_box(&self, b: &[[f32; 3]; 2], t_max: T) -> Option<T> {
        let mut t = (self.t_min, t_max * self.slack);
        for a in 0..3 {
            let near = <T as Real>::from_f64(f64::from(b[self.neg[a] as usize][a]));
            let far = <T as Real>::from_f64(f64::from(b[!self.neg[a] as usize][a]));
            let ray = (self.origin[a], self.inv_dir[a], self.inv_far[a]);
            t = slab(t, near, far, ray);
        }
        (t.0 <= t.1).then_some(t.0)
    }
}

/// One axis of the slab test (Ize 2013, see the module docs), the one source of the
/// formula for one ray against one box ([`TraversalRay::hit_box`]) and for a packet of
/// rays against one box (`PacketRay::hit_box`, `PacketRay::hit_slot`, over the SIMD
/// lane types). Each lane of `V` holds one ray–box pair: `(t_near, t_far)` are its
/// running entry and exit distances (starting at `t_min` and at `t_max` times the slack
/// factor), `near` and `far` the box's planes the ray meets first and last on this axis
/// (picked by the sign of its direction), and `ray` its `(origin, inv_dir, inv_far)` on
/// this axis (as in [`TraversalRay`]). Returns the narrowed distances; after the three
/// axes the box is hit in the lanes where `t_near <= t_far`, and `t_near` is the entry
/// distance.
///
/// The callers differ only in how they fill the lanes (which operands are splatted and
/// how the planes are picked), which follows their data layout. The four-box test of a
/// wide node (`TraversalRay::hit_box4_bits`) writes the same operations out instead,
/// because calling this function there cost 10 % of the instructions of single rays;
/// its module docs (`bvh/wide/box_test.rs`) give the measurement.
#[inline(always)]
pub fn slab<V: Scalar>((t_near, t_far): (V, V), near: V, far: V, ray: (V, V, V)) -> (V, V) {
    let (origin, inv_dir, inv_far) = ray;
    let tn = (near - origin) * inv_dir;
    let tf = (far - origin) * inv_far;
    // minps/maxps rule: a NaN `tn`/`tf` leaves the running value unchanged.
    (Scalar::max(tn, t_near), Scalar::min(tf, t_far))
}

/// What the single-ray walks ([`Bvh::traverse`], [`Bvh::traverse4_from`]) ask of their
/// caller: the tests of a leaf.
///
/// A trait rather than a closure so that the method can be `#[inline(always)]`: a
/// closure is inlined at the compiler's discretion, and one query instance inlined at
/// two places (the shading's shadow test with and without its cache entry) called its
/// leaf closure out of line from both, which cost the any-hit query 2.9 % of the
/// instructions per frame on gears-s4 at depth 1 (see the docs of `crate::geometry`).
pub trait LeafVisitor<T> {
    /// Tests the primitives of `leaf`, which the ray reaches before `t_max`: `Some(t)`
    /// for a hit at `t <= t_max`, the walk's new `t_max`.
    fn leaf(&mut self, leaf: Leaf<'_>, t_max: T) -> Option<T>;
}

impl Bvh {
    /// Walks the tree front to back along `ray`, calling `visit.leaf` with
    /// [`Leaf::Refs`] for each leaf whose box the ray overlaps before `t_max`.
    ///
    /// `leaf` returns `Some(t)` when it found a hit at `t <= t_max`, which becomes the new
    /// `t_max`. With `ANY_HIT` the walk stops at the first such hit. Returns whether any
    /// leaf reported a hit.
    #[inline(always)]
    pub fn traverse<T: Real, const ANY_HIT: bool>(
        &self,
        ray: &TraversalRay<T>,
        mut t_max: T,
        visit: &mut impl LeafVisitor<T>,
    ) -> bool {
        let nodes: &[Node] = &self.nodes;
        let Some(root) = nodes.first() else {
            return false;
        };
        if ray.hit_box(&root.bounds, t_max).is_none() {
            return false;
        }
        let mut stack_node = [0u32; STACK_SIZE];
        let mut stack_t = [T::ZERO; STACK_SIZE];
        let mut sp = 0usize;
        let mut at = 0usize;
        let mut found = false;
        loop {
            let node = &nodes[at];
            if node.is_leaf() {
                let first = node.offset as usize;
                let refs = &self.refs[first..first + node.count as usize];
                if let Some(t) = visit.leaf(Leaf::Refs(refs), t_max) {
                    found = true;
                    if ANY_HIT {
                        return true;
                    }
                    t_max = t;
                }
            } else {
                let (l, r) = (at + 1, node.offset as usize);
                let hl = ray.hit_box(&nodes[l].bounds, t_max);
                let hr = ray.hit_box(&nodes[r].bounds, t_max);
                match (hl, hr) {
                    (Some(tl), Some(tr)) => {
                        let (near, far, t_far) = if tr < tl { (r, l, tl) } else { (l, r, tr) };
                        stack_node[sp] = far as u32;
                        stack_t[sp] = t_far;
                        sp += 1;
                        at = near;
                        continue;
                    }
                    (Some(_), None) => {
                        at = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        at = r;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop the nearest pending node that may still hold a closer hit.
            loop {
                if sp == 0 {
                    return found;
                }
                sp -= 1;
                if stack_t[sp] <= t_max * ray.slack {
                    at = stack_node[sp] as usize;
                    break;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vecexpr::vec3;

    const UNIT: [[f32; 3]; 2] = [[0.0; 3], [1.0; 3]];

    #[test]
    fn slab_test_basic() {
        let r = TraversalRay::new(&vec3(-1.0f32, 0.5, 0.5), &vec3(1.0, 0.0, 0.0), 0.0);
        assert_eq!(r.hit_box(&UNIT, f32::INFINITY), Some(1.0));
        assert_eq!(r.hit_box(&UNIT, 0.5), None);
        let away = TraversalRay::new(&vec3(-1.0f32, 0.5, 0.5), &vec3(-1.0, 0.0, 0.0), 0.0);
        assert_eq!(away.hit_box(&UNIT, f32::INFINITY), None);
        let inside = TraversalRay::new(&vec3(0.5f64, 0.5, 0.5), &vec3(0.0, -1.0, 0.0), 0.0);
        assert_eq!(inside.hit_box(&UNIT, f64::INFINITY), Some(0.0));
    }

    #[test]
    fn ray_in_a_face_plane_is_not_rejected() {
        // Origin on the plane x = 0 and no x motion: (0 - 0) * inf is NaN.
        for d in [vec3(0.0f32, 0.0, 1.0), vec3(-0.0f32, 0.0, 1.0)] {
            let r = TraversalRay::new(&vec3(0.0f32, 0.5, -1.0), &d, 0.0);
            assert_eq!(r.hit_box(&UNIT, f32::INFINITY), Some(1.0));
            let r = TraversalRay::new(&vec3(1.0f32, 0.5, -1.0), &d, 0.0);
            assert_eq!(r.hit_box(&UNIT, f32::INFINITY), Some(1.0));
        }
    }

    #[test]
    fn flat_box_is_hit() {
        let flat = [[0.0f32, 0.0, 0.0], [1.0, 1.0, 0.0]];
        let r = TraversalRay::new(&vec3(0.3f32, 0.3, 1.0), &vec3(0.0, 0.0, -1.0), 0.0);
        assert_eq!(r.hit_box(&flat, f32::INFINITY), Some(1.0));
    }

    #[test]
    fn gamma_values() {
        let g: f32 = gamma(3);
        assert!((g - 3.0 * f32::EPSILON / 2.0).abs() < 1e-12);
        let g: f64 = gamma(3);
        assert!(g > 0.0 && g < 1e-15);
    }
}
