//! The compact BVH node and the conservative `f64` → `f32` rounding of its bounds.
//!
//! # Layout (32 bytes, two nodes per 64-byte cache line)
//! ```text
//! bounds[0] = lo.xyz   f32 x 3   12 bytes
//! bounds[1] = hi.xyz   f32 x 3   12 bytes
//! offset               u32        4 bytes  leaf: first index into `Bvh::refs`
//!                                          interior: index of the second child
//! count                u32        4 bytes  leaf: number of primitives (> 0)
//!                                          interior: 0
//! ```
//! Nodes are stored depth-first: an interior node's first child is the next node in
//! the array, so only the second child needs an index (pbrt-v4 `LinearBVHNode`).
//!
//! Bounds are `f32` for both precisions: a `f64` scene would need 56-byte nodes
//! otherwise. Each bound is rounded outward ([`round_down`], [`round_up`]), so the box
//! stored always contains the exact one and a box test in `f64` against it can only
//! report extra candidates, never miss a primitive. The extra width is one `f32` ulp,
//! far below the size of any leaf.
//!
//! `bounds[0]`/`bounds[1]` as an array of two lets the traversal select the near and far
//! plane of an axis with `bounds[neg as usize][axis]`, with no branch and no bounds check.

use vecexpr::Real;

/// One node of the flattened BVH (see the module docs for the layout).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub struct Node {
    /// `[lo, hi]` corners, rounded outward to `f32`.
    pub bounds: [[f32; 3]; 2],
    /// Leaf: first index into the reference array; interior: index of the second child.
    pub offset: u32,
    /// Leaf: number of primitives (at least 1); interior: 0.
    pub count: u32,
}

const _: () = assert!(core::mem::size_of::<Node>() == 32);
const _: () = assert!(core::mem::align_of::<Node>() == 32);

impl Node {
    /// Is this a leaf?
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.count != 0
    }

    /// A leaf over `refs[first..first + count]`.
    #[inline]
    pub fn leaf(bounds: [[f32; 3]; 2], first: u32, count: u32) -> Self {
        debug_assert!(count > 0);
        Self {
            bounds,
            offset: first,
            count,
        }
    }

    /// An interior node; the second child index is filled in later.
    #[inline]
    pub fn interior(bounds: [[f32; 3]; 2]) -> Self {
        Self {
            bounds,
            offset: 0,
            count: 0,
        }
    }
}

/// The largest `f32` not greater than `x` (`-inf` below the `f32` range, NaN stays NaN).
///
/// Without branches: whether the nearest `f32` lies above `x` is a coin toss for
/// arbitrary input, and six mispredicted branches a box cost about half of the making of
/// the build primitives (balls-s6: 14.5 ms of a 221 ms build). When the nearest `f32` `f`
/// lies above `x`, `f` is neither NaN nor `-inf`, and the next `f32` down is one step in
/// its bits: down in magnitude for positive `f` (`+inf` steps to `MAX`), up in magnitude
/// for negative `f` and for `-0.0` (to the smallest negative subnormal).
#[inline]
pub fn round_down(x: f64) -> f32 {
    let f = x as f32;
    let bits = f.to_bits() as i32;
    // -1 for a positive sign bit, +1 for a negative one.
    let step = -((bits >> 31) * 2 + 1);
    let down = f32::from_bits(bits.wrapping_add(step) as u32);
    if f64::from(f) > x {
        down
    } else {
        f
    }
}

/// The smallest `f32` not less than `x` (`+inf` above the `f32` range, NaN stays NaN);
/// without branches, as [`round_down`]. When the nearest `f32` `f` lies below `x`, `f` is
/// neither NaN nor `+inf` nor `-0.0` (a negative `x` rounds to a negative `f`, and only
/// a non-negative `x` lies above `-0.0`, which rounds to `+0.0`), and the next `f32` up
/// is one step in its bits: up for positive `f` and `+0.0`, down in magnitude for
/// negative `f` (`-inf` steps to `-MAX`).
#[inline]
pub fn round_up(x: f64) -> f32 {
    let f = x as f32;
    let bits = f.to_bits() as i32;
    // +1 for a positive sign bit, -1 for a negative one.
    let step = (bits >> 31) * 2 + 1;
    let up = f32::from_bits(bits.wrapping_add(step) as u32);
    if f64::from(f) < x {
        up
    } else {
        f
    }
}

/// An axis-aligned box under construction, in `f32` with outward rounding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds3 {
    /// Lower corner.
    pub lo: [f32; 3],
    /// Upper corner.
    pub hi: [f32; 3],
}

impl Default for Bounds3 {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Bounds3 {
    /// The empty box (`lo = +inf`, `hi = -inf`), identity of [`Bounds3::union`].
    pub const EMPTY: Self = Self {
        lo: [f32::INFINITY; 3],
        hi: [f32::NEG_INFINITY; 3],
    };

    /// The smallest `f32` box containing the `f64` box `[lo, hi]`.
    #[inline]
    pub fn from_f64(lo: [f64; 3], hi: [f64; 3]) -> Self {
        Self {
            lo: lo.map(round_down),
            hi: hi.map(round_up),
        }
    }

    /// The smallest `f32` box containing the points.
    pub fn from_points<T: Real>(points: &[vecexpr::Vec3<T>]) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in points {
            for a in 0..3 {
                let x = p[a].to_f64();
                lo[a] = lo[a].min(x);
                hi[a] = hi[a].max(x);
            }
        }
        Self::from_f64(lo, hi)
    }

    /// Grows to contain `other`.
    #[inline(always)]
    pub fn union(&mut self, other: &Self) {
        for a in 0..3 {
            self.lo[a] = vecexpr::Scalar::min(other.lo[a], self.lo[a]);
            self.hi[a] = vecexpr::Scalar::max(other.hi[a], self.hi[a]);
        }
    }

    /// Grows to contain the point `p`.
    #[inline(always)]
    pub fn add_point(&mut self, p: [f32; 3]) {
        for (a, &x) in p.iter().enumerate() {
            self.lo[a] = vecexpr::Scalar::min(x, self.lo[a]);
            self.hi[a] = vecexpr::Scalar::max(x, self.hi[a]);
        }
    }

    /// Half the surface area (the SAH only needs ratios); 0 for an empty box.
    #[inline(always)]
    pub fn half_area(&self) -> f32 {
        let d = [
            (self.hi[0] - self.lo[0]).max(0.0),
            (self.hi[1] - self.lo[1]).max(0.0),
            (self.hi[2] - self.lo[2]).max(0.0),
        ];
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }

    /// The box centre, clamped to the finite `f32` range (NaN becomes 0) so that binning
    /// never sees a non-finite centroid.
    #[inline(always)]
    pub fn centroid(&self) -> [f32; 3] {
        core::array::from_fn(|a| {
            // 0.5 lo + 0.5 hi cannot overflow for finite bounds.
            let c = 0.5 * self.lo[a] + 0.5 * self.hi[a];
            if c.is_nan() {
                0.0
            } else {
                c.clamp(-f32::MAX, f32::MAX)
            }
        })
    }

    /// As the node's `[lo, hi]` array.
    #[inline(always)]
    pub fn to_array(self) -> [[f32; 3]; 2] {
        [self.lo, self.hi]
    }

    /// Is the box empty (any `lo > hi`)?
    #[inline]
    pub fn is_empty(&self) -> bool {
        !(0..3).all(|a| self.lo[a] <= self.hi[a])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_is_outward() {
        for &x in &[
            0.1f64,
            -0.1,
            1.0 / 3.0,
            -1e-40,
            3.0e38,
            1e300,
            -1e300,
            0.0,
            1.5,
        ] {
            let (lo, hi) = (round_down(x), round_up(x));
            assert!(f64::from(lo) <= x && x <= f64::from(hi), "{x}: {lo} {hi}");
            assert!(hi == lo || hi == Real::next_up(lo), "{x}: {lo} {hi}");
        }
        assert_eq!(round_down(1.0), 1.0);
        assert_eq!(round_up(1.0), 1.0);
        assert_eq!(round_up(1e300), f32::INFINITY);
        assert_eq!(round_down(1e300), f32::MAX);
    }

    /// The rounding without branches agrees bit for bit with the definition (the `f32`
    /// nearest `x`, moved one `f32` outward when it lies on the wrong side), on the
    /// special values and on values spread over the whole `f64` range.
    #[test]
    fn rounding_matches_its_definition() {
        let reference = |x: f64| {
            let f = x as f32;
            let lo = if f64::from(f) > x { f.next_down() } else { f };
            let hi = if f64::from(f) < x { f.next_up() } else { f };
            (lo.to_bits(), hi.to_bits())
        };
        let mut values = vec![
            0.0,
            -0.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::from(f32::MAX),
            -f64::from(f32::MAX),
            f64::from(f32::MAX) * (1.0 + f64::EPSILON),
            f64::from(f32::from_bits(1)) / 3.0,
            -f64::from(f32::from_bits(1)) / 3.0,
            f64::from(f32::from_bits(1)),
            -f64::from(f32::from_bits(1)),
        ];
        // A fixed xorshift sequence of bit patterns covers signs, exponents and
        // mantissas; each is also tried one `f64` step to either side of an `f32`.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            values.push(x);
            let f = f64::from(x as f32);
            values.extend([f, f.next_up(), f.next_down()]);
        }
        for x in values {
            let got = (round_down(x).to_bits(), round_up(x).to_bits());
            assert_eq!(got, reference(x), "{x:e}");
        }
    }

    #[test]
    fn bounds_union_and_area() {
        let mut b = Bounds3::EMPTY;
        assert!(b.is_empty());
        assert_eq!(b.half_area(), 0.0);
        b.add_point([0.0, 0.0, 0.0]);
        b.union(&Bounds3 {
            lo: [1.0, 1.0, 1.0],
            hi: [1.0, 2.0, 3.0],
        });
        assert_eq!(b.lo, [0.0; 3]);
        assert_eq!(b.hi, [1.0, 2.0, 3.0]);
        assert_eq!(b.half_area(), 2.0 + 6.0 + 3.0);
        assert_eq!(b.centroid(), [0.5, 1.0, 1.5]);
    }
}
