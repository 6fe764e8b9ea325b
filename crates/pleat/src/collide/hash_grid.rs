//! A flat spatial hash grid (Teschner et al. 2003): points are binned into
//! cubic cells, cells hashed into a fixed table, and the table filled by a
//! counting sort, so that the points of one cell lie next to each other.
//!
//! Buffers are sized by the number of points and kept between builds: a
//! rebuild over the same points allocates nothing. Building and querying are
//! deterministic; each point is reported once per query even when two cells
//! of the query hash to the same bucket.

use glam::{IVec3, Vec3};
use rayon::prelude::*;

/// Points binned by cell, queried by box.
#[derive(Clone, Debug, Default)]
pub struct HashGrid {
    inv_cell_size: f32,
    /// Buckets minus one (a power of two minus one).
    mask: u32,
    /// Per bucket: first entry; one more at the end.
    bucket_start: Vec<u32>,
    /// Point indices sorted by bucket.
    entries: Vec<u32>,
    /// Per point: its cell.
    cell: Vec<IVec3>,
    /// Per point: its bucket.
    bucket: Vec<u32>,
}

impl HashGrid {
    /// Bins `points` into cells of `cell_size` (positive, finite).
    pub fn build(&mut self, points: &[Vec3], cell_size: f32) {
        let n = points.len();
        let buckets = (2 * n).next_power_of_two().max(2);
        self.inv_cell_size = 1.0 / cell_size;
        self.mask = buckets as u32 - 1;
        self.cell.resize(n, IVec3::ZERO);
        self.bucket.resize(n, 0);
        self.entries.resize(n, 0);
        self.bucket_start.clear();
        self.bucket_start.resize(buckets + 1, 0);
        let (inv, mask) = (self.inv_cell_size, self.mask);
        (&mut self.cell, &mut self.bucket, points)
            .into_par_iter()
            .with_min_len(4096)
            .for_each(|(cell, bucket, &p)| {
                *cell = cell_of(p, inv);
                *bucket = hash(*cell) & mask;
            });
        counting_sort(&self.bucket, &mut self.bucket_start, &mut self.entries);
    }

    /// Calls `f` once for every point whose cell overlaps the box `[min, max]`
    /// (a superset of the points inside it), in a deterministic order.
    pub fn for_each_in_box(&self, min: Vec3, max: Vec3, mut f: impl FnMut(u32)) {
        let lo = cell_of(min, self.inv_cell_size);
        let hi = cell_of(max, self.inv_cell_size);
        for z in lo.z..=hi.z {
            for y in lo.y..=hi.y {
                for x in lo.x..=hi.x {
                    let c = IVec3::new(x, y, z);
                    let b = (hash(c) & self.mask) as usize;
                    let range = self.bucket_start[b] as usize..self.bucket_start[b + 1] as usize;
                    for &i in &self.entries[range] {
                        // Another cell hashed to this bucket: not ours to report.
                        if self.cell[i as usize] == c {
                            f(i);
                        }
                    }
                }
            }
        }
    }
}

fn cell_of(p: Vec3, inv_cell_size: f32) -> IVec3 {
    // Saturating float-to-int casts keep far or non-finite points in range.
    (p * inv_cell_size).floor().as_ivec3()
}

/// Spatial hash of Teschner et al. (2003).
fn hash(c: IVec3) -> u32 {
    (c.x.wrapping_mul(73_856_093) ^ c.y.wrapping_mul(19_349_663) ^ c.z.wrapping_mul(83_492_791))
        as u32
}

/// Stable counting sort of point indices by bucket.
fn counting_sort(bucket: &[u32], start: &mut [u32], entries: &mut [u32]) {
    for &b in bucket {
        start[b as usize + 1] += 1;
    }
    for k in 1..start.len() {
        start[k] += start[k - 1];
    }
    // `start[b]` is used as the write cursor of bucket `b`, then restored.
    for (i, &b) in bucket.iter().enumerate() {
        entries[start[b as usize] as usize] = i as u32;
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

    /// A small deterministic generator (xorshift), so the test needs no crate.
    fn random_points(n: usize, seed: u64) -> Vec<Vec3> {
        let mut s = seed;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..n)
            .map(|_| Vec3::new(next(), next(), next()) * 2.0 - 1.0)
            .collect()
    }

    fn pairs_from_grid(points: &[Vec3], r: f32, grid: &HashGrid) -> Vec<(u32, u32)> {
        let mut pairs = Vec::new();
        for (i, &p) in points.iter().enumerate() {
            grid.for_each_in_box(p - r, p + r, |j| {
                if (i as u32) < j && p.distance(points[j as usize]) < r {
                    pairs.push((i as u32, j));
                }
            });
        }
        pairs.sort_unstable();
        pairs
    }

    #[test]
    fn finds_exactly_the_pairs_of_a_brute_force_search() {
        let mut grid = HashGrid::default();
        for (seed, r) in [(1, 0.05), (7, 0.2), (42, 0.011)] {
            let points = random_points(1500, seed);
            // Cells smaller than, equal to and larger than the radius.
            for cell in [r * 0.5, r, r * 3.0] {
                grid.build(&points, cell);
                let mut brute = Vec::new();
                for i in 0..points.len() {
                    for j in i + 1..points.len() {
                        if points[i].distance(points[j]) < r {
                            brute.push((i as u32, j as u32));
                        }
                    }
                }
                assert!(!brute.is_empty());
                assert_eq!(
                    pairs_from_grid(&points, r, &grid),
                    brute,
                    "r {r} cell {cell}"
                );
            }
        }
    }

    #[test]
    fn rebuild_keeps_its_buffers() {
        let points = random_points(500, 3);
        let mut grid = HashGrid::default();
        grid.build(&points, 0.1);
        let ptr = grid.entries.as_ptr();
        let moved: Vec<Vec3> = points.iter().map(|p| *p * 0.5).collect();
        grid.build(&moved, 0.1);
        assert_eq!(ptr, grid.entries.as_ptr());
    }
}
