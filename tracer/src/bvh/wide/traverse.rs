//! The single-ray walk of the wide trees, ordered for closest hits and early-exit for
//! any hits: one walk for both widths, over the four-wide tree with SSE box tests
//! ([`Bvh::traverse4`]) or the eight-wide tree with AVX ones ([`Bvh::traverse8`]).

#[cfg(target_arch = "x86_64")]
use super::box_test::Box8Ray;
use super::box_test::{Box4Ray, NodeTest};
use super::{WideNode, STACK_SIZE, STACK_SIZE8, WIDTH};
use crate::bvh::traverse::{LeafVisitor, TraversalRay};
use crate::bvh::Bvh;
use crate::float::Float;
use core::mem::MaybeUninit;

/// A pending subtree: child (node index or first reference), count (0 for an interior
/// node) and entry distance.
#[derive(Clone, Copy)]
struct Entry<T> {
    child: u32,
    count: u32,
    t: T,
}

/// Pushes slot `i` of `node`, with its entry distance from `tn`, onto the stack.
#[inline(always)]
fn push<T: Copy, const W: usize>(
    stack: &mut [MaybeUninit<Entry<T>>],
    sp: &mut usize,
    node: &WideNode<W>,
    tn: &[T; W],
    i: usize,
) {
    stack[*sp].write(Entry {
        child: node.child[i],
        count: node.count[i],
        t: tn[i],
    });
    *sp += 1;
}

/// Pushes every slot set in `bits`, in slot order.
#[inline(always)]
fn push_slots<T: Copy, const W: usize>(
    stack: &mut [MaybeUninit<Entry<T>>],
    sp: &mut usize,
    node: &WideNode<W>,
    tn: &[T; W],
    mut bits: u32,
) {
    while bits != 0 {
        let i = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        push(stack, sp, node, tn, i);
    }
}

impl Bvh {
    /// As [`Bvh::traverse`], over the four-wide tree: at each node the four child boxes
    /// are tested in one packet, the hit children are visited nearest first and the
    /// others pushed with their entry distances. With `ANY_HIT` the hit children are
    /// visited in slot order instead: the walk stops at the first hit anyway, and
    /// `t_max` never shrinks, so neither sorting nor the distance check on pop pays.
    ///
    /// `visit.leaf(leaf, t_max)` is called with [`super::Leaf::Refs`] for a leaf of
    /// references and with [`super::Leaf::Grouped`] for one rewritten by
    /// `Bvh::regroup_wide_leaves`.
    #[inline(always)]
    pub fn traverse4<T: Float, const ANY_HIT: bool>(
        &self,
        ray: &TraversalRay<T>,
        t_max: T,
        visit: &mut impl LeafVisitor<T>,
    ) -> bool {
        self.traverse4_from::<T, ANY_HIT>(0, ray, t_max, visit)
    }

    /// [`Bvh::traverse4`] over the subtree of wide node `start` only (0 is the root):
    /// the packet traversal hands its rays over to it one by one where few rays of a
    /// packet remain ([`Bvh::traverse4_packet`]).
    #[inline(always)]
    pub fn traverse4_from<T: Float, const ANY_HIT: bool>(
        &self,
        start: u32,
        ray: &TraversalRay<T>,
        t_max: T,
        visit: &mut impl LeafVisitor<T>,
    ) -> bool {
        let boxes = Box4Ray::new(ray);
        self.walk::<T, WIDTH, STACK_SIZE, ANY_HIT>(&self.wide, start, &boxes, ray, t_max, visit)
    }

    /// [`Bvh::traverse4`] over the eight-wide tree ([`Bvh::build_with_eight_wide`]), its
    /// eight boxes tested in one AVX register (`proof` that `T` is `f32`). Where three
    /// or more children are hit, the nearest is visited first and the others are
    /// pushed unsorted (see the walk). The closest hit is the same as the four-wide
    /// walk's: every box test gives the same answer, and the result does not depend on
    /// the order of the leaves.
    ///
    /// # Safety
    /// The CPU must have AVX2 and FMA ([`vecexpr::simd::Isa::Avx2`]), and the caller is
    /// compiled with them (`#[target_feature(enable = "avx2,fma")]`): the walk is
    /// inlined into it.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub unsafe fn traverse8<T: Float, const ANY_HIT: bool>(
        &self,
        proof: T::F32,
        ray: &TraversalRay<T>,
        t_max: T,
        visit: &mut impl LeafVisitor<T>,
    ) -> bool {
        debug_assert!(
            !self.wide8.is_empty() || self.wide.is_empty(),
            "the eight-wide tree was not built"
        );
        let boxes = Box8Ray::new(proof, ray);
        self.walk::<T, { super::WIDTH8 }, STACK_SIZE8, ANY_HIT>(
            &self.wide8,
            0,
            &boxes,
            ray,
            t_max,
            visit,
        )
    }

    /// The walk of [`Bvh::traverse4_from`] over the `W`-wide `nodes`, with the box
    /// test `boxes` (prepared from `ray`) and a stack of `STACK` entries (the bound of
    /// that width).
    #[inline(always)]
    fn walk<T: Float, const W: usize, const STACK: usize, const ANY_HIT: bool>(
        &self,
        nodes: &[WideNode<W>],
        start: u32,
        boxes: &impl NodeTest<T, W>,
        ray: &TraversalRay<T>,
        mut t_max: T,
        visit: &mut impl LeafVisitor<T>,
    ) -> bool {
        if nodes.is_empty() {
            return false;
        }
        // Left uninitialised: only the entries below `sp` are ever read, and zeroing
        // the whole array cost more than a typical query's box tests.
        let mut stack = [const { MaybeUninit::<Entry<T>>::uninit() }; STACK];
        let mut sp = 0usize;
        let mut found = false;
        let mut at = start as usize;
        'walk: loop {
            let node = &nodes[at];
            if W > WIDTH {
                // An eight-wide node's children and counts fill its fourth cache line,
                // which the box test does not read: fetched now, it arrives while the
                // boxes are tested instead of after. balls-s6, whose tree does not fit
                // in the caches: single eye rays 1.012 to 1.036 times as fast in five
                // alternations; the classic scenes unchanged (`tracer/JOURNAL.md`,
                // "The node's last cache line fetched early, and where the per-ray
                // instructions go").
                vecexpr::simd::prefetch(node.child.as_ptr());
            }
            let (mut bits, tn) = boxes.node_hits(node, t_max);
            let mut entry = None;
            if bits != 0 {
                let first = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                if bits == 0 {
                    // One child hit (the common case): no ordering.
                    entry = Some((node.child[first], node.count[first]));
                } else if ANY_HIT {
                    entry = Some((node.child[first], node.count[first]));
                    push_slots(&mut stack, &mut sp, node, &tn, bits);
                } else if bits & (bits - 1) == 0 {
                    // Two children hit: visit the nearer, push the farther.
                    let second = bits.trailing_zeros() as usize;
                    let (near, far) = if tn[second] < tn[first] {
                        (second, first)
                    } else {
                        (first, second)
                    };
                    push(&mut stack, &mut sp, node, &tn, far);
                    entry = Some((node.child[near], node.count[near]));
                } else if W > WIDTH {
                    // Eight-wide nodes: the nearest hit child is visited first and the
                    // others are pushed unsorted, in slot order. Sorting three to eight
                    // children by insertion, as below, cost more than the visits it
                    // saves: without it 2 to 4 % fewer instructions per single eye ray
                    // (teapot-s12 739 to 713, tetra-s6 531 to 517) and 5 to 10 % faster
                    // (`tracer/JOURNAL.md`, "An eight-wide tree for single rays"). The
                    // closest hit is the same: a popped entry is still culled by its
                    // exact entry distance, and the result does not depend on the order.
                    let all = bits | (1 << first);
                    let mut near = first;
                    let mut m = bits;
                    while m != 0 {
                        let i = m.trailing_zeros() as usize;
                        m &= m - 1;
                        near = if tn[i] < tn[near] { i } else { near };
                    }
                    push_slots(&mut stack, &mut sp, node, &tn, all & !(1 << near));
                    entry = Some((node.child[near], node.count[near]));
                } else {
                    // Hit children sorted by entry distance (insertion sort of 3 to
                    // `W`), pushed farthest first so that pops come nearest first.
                    let mut order = [first; W];
                    let mut k = 1;
                    while bits != 0 {
                        let i = bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        let mut j = k;
                        while j > 0 && tn[i] < tn[order[j - 1]] {
                            order[j] = order[j - 1];
                            j -= 1;
                        }
                        order[j] = i;
                        k += 1;
                    }
                    for &i in order[1..k].iter().rev() {
                        push(&mut stack, &mut sp, node, &tn, i);
                    }
                    let i = order[0];
                    entry = Some((node.child[i], node.count[i]));
                }
            }
            loop {
                match entry {
                    Some((child, 0)) => {
                        at = child as usize;
                        continue 'walk;
                    }
                    Some((first, count)) => {
                        let l = self.leaf(first, count);
                        if let Some(t) = visit.leaf(l, t_max) {
                            found = true;
                            if ANY_HIT {
                                return true;
                            }
                            t_max = t;
                        }
                    }
                    None => {}
                }
                // Pop the nearest pending entry that may still hold a closer hit.
                entry = None;
                while sp > 0 {
                    sp -= 1;
                    // SAFETY: every slot below `sp` was written by a push above, and
                    // `Entry` is `Copy`, so reading it out leaves the slot valid.
                    let e = unsafe { stack[sp].assume_init_read() };
                    if ANY_HIT || e.t <= t_max * ray.slack {
                        entry = Some((e.child, e.count));
                        break;
                    }
                }
                if entry.is_none() {
                    return found;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::bvh::traverse::{LeafVisitor, TraversalRay};
    use crate::bvh::wide::Leaf;
    use crate::bvh::{Bounds3, BuildConfig, BuildPrim, Bvh};
    use vecexpr::vec3;

    /// Records the primitives of each leaf in the order a walk reaches them, and reports
    /// no hit, so that `t_max` stays infinite and every leaf on the ray is reached.
    struct Order(Vec<u32>);

    impl LeafVisitor<f32> for Order {
        fn leaf(&mut self, leaf: Leaf<'_>, _t_max: f32) -> Option<f32> {
            let Leaf::Refs(refs) = leaf else {
                panic!("a tree without regrouped leaves");
            };
            self.0.extend_from_slice(refs);
            None
        }
    }

    /// The eight-wide walk, in code compiled for AVX2 as its contract asks.
    ///
    /// # Safety
    /// The CPU has AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn walk8(bvh: &Bvh, ray: &TraversalRay<f32>, visit: &mut Order) -> bool {
        // SAFETY: the caller's contract, and this function is compiled for AVX2 and FMA.
        unsafe { bvh.traverse8::<f32, false>(crate::float::IsF32, ray, f32::INFINITY, visit) }
    }

    /// The closest-hit walks of the binary and four-wide trees reach the leaves on a
    /// ray nearest first (which is what lets them stop early), whatever the ray's
    /// direction, and the eight-wide walk reaches the same leaves, the nearest first: a
    /// grid of 8 x 8 unit boxes, one per leaf, 2 apart, crossed along every row and
    /// column both ways. Only the boxes of the crossed row or column are reached, so at
    /// the wide nodes above them the ray hits two children as well as three to eight.
    #[test]
    fn closest_hit_walks_reach_leaves_nearest_first() {
        const N: u32 = 8;
        let id = |i: u32, j: u32| i * N + j;
        let mut prims: Vec<BuildPrim> = (0..N)
            .flat_map(|i| (0..N).map(move |j| (i, j)))
            .map(|(i, j)| {
                let (x, y) = (2.0 * i as f32, 2.0 * j as f32);
                let b = Bounds3 {
                    lo: [x, y, 0.0],
                    hi: [x + 1.0, y + 1.0, 1.0],
                };
                BuildPrim::new(b, id(i, j))
            })
            .collect();
        let cfg = BuildConfig {
            max_leaf_size: 1,
            parallel: false,
            traversal_cost: crate::bvh::build::TRAVERSAL_COST,
        };
        let bvh = Bvh::build_with_eight_wide(&mut prims, &cfg);
        #[cfg(target_arch = "x86_64")]
        let avx2 = vecexpr::simd::Isa::Avx2.is_available();
        let far = 2.0 * N as f32 + 4.0;
        for k in 0..N {
            let c = 2.0 * k as f32 + 0.5;
            // (origin, direction, the ids in order of distance)
            let along_x: Vec<u32> = (0..N).map(|i| id(i, k)).collect();
            let along_y: Vec<u32> = (0..N).map(|j| id(k, j)).collect();
            let rev = |v: &[u32]| v.iter().rev().copied().collect::<Vec<u32>>();
            let cases = [
                (
                    vec3(-3.0f32, c, 0.5),
                    vec3(1.0f32, 0.0, 0.0),
                    along_x.clone(),
                ),
                (vec3(far, c, 0.5), vec3(-1.0, 0.0, 0.0), rev(&along_x)),
                (vec3(c, -3.0, 0.5), vec3(0.0, 1.0, 0.0), along_y.clone()),
                (vec3(c, far, 0.5), vec3(0.0, -1.0, 0.0), rev(&along_y)),
            ];
            for (o, d, want) in cases {
                let ray = TraversalRay::new(&o, &d, 0.0);
                let mut wide = Order(Vec::new());
                assert!(!bvh.traverse4::<f32, false>(&ray, f32::INFINITY, &mut wide));
                assert_eq!(wide.0, want, "four-wide tree, ray from {o:?} along {d:?}");
                let mut binary = Order(Vec::new());
                assert!(!bvh.traverse::<f32, false>(&ray, f32::INFINITY, &mut binary));
                assert_eq!(binary.0, want, "binary tree, ray from {o:?} along {d:?}");
                #[cfg(target_arch = "x86_64")]
                if avx2 {
                    // The eight-wide walk visits the nearest child of a node first but
                    // pushes the others unsorted: it reaches every leaf on the ray once,
                    // the nearest first.
                    let mut eight = Order(Vec::new());
                    // SAFETY: the CPU has AVX2 and FMA (checked above).
                    assert!(!unsafe { walk8(&bvh, &ray, &mut eight) });
                    assert_eq!(eight.0.first(), want.first(), "eight-wide, from {o:?}");
                    let mut reached = eight.0.clone();
                    reached.sort_unstable();
                    let mut all = want.clone();
                    all.sort_unstable();
                    assert_eq!(reached, all, "eight-wide tree, ray from {o:?} along {d:?}");
                }
            }
        }
    }
}
