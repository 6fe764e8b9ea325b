//! A flat spatial hash grid of boxes (Teschner et al. 2003): each box is
//! entered in every cubic cell it overlaps, cells are hashed into a fixed
//! table, and the table is filled by a counting sort, so that the entries of
//! one bucket lie next to each other.
//!
//! Buffers are kept between builds: a rebuild with no more entries than
//! before allocates nothing. Building and querying are deterministic. A query
//! reports each overlapping box exactly once, without a visited set: a pair
//! of boxes is reported only from the lowest cell the two share.

use crate::math::Aabb;
use glam::{IVec3, Vec3};

/// One box entered in one cell, with what a query tests (kept inline, so a
/// query reads its buckets in order).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Entry {
    item: u32,
    cell: IVec3,
    /// The lowest cell of the box.
    lowest: IVec3,
    bounds: Aabb,
}

/// Boxes binned by cell, queried by box.
#[derive(Clone, Debug, Default)]
pub struct HashGrid {
    inv_cell_size: f32,
    /// Buckets minus one (a power of two minus one).
    mask: u32,
    /// Per bucket: first entry; one more at the end.
    bucket_start: Vec<u32>,
    /// Entries sorted by bucket.
    entries: Vec<Entry>,
    /// Entries in item order, before the sort, and their buckets.
    staged: Vec<Entry>,
    staged_bucket: Vec<u32>,
}

impl HashGrid {
    /// Enters `boxes` (finite) into cells of `cell_size` (positive, finite).
    pub fn build(&mut self, boxes: &[Aabb], cell_size: f32) {
        self.inv_cell_size = 1.0 / cell_size;
        self.staged.clear();
        for (item, b) in boxes.iter().enumerate() {
            let (lo, hi) = (self.cell_of(b.min), self.cell_of(b.max));
            for_each_cell(lo, hi, |cell| {
                self.staged.push(Entry {
                    item: item as u32,
                    cell,
                    lowest: lo,
                    bounds: *b,
                })
            });
        }
        let buckets = (2 * self.staged.len()).next_power_of_two().max(2);
        self.mask = buckets as u32 - 1;
        let mask = self.mask;
        self.staged_bucket.clear();
        self.staged_bucket
            .extend(self.staged.iter().map(|e| hash(e.cell) & mask));
        self.bucket_start.clear();
        self.bucket_start.resize(buckets + 1, 0);
        self.entries.resize(self.staged.len(), Entry::default());
        counting_sort(
            &self.staged,
            &self.staged_bucket,
            &mut self.bucket_start,
            &mut self.entries,
        );
    }

    /// Calls `f` exactly once for every box that overlaps `query`, in a
    /// deterministic order.
    pub fn for_each_overlapping(&self, query: &Aabb, mut f: impl FnMut(u32)) {
        let (lo, hi) = (self.cell_of(query.min), self.cell_of(query.max));
        for_each_cell(lo, hi, |c| {
            let b = (hash(c) & self.mask) as usize;
            let range = self.bucket_start[b] as usize..self.bucket_start[b + 1] as usize;
            for e in &self.entries[range] {
                // Skip other cells of the bucket, and report a pair only from
                // the lowest cell both boxes cover.
                if e.cell == c && e.lowest.max(lo) == c && e.bounds.overlaps(query) {
                    f(e.item);
                }
            }
        });
    }

    fn cell_of(&self, p: Vec3) -> IVec3 {
        // Saturating float-to-int casts keep far points in range.
        (p * self.inv_cell_size).floor().as_ivec3()
    }
}

fn for_each_cell(lo: IVec3, hi: IVec3, mut f: impl FnMut(IVec3)) {
    for z in lo.z..=hi.z {
        for y in lo.y..=hi.y {
            for x in lo.x..=hi.x {
                f(IVec3::new(x, y, z));
            }
        }
    }
}

/// Spatial hash of Teschner et al. (2003).
fn hash(c: IVec3) -> u32 {
    (c.x.wrapping_mul(73_856_093) ^ c.y.wrapping_mul(19_349_663) ^ c.z.wrapping_mul(83_492_791))
        as u32
}

/// Stable counting sort of `items` by `bucket`.
fn counting_sort(items: &[Entry], bucket: &[u32], start: &mut [u32], sorted: &mut [Entry]) {
    for &b in bucket {
        start[b as usize + 1] += 1;
    }
    for k in 1..start.len() {
        start[k] += start[k - 1];
    }
    // `start[b]` is used as the write cursor of bucket `b`, then restored.
    for (e, &b) in items.iter().zip(bucket) {
        sorted[start[b as usize] as usize] = *e;
        start[b as usize] += 1;
    }
    for k in (1..start.len()).rev() {
        start[k] = start[k - 1];
    }
    start[0] = 0;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;

    fn random_boxes(n: usize, size: f32, seed: u64) -> Vec<Aabb> {
        let mut rng = Rng(seed);
        (0..n)
            .map(|_| {
                let p = rng.vec3() * 2.0 - 1.0;
                let q = p + rng.vec3() * size;
                Aabb::around(p, q)
            })
            .collect()
    }

    fn pairs_from_grid(boxes: &[Aabb], grid: &HashGrid) -> Vec<(u32, u32)> {
        let mut pairs = Vec::new();
        for (i, b) in boxes.iter().enumerate() {
            grid.for_each_overlapping(b, |j| {
                if (i as u32) < j {
                    pairs.push((i as u32, j));
                }
            });
        }
        pairs.sort_unstable();
        pairs
    }

    #[test]
    fn finds_exactly_the_pairs_of_a_brute_force_search_once_each() {
        let mut grid = HashGrid::default();
        for (seed, size) in [(1, 0.05), (7, 0.2), (42, 0.1)] {
            let boxes = random_boxes(1500, size, seed);
            // Cells smaller than, equal to and larger than the boxes.
            for cell in [size * 0.3, size, size * 3.0] {
                grid.build(&boxes, cell);
                let mut brute = Vec::new();
                for i in 0..boxes.len() {
                    for j in i + 1..boxes.len() {
                        if boxes[i].overlaps(&boxes[j]) {
                            brute.push((i as u32, j as u32));
                        }
                    }
                }
                assert!(!brute.is_empty());
                let found = pairs_from_grid(&boxes, &grid);
                assert_eq!(found, brute, "size {size} cell {cell}");
            }
        }
    }

    #[test]
    fn rebuild_keeps_its_buffers() {
        let boxes = random_boxes(500, 0.05, 3);
        let mut grid = HashGrid::default();
        grid.build(&boxes, 0.1);
        let ptr = grid.entries.as_ptr();
        // The same boxes in another order: as many entries.
        let shuffled: Vec<Aabb> = boxes.iter().rev().copied().collect();
        grid.build(&shuffled, 0.1);
        assert_eq!(ptr, grid.entries.as_ptr());
    }
}
