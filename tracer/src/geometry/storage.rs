//! Primitive storage: one array per type, hot kernel data apart from cold hit data, and
//! the typed `u32` references the BVH stores (the reasons are in the `geometry` module
//! docs).

use super::cone::Cone;
use super::plane::Plane;
use super::sphere::Sphere;
use super::triangle::{Tri4, Triangle, TRI4_LANES};
use crate::bvh::{Bounds3, BuildPrim, Bvh};
use vecexpr::{Real, Vec3};

/// Fewest items for which [`Prims::build_prims`] and [`Prims::reorder`] split their work
/// over the rayon pool.
const PARALLEL_PRIMS: usize = 1 << 14;

/// Bits of a reference that hold the type tag.
pub(crate) const TAG_SHIFT: u32 = 30;
/// Mask of the index part of a reference.
pub(crate) const INDEX_MASK: u32 = (1 << TAG_SHIFT) - 1;
/// Largest number of primitives of one type.
pub(crate) const MAX_PER_TYPE: usize = INDEX_MASK as usize;
pub(crate) const SPHERE: u32 = 0;
pub(crate) const TRIANGLE: u32 = 1;
pub(crate) const CONE: u32 = 2;
pub(crate) const PLANE: u32 = 3;
/// "No shading normals" in [`TriangleInfo::shading`].
pub(crate) const NO_SHADING: u32 = u32::MAX;

/// A typed reference.
#[inline(always)]
pub(crate) fn make_ref(tag: u32, index: usize) -> u32 {
    debug_assert!(index <= MAX_PER_TYPE);
    (tag << TAG_SHIFT) | index as u32
}

/// Cold data of a sphere, cone or plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PrimInfo {
    pub prim_id: u32,
    pub material: u32,
    /// Normals point inward (NFF negative radius).
    pub inside_visible: bool,
}

/// Cold data of a triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TriangleInfo<T: Real> {
    pub prim_id: u32,
    pub material: u32,
    /// Index of the triangle within its polygon, to order ties between them.
    pub sub: u32,
    /// Index into [`Prims::shading`], or [`NO_SHADING`].
    pub shading: u32,
    /// Unit geometric normal (the polygon's, for triangles cut from a polygon).
    pub normal: Vec3<T>,
}

/// All primitives of a scene.
#[derive(Clone, Debug)]
pub(crate) struct Prims<T: Real> {
    pub spheres: Vec<Sphere<T>>,
    pub sphere_info: Vec<PrimInfo>,
    pub triangles: Vec<Triangle<T>>,
    pub triangle_info: Vec<TriangleInfo<T>>,
    /// Unit (or zero) vertex normals of smooth-shaded triangles.
    pub shading: Vec<[Vec3<T>; 3]>,
    pub cones: Vec<Cone<T>>,
    pub cone_info: Vec<PrimInfo>,
    pub planes: Vec<Plane<T>>,
    pub plane_info: Vec<PrimInfo>,
    /// The triangles of every all-triangle leaf of the four-wide tree, in groups of
    /// four per leaf (see [`Prims::group_leaves`]).
    pub tri4: Vec<Tri4<T>>,
}

impl<T: Real> Default for Prims<T> {
    fn default() -> Self {
        Self {
            spheres: Vec::new(),
            sphere_info: Vec::new(),
            triangles: Vec::new(),
            triangle_info: Vec::new(),
            shading: Vec::new(),
            cones: Vec::new(),
            cone_info: Vec::new(),
            planes: Vec::new(),
            plane_info: Vec::new(),
            tri4: Vec::new(),
        }
    }
}

/// Pads an `f64` box by a few ulps of `T` relative to its magnitude and size, so that
/// rounding in the intersection kernels cannot report a hit outside the box, then rounds
/// it outward to `f32`.
fn padded<T: Real>(lo: [f64; 3], hi: [f64; 3]) -> Bounds3 {
    // The largest of the corners' magnitudes and the extents. A NaN never compares
    // greater, so it is skipped as `f64::max` skips it, but without the NaN tests that
    // `f64::max` compiles to: 18 fewer instructions a sphere (callgrind, balls-s6), and
    // the same boxes bit for bit (`padded_boxes_take_the_largest_magnitude_as_f64_max_does`).
    let mut mag = 0.0f64;
    for a in 0..3 {
        for v in [lo[a].abs(), hi[a].abs(), hi[a] - lo[a]] {
            if v > mag {
                mag = v;
            }
        }
    }
    let pad = 4.0 * T::EPSILON.to_f64() * mag;
    Bounds3::from_f64(lo.map(|x| x - pad), hi.map(|x| x + pad))
}

impl<T: Real> Prims<T> {
    /// Number of primitives in the BVH (planes excluded).
    pub fn bvh_len(&self) -> usize {
        self.spheres.len() + self.triangles.len() + self.cones.len()
    }

    /// Bytes of all primitive arrays.
    pub fn bytes(&self) -> usize {
        use core::mem::size_of_val;
        size_of_val(self.spheres.as_slice())
            + size_of_val(self.sphere_info.as_slice())
            + size_of_val(self.triangles.as_slice())
            + size_of_val(self.triangle_info.as_slice())
            + size_of_val(self.shading.as_slice())
            + size_of_val(self.cones.as_slice())
            + size_of_val(self.cone_info.as_slice())
            + size_of_val(self.planes.as_slice())
            + size_of_val(self.plane_info.as_slice())
            + size_of_val(self.tri4.as_slice())
    }

    /// `(prim_id, sub)` of a reference: ties in `t` go to the smaller key, i.e. to the
    /// primitive given first, whatever order the BVH visits them in.
    #[inline]
    pub fn key(&self, r: u32) -> (u32, u32) {
        let i = (r & INDEX_MASK) as usize;
        match r >> TAG_SHIFT {
            SPHERE => (self.sphere_info[i].prim_id, 0),
            TRIANGLE => (self.triangle_info[i].prim_id, self.triangle_info[i].sub),
            CONE => (self.cone_info[i].prim_id, 0),
            _ => (self.plane_info[i].prim_id, 0),
        }
    }

    /// The `k`-th BVH primitive's reference: spheres, then triangles, then cones.
    fn ref_at(&self, k: usize) -> u32 {
        let (ns, nt) = (self.spheres.len(), self.triangles.len());
        if k < ns {
            make_ref(SPHERE, k)
        } else if k < ns + nt {
            make_ref(TRIANGLE, k - ns)
        } else {
            make_ref(CONE, k - ns - nt)
        }
    }

    /// Conservative `f32` bounds of a referenced primitive.
    fn bounds_of(&self, r: u32) -> Bounds3 {
        let i = (r & INDEX_MASK) as usize;
        match r >> TAG_SHIFT {
            SPHERE => {
                let s = &self.spheres[i];
                let r = s.radius.to_f64();
                let c: [f64; 3] = core::array::from_fn(|a| s.center[a].to_f64());
                padded::<T>(c.map(|x| x - r), c.map(|x| x + r))
            }
            TRIANGLE => {
                let mut lo = [f64::INFINITY; 3];
                let mut hi = [f64::NEG_INFINITY; 3];
                for v in &self.triangles[i].v {
                    for a in 0..3 {
                        lo[a] = lo[a].min(v[a].to_f64());
                        hi[a] = hi[a].max(v[a].to_f64());
                    }
                }
                padded::<T>(lo, hi)
            }
            _ => {
                let (lo, hi) = self.cones[i].bounds_f64();
                padded::<T>(lo, hi)
            }
        }
    }

    /// Conservative `f32` boxes of every BVH primitive, with their typed references, in
    /// parallel for large scenes (the order is the same either way).
    pub fn build_prims(&self, parallel: bool) -> Vec<BuildPrim> {
        collect(self.bvh_len(), parallel, |k| {
            let r = self.ref_at(k);
            BuildPrim::new(self.bounds_of(r), r)
        })
    }

    /// Reorders the primitive arrays into the leaf order of a BVH's references `refs`
    /// and points the references at the new positions: one pass over the references
    /// lists, per kind, the old indices in leaf order, then each array is gathered (in
    /// parallel for large scenes when `parallel`). Meant as the side task of
    /// [`Bvh::build_beside`].
    pub fn reorder(&mut self, refs: &mut [u32], parallel: bool) {
        use crate::pages::vec_with_capacity;
        let mut spheres = vec_with_capacity(self.spheres.len());
        let mut triangles = vec_with_capacity(self.triangles.len());
        let mut cones = vec_with_capacity(self.cones.len());
        for r in refs.iter_mut() {
            let i = *r & INDEX_MASK;
            let (kind, order) = match *r >> TAG_SHIFT {
                SPHERE => (SPHERE, &mut spheres),
                TRIANGLE => (TRIANGLE, &mut triangles),
                _ => (CONE, &mut cones),
            };
            order.push(i);
            *r = make_ref(kind, order.len() - 1);
        }
        debug_assert_eq!(spheres.len(), self.spheres.len());
        debug_assert_eq!(triangles.len(), self.triangles.len());
        debug_assert_eq!(cones.len(), self.cones.len());
        self.spheres = gather(&self.spheres, &spheres, parallel);
        self.sphere_info = gather(&self.sphere_info, &spheres, parallel);
        self.triangles = gather(&self.triangles, &triangles, parallel);
        self.triangle_info = gather(&self.triangle_info, &triangles, parallel);
        self.cones = gather(&self.cones, &cones, parallel);
        self.cone_info = gather(&self.cone_info, &cones, parallel);
    }

    /// Copies the triangles of every four-wide leaf that holds only triangles into
    /// [`Prims::tri4`], `ceil(n / 4)` consecutive groups per leaf in leaf order, and
    /// points the leaf at its first group ([`Bvh::regroup_wide_leaves`]). Such a leaf
    /// is then read as a few contiguous 160-byte groups (in `f32`) instead of its
    /// references plus one triangle each, and tested four triangles at a time. Call
    /// after [`Prims::reorder`]; the `triangles` array and the references stay, for
    /// the binary tree, packets, hit records and the shadow cache.
    pub fn group_leaves(&mut self, bvh: &mut Bvh) {
        if self.triangles.is_empty() {
            // No leaf to group; skips a pass over both wide trees.
            self.tri4 = Vec::new();
            return;
        }
        let mut groups = Vec::new();
        let mut lanes: Vec<(u32, Triangle<T>)> = Vec::with_capacity(TRI4_LANES);
        bvh.regroup_wide_leaves(|refs| {
            if !refs.iter().all(|&r| r >> TAG_SHIFT == TRIANGLE) {
                return None;
            }
            let first = u32::try_from(groups.len()).ok()?;
            for chunk in refs.chunks(TRI4_LANES) {
                lanes.clear();
                lanes.extend(chunk.iter().map(|&r| {
                    let i = r & INDEX_MASK;
                    (i, self.triangles[i as usize])
                }));
                groups.push(Tri4::new(&lanes));
            }
            Some(first)
        });
        self.tri4 = groups;
    }
}

/// `src[order[k]]` for every `k`, in parallel for long arrays when `parallel`.
fn gather<X: Copy + Send + Sync>(src: &[X], order: &[u32], parallel: bool) -> Vec<X> {
    collect(order.len(), parallel, |k| src[order[k] as usize])
}

/// `[f(0), .., f(n - 1)]` in a vector on huge pages ([`crate::pages`]), made over the
/// rayon pool from [`PARALLEL_PRIMS`] items up when `parallel` (the same items either
/// way).
fn collect<X: Send>(n: usize, parallel: bool, f: impl Fn(usize) -> X + Sync + Send) -> Vec<X> {
    let mut out = crate::pages::vec_with_capacity(n);
    if parallel && n >= PARALLEL_PRIMS {
        use rayon::prelude::*;
        (0..n).into_par_iter().map(f).collect_into_vec(&mut out);
    } else {
        out.extend((0..n).map(f));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn padded_boxes_take_the_largest_magnitude_as_f64_max_does() {
        // The padding as first written, with `f64::max`.
        let reference = |lo: [f64; 3], hi: [f64; 3]| {
            let mag = (0..3).fold(0.0f64, |m, a| {
                m.max(lo[a].abs()).max(hi[a].abs()).max(hi[a] - lo[a])
            });
            let pad = 4.0 * f64::from(f32::EPSILON) * mag;
            Bounds3::from_f64(lo.map(|x| x - pad), hi.map(|x| x + pad))
        };
        let values = [
            0.0,
            -0.0,
            1.0,
            -3.5,
            123.456,
            1e30,
            -1e-30,
            2.0 * f64::from(f32::MAX),
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut pick = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            values[(s % values.len() as u64) as usize]
        };
        let bits = |b: Bounds3| (b.lo.map(f32::to_bits), b.hi.map(f32::to_bits));
        for _ in 0..20_000 {
            let lo = [pick(), pick(), pick()];
            let hi = [pick(), pick(), pick()];
            assert_eq!(
                bits(padded::<f32>(lo, hi)),
                bits(reference(lo, hi)),
                "{lo:?} {hi:?}"
            );
        }
    }

    #[test]
    fn hot_data_sizes() {
        assert_eq!(core::mem::size_of::<Sphere<f32>>(), 16);
        assert_eq!(core::mem::size_of::<Triangle<f32>>(), 36);
        assert_eq!(core::mem::size_of::<Cone<f32>>(), 36);
        assert_eq!(core::mem::size_of::<Sphere<f64>>(), 32);
        assert_eq!(core::mem::size_of::<PrimInfo>(), 12);
    }

    #[test]
    fn parallel_reorder_equals_serial_reorder() {
        use crate::geometry::{AccelOptions, Geometry};
        use crate::scene::desc::{Shape, ShapeDesc};
        // Spheres, triangles and cones interleaved, more of them than the parallel
        // threshold, so that the gathers run in parallel chunks.
        let shapes: Vec<ShapeDesc> = (0..PARALLEL_PRIMS + 1000)
            .map(|i| {
                let x = (i * 7919 % 1000) as f64;
                let y = (i / 1000) as f64;
                let shape = match i % 3 {
                    0 => Shape::Sphere {
                        center: [x, y, 0.0],
                        radius: 0.3,
                        inside_visible: false,
                    },
                    1 => Shape::Polygon {
                        vertices: vec![[x, y, 1.0], [x + 0.5, y, 1.0], [x, y + 0.5, 1.0]],
                    },
                    _ => Shape::Cone {
                        base: [x, y, 2.0],
                        base_radius: 0.2,
                        apex: [x, y, 2.5],
                        apex_radius: 0.1,
                        inside_visible: false,
                    },
                };
                ShapeDesc {
                    shape,
                    material: 0,
                    line: i as u32 + 1,
                }
            })
            .collect();
        let build = |parallel_build| {
            Geometry::<f32>::build(
                &shapes,
                &AccelOptions {
                    parallel_build,
                    ..AccelOptions::default()
                },
            )
        };
        let (p, s) = (build(true), build(false));
        assert_eq!(p.prims.spheres, s.prims.spheres);
        assert_eq!(p.prims.sphere_info, s.prims.sphere_info);
        assert_eq!(p.prims.triangles, s.prims.triangles);
        assert_eq!(p.prims.triangle_info, s.prims.triangle_info);
        assert_eq!(p.prims.cones, s.prims.cones);
        assert_eq!(p.prims.cone_info, s.prims.cone_info);
        let (pb, sb) = (p.bvh().unwrap(), s.bvh().unwrap());
        assert_eq!(pb.refs(), sb.refs());
        // Every reference leads to the primitive it was built from: leaf order lists
        // each shape once, and the kinds keep their shapes.
        let mut seen = vec![false; shapes.len()];
        for &r in pb.refs() {
            let (id, _) = p.prims.key(r);
            let kind = r >> TAG_SHIFT;
            assert_eq!(kind, [SPHERE, TRIANGLE, CONE][id as usize % 3]);
            assert!(!std::mem::replace(&mut seen[id as usize], true));
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn references() {
        let r = make_ref(CONE, 12345);
        assert_eq!((r >> TAG_SHIFT, r & INDEX_MASK), (CONE, 12345));
        assert_ne!(make_ref(PLANE, MAX_PER_TYPE - 1), u32::MAX);
    }
}
