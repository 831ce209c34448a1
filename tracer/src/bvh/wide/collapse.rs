//! The collapse of the binary tree into four- or eight-wide nodes (see [`super`] for
//! the rule).

use super::WideNode;
use crate::bvh::node::{Bounds3, Node};

/// Collapses a depth-first binary tree (root at 0) into `W`-wide nodes, depth-first,
/// root at 0. Returns the nodes and the depth in wide levels.
pub fn collapse<const W: usize>(bin: &[Node]) -> (Vec<WideNode<W>>, usize) {
    let mut out = crate::pages::vec_with_capacity(bin.len() / 2 + 1);
    if bin.is_empty() {
        return (out, 0);
    }
    let depth = emit(bin, 0, &mut out);
    (out, depth)
}

/// Emits the wide node of binary node `at` and, recursively, its interior children.
/// Returns the depth (levels) of the emitted subtree.
fn emit<const W: usize>(bin: &[Node], at: usize, out: &mut Vec<WideNode<W>>) -> usize {
    let mut slots = [0usize; W];
    let mut n;
    let node = &bin[at];
    if node.is_leaf() {
        slots[0] = at;
        n = 1;
    } else {
        // Start from the two children and open the interior child of largest surface
        // area (the first of equals) until the `W` slots are filled or only leaves are
        // left. Each slot's area is computed once, when the slot is filled.
        let area_of = |c: usize| {
            let b = &bin[c];
            (!b.is_leaf()).then(|| {
                // The far child of an interior slot, which opening the slot or emitting
                // its node reads next, is fetched now (the near child is the next node).
                vecexpr::simd::prefetch(bin.as_ptr().wrapping_add(b.offset as usize));
                Bounds3 {
                    lo: b.bounds[0],
                    hi: b.bounds[1],
                }
                .half_area()
            })
        };
        let mut areas = [None; W];
        slots[0] = at + 1;
        slots[1] = node.offset as usize;
        areas[0] = area_of(slots[0]);
        areas[1] = area_of(slots[1]);
        n = 2;
        while n < W {
            let mut open: Option<(usize, f32)> = None;
            for (i, a) in areas[..n].iter().enumerate() {
                if let Some(area) = *a {
                    if open.is_none_or(|(_, best)| area > best) {
                        open = Some((i, area));
                    }
                }
            }
            let Some((i, _)) = open else {
                break;
            };
            let c = slots[i];
            slots[i] = c + 1;
            slots[n] = bin[c].offset as usize;
            areas[i] = area_of(slots[i]);
            areas[n] = area_of(slots[n]);
            n += 1;
        }
    }
    // The node is written once, whole: an interior lane gets its child's index after
    // that child's subtree is emitted. (An empty node pushed first and the finished one
    // copied over it after the subtree wrote each node twice, the second time long
    // after its line had left the caches.)
    let mut wide = WideNode::EMPTY;
    for (lane, &c) in slots[..n].iter().enumerate() {
        let b = &bin[c];
        let (child, count) = if b.is_leaf() {
            (b.offset, b.count)
        } else {
            (0, 0)
        };
        wide.set(lane, &b.bounds, child, count);
    }
    let idx = out.len();
    out.push(wide);
    let mut depth = 1;
    for (lane, &c) in slots[..n].iter().enumerate() {
        if !bin[c].is_leaf() {
            let child = out.len() as u32;
            depth = depth.max(1 + emit(bin, c, out));
            out[idx].child[lane] = child;
        }
    }
    depth
}

#[cfg(test)]
mod tests {
    use super::super::EMPTY_SLOT;
    use crate::bvh::Bvh;

    #[test]
    fn collapse_keeps_every_leaf_once() {
        use crate::bvh::{Bounds3, BuildConfig, BuildPrim};
        let mut prims: Vec<BuildPrim> = (0..300)
            .map(|i| {
                let x = (i * 7919 % 300) as f32;
                BuildPrim::new(
                    Bounds3 {
                        lo: [x, (i % 17) as f32, 0.0],
                        hi: [x + 0.5, (i % 17) as f32 + 0.5, 1.0],
                    },
                    i,
                )
            })
            .collect();
        let cfg = BuildConfig {
            max_leaf_size: 4,
            parallel: false,
            traversal_cost: 2.0,
        };
        let bvh = Bvh::build_with_eight_wide(&mut prims, &cfg);
        check(bvh.wide_nodes(), prims.len());
        check(bvh.wide8_nodes(), prims.len());
        // Every four-wide level spans one or two binary levels.
        assert!(bvh.wide_depth() * 2 >= bvh.depth() - 1);
        assert!(bvh.wide_depth() <= bvh.depth());
        let (_, depth8) = super::collapse::<{ super::super::WIDTH8 }>(bvh.nodes());
        assert!(depth8 <= bvh.wide_depth() && depth8 * 3 >= bvh.depth() - 1);

        fn check<const W: usize>(nodes: &[super::WideNode<W>], prims: usize) {
            let mut seen = vec![0u32; prims];
            for n in nodes {
                for i in 0..W {
                    if n.count[i] > 0 {
                        for r in n.child[i]..n.child[i] + n.count[i] {
                            seen[r as usize] += 1;
                        }
                    }
                }
            }
            assert!(seen.iter().all(|&s| s == 1), "width {W}");
            // A node has fewer than `W` slots only when nothing is left to open: all
            // its children are leaves.
            for n in nodes {
                let used = n.child.iter().filter(|&&c| c != EMPTY_SLOT).count();
                if used < W {
                    assert!((0..used).all(|i| n.count[i] > 0), "{n:?}");
                }
            }
        }
    }
}
