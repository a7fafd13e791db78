//! A bounding-volume hierarchy: a binary tree of axis-aligned boxes over numbered items, for
//! nearest-item and within-radius queries by branch and bound.
//!
//! Construction is the classic top-down median split (Kay & Kajiya, *Ray tracing complex
//! scenes*, SIGGRAPH 1986; the object-median variant of Wald, *On fast construction of SAH-based
//! bounding volume hierarchies*, 2007, without the surface-area heuristic): the items' box
//! centres are split at the median along the longest axis of their spread until at most
//! [`LEAF_SIZE`] items remain. The tree is balanced, so its depth is `⌈log₂(n / LEAF_SIZE)⌉ + 1`
//! and queries use a fixed-size stack (no allocation).
//!
//! Queries are branch and bound (the nearest-neighbour search of Roussopoulos, Kelley &
//! Vincent, *Nearest neighbor queries*, SIGMOD 1995, depth first): a node is entered only when
//! the distance from the query point to its box is below the current bound, children are
//! entered nearer box first, and the caller's visitor tightens the bound as it finds items.

use super::bbox::Aabb;
use glam::DVec3;

/// Most items in a leaf. Items here are faces, whose exact distance costs microseconds, so
/// leaves hold one or two to make the boxes as tight as possible.
pub const LEAF_SIZE: usize = 2;

/// Capacity of the traversal stack. A balanced tree over `n` items has depth
/// `⌈log₂ n⌉ + 1`, and depth-first traversal keeps at most one pending sibling per level;
/// 64 levels is far beyond any model.
const STACK: usize = 64;

#[derive(Clone, Debug)]
struct Node {
    bbox: Aabb,
    /// Leaf: first index into `items`; inner node: index of the left child (right = left + 1).
    first: u32,
    /// Leaf: number of items (≥ 1); inner node: 0.
    count: u32,
}

/// A binary AABB tree over items `0..n` (see the module docs).
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    items: Vec<u32>,
    /// Each item's own box (a leaf's box is the union of its items').
    boxes: Vec<Aabb>,
}

/// Squared distance from `p` to the box (0 inside).
#[inline]
pub fn box_distance_squared(b: &Aabb, p: DVec3) -> f64 {
    let d = (b.min - p).max(p - b.max).max(DVec3::ZERO);
    d.length_squared()
}

/// The smallest box containing both.
#[inline]
pub fn union(a: &Aabb, b: &Aabb) -> Aabb {
    Aabb {
        min: a.min.min(b.min),
        max: a.max.max(b.max),
    }
}

impl Bvh {
    /// Builds the tree over `boxes` (item `i` has box `boxes[i]`). Empty boxes are kept
    /// but never visited.
    pub fn new(boxes: &[Aabb]) -> Bvh {
        let mut items: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * boxes.len().max(1));
        nodes.push(Node {
            bbox: Aabb::EMPTY,
            first: 0,
            count: 0,
        });
        if !boxes.is_empty() {
            build(&mut nodes, 0, &mut items, 0, boxes);
        }
        Bvh {
            nodes,
            items,
            boxes: boxes.to_vec(),
        }
    }

    /// Number of items.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// True when there are no items.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Depth of the tree (1 for a single leaf, 0 when empty).
    pub fn depth(&self) -> usize {
        fn go(nodes: &[Node], i: usize) -> usize {
            let n = &nodes[i];
            if n.count > 0 {
                1
            } else {
                1 + go(nodes, n.first as usize).max(go(nodes, n.first as usize + 1))
            }
        }
        if self.is_empty() {
            0
        } else {
            go(&self.nodes, 0)
        }
    }

    /// Branch and bound: calls `visit(item, box_distance²)` for every item whose box is closer
    /// to `p` than the current bound (`bound²` initially), nearer boxes first as far as the
    /// depth-first order allows. `visit` returns the new squared bound (the best squared
    /// distance found so far, or the unchanged radius² for a fixed-radius query); bounds only
    /// shrink. Returns the final squared bound.
    pub fn branch_and_bound(
        &self,
        p: DVec3,
        bound_squared: f64,
        mut visit: impl FnMut(usize, f64) -> f64,
    ) -> f64 {
        let mut bound = bound_squared;
        if self.items.is_empty() {
            return bound;
        }
        let mut stack = [(0u32, 0.0f64); STACK];
        let mut top = 0usize;
        let root = box_distance_squared(&self.nodes[0].bbox, p);
        if root < bound {
            stack[0] = (0, root);
            top = 1;
        }
        while top > 0 {
            top -= 1;
            let (i, lb) = stack[top];
            if lb >= bound {
                continue;
            }
            let node = &self.nodes[i as usize];
            if node.count > 0 {
                for k in node.first..node.first + node.count {
                    let item = self.items[k as usize] as usize;
                    let d = if node.count == 1 {
                        lb
                    } else {
                        box_distance_squared(&self.boxes[item], p)
                    };
                    if d < bound {
                        bound = visit(item, d).min(bound);
                    }
                }
                continue;
            }
            let (l, r) = (node.first, node.first + 1);
            let dl = box_distance_squared(&self.nodes[l as usize].bbox, p);
            let dr = box_distance_squared(&self.nodes[r as usize].bbox, p);
            // Push the farther child first so that the nearer one is popped first.
            let (near, dn, far, df) = if dl <= dr {
                (l, dl, r, dr)
            } else {
                (r, dr, l, dl)
            };
            if df < bound && top < STACK {
                stack[top] = (far, df);
                top += 1;
            }
            if dn < bound && top < STACK {
                stack[top] = (near, dn);
                top += 1;
            }
        }
        bound
    }
}

/// Fills node `at` with `items` (which start at `first` in the item order), splitting at the
/// median recursively.
fn build(nodes: &mut Vec<Node>, at: usize, items: &mut [u32], first: usize, boxes: &[Aabb]) {
    let mut bbox = Aabb::EMPTY;
    let mut centres = Aabb::EMPTY;
    for &i in items.iter() {
        let b = &boxes[i as usize];
        if !b.is_empty() {
            bbox = union(&bbox, b);
            centres.add((b.min + b.max) * 0.5);
        }
    }
    if items.len() <= LEAF_SIZE {
        nodes[at] = Node {
            bbox,
            first: first as u32,
            count: items.len() as u32,
        };
        return;
    }
    let spread = if centres.is_empty() {
        DVec3::ZERO
    } else {
        centres.max - centres.min
    };
    let axis = if spread.x >= spread.y && spread.x >= spread.z {
        0
    } else if spread.y >= spread.z {
        1
    } else {
        2
    };
    let key = |i: &u32| {
        let b = &boxes[*i as usize];
        if b.is_empty() {
            f64::INFINITY
        } else {
            ((b.min + b.max) * 0.5)[axis]
        }
    };
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| key(a).total_cmp(&key(b)));
    let left = nodes.len();
    let placeholder = Node {
        bbox: Aabb::EMPTY,
        first: 0,
        count: 0,
    };
    nodes.push(placeholder.clone());
    nodes.push(placeholder);
    nodes[at] = Node {
        bbox,
        first: left as u32,
        count: 0,
    };
    let (a, b) = items.split_at_mut(mid);
    build(nodes, left, a, first, boxes);
    build(nodes, left + 1, b, first + mid, boxes);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn boxes(n: usize, seed: u64) -> Vec<Aabb> {
        let mut s = seed;
        let mut rnd = move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| {
                let c = DVec3::new(rnd(), rnd(), rnd()) * 100.0;
                let h = DVec3::new(rnd(), rnd(), rnd()) * 5.0;
                Aabb {
                    min: c - h,
                    max: c + h,
                }
            })
            .collect()
    }

    /// An unbounded box (a face nothing bounds) is visited by every query and does not
    /// hide the others.
    #[test]
    fn unbounded_box_is_always_visited() {
        let mut bs = boxes(50, 3);
        bs.push(Aabb::UNBOUNDED);
        let bvh = Bvh::new(&bs);
        for k in 0..20 {
            let p = DVec3::new(k as f64 * 13.0 - 50.0, 20.0, k as f64 * 3.0);
            let mut seen = false;
            let best = bvh.branch_and_bound(p, f64::INFINITY, |i, lb| {
                if i == 50 {
                    seen = true;
                    assert_eq!(lb, 0.0);
                    return f64::INFINITY;
                }
                box_distance_squared(&bs[i], p)
            });
            let brute = bs[..50]
                .iter()
                .map(|b| box_distance_squared(b, p))
                .fold(f64::INFINITY, f64::min);
            assert!(seen);
            assert_eq!(best, brute);
        }
    }

    #[test]
    fn nearest_box_matches_brute_force() {
        for n in [0, 1, 2, 3, 7, 100, 1000] {
            let bs = boxes(n, n as u64 + 1);
            let bvh = Bvh::new(&bs);
            assert_eq!(bvh.len(), n);
            if n > 0 {
                // Balanced: ⌈log₂(n / LEAF_SIZE)⌉ + 1 levels.
                let expect = (n as f64 / LEAF_SIZE as f64).log2().ceil().max(0.0) as usize + 1;
                assert!(bvh.depth() <= expect, "depth {} > {expect}", bvh.depth());
            }
            for k in 0..50 {
                let p = DVec3::new(
                    k as f64 * 2.9 - 20.0,
                    (k * 7 % 13) as f64 * 9.0,
                    50.0 - k as f64,
                );
                let brute = bs
                    .iter()
                    .map(|b| box_distance_squared(b, p))
                    .fold(f64::INFINITY, f64::min);
                let mut visited = 0;
                let best = bvh.branch_and_bound(p, f64::INFINITY, |i, lb| {
                    visited += 1;
                    assert_eq!(lb, box_distance_squared(&bs[i], p));
                    box_distance_squared(&bs[i], p)
                });
                assert_eq!(best, brute);
                assert!(n < 100 || visited < n / 4, "visited {visited} of {n}");
                // Fixed radius: every item within r is visited.
                let r2 = 15.0f64 * 15.0;
                let mut within = vec![];
                bvh.branch_and_bound(p, r2, |i, _| {
                    within.push(i);
                    r2
                });
                within.sort();
                let expect: Vec<usize> = (0..n)
                    .filter(|&i| box_distance_squared(&bs[i], p) < r2)
                    .collect();
                let mut got: Vec<usize> = within
                    .into_iter()
                    .filter(|&i| box_distance_squared(&bs[i], p) < r2)
                    .collect();
                got.dedup();
                assert_eq!(got, expect);
            }
        }
    }
}
