//! Greedy graph colouring of constraints: two constraints that move a common
//! particle never get the same colour.

use rayon::prelude::*;
use std::ops::Range;

/// Colours beyond this many go to one last colour solved serially.
const MAX_PARALLEL_COLORS: u32 = 128;

/// Colours `items` in order, each with the smallest colour none of its
/// particles has yet, and returns them sorted by colour with the colour ranges.
/// Constraints that find no free colour among the first 128 go to an overflow
/// colour, split into single-item ranges so that they are solved one at a time.
/// The items are copied once, in parallel, into their sorted places.
pub fn greedy_colors<C: Copy + Send + Sync>(
    items: Vec<C>,
    particle_count: usize,
    particles: impl Fn(&C) -> &[u32],
) -> (Vec<C>, Vec<Range<usize>>) {
    let mut used = vec![0u128; particle_count];
    let mut color_of = Vec::with_capacity(items.len());
    for item in &items {
        let ps = particles(item);
        let taken = ps.iter().fold(0u128, |m, &p| m | used[p as usize]);
        let color = (!taken).trailing_zeros().min(MAX_PARALLEL_COLORS);
        if color < MAX_PARALLEL_COLORS {
            for &p in ps {
                used[p as usize] |= 1 << color;
            }
        }
        color_of.push(color);
    }
    let order = by_color(&color_of);
    let ranges = color_ranges(&order, &color_of);
    let sorted = order.par_iter().map(|&i| items[i]).collect();
    (sorted, ranges)
}

/// The items' indices sorted by colour, in their order within a colour (a
/// counting sort: the colours are few).
fn by_color(color_of: &[u32]) -> Vec<usize> {
    let mut start = vec![0usize; MAX_PARALLEL_COLORS as usize + 2];
    for &c in color_of {
        start[c as usize + 1] += 1;
    }
    for c in 1..start.len() {
        start[c] += start[c - 1];
    }
    let mut order = vec![0; color_of.len()];
    for (i, &c) in color_of.iter().enumerate() {
        order[start[c as usize]] = i;
        start[c as usize] += 1;
    }
    order
}

/// Ranges of equal colour over the sorted order; the overflow colour becomes
/// one range per constraint, so that it is solved one at a time.
fn color_ranges(order: &[usize], color_of: &[u32]) -> Vec<Range<usize>> {
    let mut ranges: Vec<Range<usize>> = Vec::new();
    for (pos, &i) in order.iter().enumerate() {
        let color = color_of[i];
        let extend = color < MAX_PARALLEL_COLORS && pos > 0 && color_of[order[pos - 1]] == color;
        match ranges.last_mut() {
            Some(r) if extend => r.end = pos + 1,
            _ => ranges.push(pos..pos + 1),
        }
    }
    ranges
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_colour_shares_a_particle() {
        // A chain and a fan around particle 0.
        let mut items: Vec<[u32; 2]> = (0..50).map(|i| [i, i + 1]).collect();
        items.extend((2..40).map(|i| [0, i]));
        let (sorted, ranges) = greedy_colors(items.clone(), 60, |c| c.as_slice());
        assert_eq!(sorted.len(), items.len());
        for r in &ranges {
            let mut seen = std::collections::HashSet::new();
            for c in &sorted[r.clone()] {
                assert!(
                    c.iter().all(|p| seen.insert(*p)),
                    "colour {r:?} repeats a particle"
                );
            }
        }
    }

    #[test]
    fn overflow_colour_is_serial() {
        // 200 constraints all sharing particle 0: 128 colours, then 72 single ranges.
        let items: Vec<[u32; 2]> = (1..=200).map(|i| [0, i]).collect();
        let (_, ranges) = greedy_colors(items, 201, |c| c.as_slice());
        assert_eq!(ranges.len(), 200);
        assert!(ranges.iter().all(|r| r.len() == 1));
    }
}
