//! Broad phase for self-intersection counting and layer orders: a bounding volume hierarchy
//! over axis-aligned boxes, built by median split on the longest axis of the
//! box centres, stored as a flat node array, and traversed against itself to
//! list every pair of overlapping boxes exactly once.

use crate::math::Aabb;

/// Most boxes in a leaf.
const LEAF_SIZE: usize = 4;

/// A node: a leaf holds `count > 0` items from `first` in the item arrays;
/// an inner node (`count == 0`) has its children at `first` and `first + 1`.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    first: u32,
    count: u32,
}

impl Node {
    fn is_leaf(&self) -> bool {
        self.count > 0
    }

    fn items(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.count) as usize
    }

    fn children(&self) -> [u32; 2] {
        [self.first, self.first + 1]
    }
}

/// The hierarchy over a set of boxes, each tagged with a caller's id.
pub(in crate::metrics) struct TriBvh {
    nodes: Vec<Node>,
    /// Item boxes and ids, in leaf order.
    boxes: Vec<Aabb>,
    ids: Vec<u32>,
}

impl TriBvh {
    /// Builds the hierarchy over `(id, box)` items. Boxes must not hold NaN.
    pub(in crate::metrics) fn build(items: Vec<(u32, Aabb)>) -> Self {
        let mut items = items;
        let mut bvh = Self {
            nodes: Vec::with_capacity(2 * items.len() / LEAF_SIZE + 1),
            boxes: Vec::new(),
            ids: Vec::new(),
        };
        if !items.is_empty() {
            bvh.nodes.push(Node {
                bounds: Aabb::EMPTY,
                first: 0,
                count: 0,
            });
            bvh.split(0, &mut items, 0);
        }
        bvh.boxes = items.iter().map(|&(_, b)| b).collect();
        bvh.ids = items.iter().map(|&(id, _)| id).collect();
        bvh
    }

    /// Fills node `index` with `items`, which start at `offset` in leaf order,
    /// and returns its bounds (inner bounds are unions of the children's).
    /// Median splits halve the items, so the recursion is about log2(n) deep.
    fn split(&mut self, index: usize, items: &mut [(u32, Aabb)], offset: usize) -> Aabb {
        if items.len() <= LEAF_SIZE {
            let bounds = items
                .iter()
                .fold(Aabb::EMPTY, |b, &(_, item)| b.union(item));
            self.nodes[index] = Node {
                bounds,
                first: offset as u32,
                count: items.len() as u32,
            };
            return bounds;
        }
        let axis = longest_axis(items);
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |a, b| {
            let (ca, cb) = (a.1.min[axis] + a.1.max[axis], b.1.min[axis] + b.1.max[axis]);
            ca.total_cmp(&cb)
        });
        let first = self.nodes.len();
        self.nodes.extend([self.nodes[index]; 2]);
        let (left, right) = items.split_at_mut(mid);
        let bounds =
            self.split(first, left, offset)
                .union(self.split(first + 1, right, offset + mid));
        self.nodes[index] = Node {
            bounds,
            first: first as u32,
            count: 0,
        };
        bounds
    }

    /// Calls `f(id_a, id_b)` once for every unordered pair of distinct items
    /// whose boxes overlap.
    pub(in crate::metrics) fn for_each_overlapping_pair(&self, mut f: impl FnMut(u32, u32)) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![(0u32, 0u32)];
        while let Some((a, b)) = stack.pop() {
            let (na, nb) = (&self.nodes[a as usize], &self.nodes[b as usize]);
            if a == b {
                self.self_pairs(na, &mut stack, &mut f);
            } else if na.bounds.overlaps(&nb.bounds) {
                self.cross_pairs(a, b, &mut stack, &mut f);
            }
        }
    }

    /// Pairs inside one node: within a leaf, or within and across its children.
    fn self_pairs(&self, node: &Node, stack: &mut Vec<(u32, u32)>, f: &mut impl FnMut(u32, u32)) {
        if node.is_leaf() {
            let items = node.items();
            for i in items.clone() {
                for j in i + 1..items.end {
                    self.test_items(i, j, f);
                }
            }
        } else {
            let [l, r] = node.children();
            stack.extend([(l, l), (r, r), (l, r)]);
        }
    }

    /// Pairs across two different, overlapping nodes.
    fn cross_pairs(
        &self,
        a: u32,
        b: u32,
        stack: &mut Vec<(u32, u32)>,
        f: &mut impl FnMut(u32, u32),
    ) {
        let (na, nb) = (&self.nodes[a as usize], &self.nodes[b as usize]);
        match (na.is_leaf(), nb.is_leaf()) {
            (true, true) => {
                for i in na.items() {
                    for j in nb.items() {
                        self.test_items(i, j, f);
                    }
                }
            }
            // Descend into the inner node, or the larger one if both are.
            (true, false) => stack.extend(nb.children().map(|c| (a, c))),
            (false, true) => stack.extend(na.children().map(|c| (c, b))),
            (false, false) if side_sum(&na.bounds) >= side_sum(&nb.bounds) => {
                stack.extend(na.children().map(|c| (c, b)))
            }
            (false, false) => stack.extend(nb.children().map(|c| (a, c))),
        }
    }

    fn test_items(&self, i: usize, j: usize, f: &mut impl FnMut(u32, u32)) {
        if self.boxes[i].overlaps(&self.boxes[j]) {
            f(self.ids[i], self.ids[j]);
        }
    }
}

fn longest_axis(items: &[(u32, Aabb)]) -> usize {
    let centres = items.iter().fold(Aabb::EMPTY, |b, &(_, item)| {
        let c = item.centre();
        b.union(Aabb { min: c, max: c })
    });
    (centres.max - centres.min).max_position()
}

fn side_sum(b: &Aabb) -> f32 {
    (b.max - b.min).element_sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn unit_box_at(x: f32, y: f32, z: f32) -> Aabb {
        Aabb::of_points([Vec3::new(x, y, z), Vec3::new(x + 1.0, y + 1.0, z + 1.0)])
    }

    fn pairs(bvh: &TriBvh) -> Vec<(u32, u32)> {
        let mut pairs = Vec::new();
        bvh.for_each_overlapping_pair(|a, b| pairs.push((a.min(b), a.max(b))));
        pairs.sort_unstable();
        pairs
    }

    #[test]
    fn finds_each_overlapping_pair_once() {
        // A row of unit boxes 0.75 apart: each overlaps its neighbours at
        // distance 1 only (0.75 < 1 < 1.5).
        let items: Vec<(u32, Aabb)> = (0..50)
            .map(|i| (i, unit_box_at(i as f32 * 0.75, 0.0, 0.0)))
            .collect();
        let bvh = TriBvh::build(items);
        let expected: Vec<(u32, u32)> = (0..49).map(|i| (i, i + 1)).collect();
        assert_eq!(pairs(&bvh), expected);
    }

    #[test]
    fn matches_all_pairs_on_scattered_boxes() {
        let mut seed = 12345u32;
        let mut next = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1 << 24) as f32 * 10.0
        };
        let items: Vec<(u32, Aabb)> = (0..300)
            .map(|i| (i, unit_box_at(next(), next(), next())))
            .collect();
        let mut expected = Vec::new();
        for (i, a) in &items {
            for (j, b) in &items {
                if i < j && a.overlaps(b) {
                    expected.push((*i, *j));
                }
            }
        }
        assert!(!expected.is_empty());
        assert_eq!(pairs(&TriBvh::build(items)), expected);
    }

    #[test]
    fn empty_and_identical_boxes() {
        assert!(pairs(&TriBvh::build(Vec::new())).is_empty());
        let same: Vec<(u32, Aabb)> = (0..10).map(|i| (i, unit_box_at(0.0, 0.0, 0.0))).collect();
        assert_eq!(pairs(&TriBvh::build(same)).len(), 45);
    }
}
