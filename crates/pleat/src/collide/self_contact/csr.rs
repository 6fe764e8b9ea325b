//! Compressed sparse rows: a table of sorted rows in one array, with each
//! row's start in another (the rest mesh's rings, the patches' members).

/// Compressed rows from `(row, value)` items, each row sorted.
pub(super) fn csr<T: Copy + Ord + Default>(
    rows: usize,
    items: impl Iterator<Item = (u32, T)> + Clone,
) -> (Vec<u32>, Vec<T>) {
    let mut start = vec![0u32; rows + 1];
    for (r, _) in items.clone() {
        start[r as usize + 1] += 1;
    }
    for k in 1..=rows {
        start[k] += start[k - 1];
    }
    let mut cursor = start.clone();
    let mut values = vec![T::default(); start[rows] as usize];
    for (r, v) in items {
        values[cursor[r as usize] as usize] = v;
        cursor[r as usize] += 1;
    }
    for r in 0..rows {
        values[start[r] as usize..start[r + 1] as usize].sort_unstable();
    }
    (start, values)
}

/// Row `r` of a CSR table.
pub(super) fn row<'a, T>(start: &[u32], values: &'a [T], r: usize) -> &'a [T] {
    &values[start[r] as usize..start[r + 1] as usize]
}
