//! Counting pairs of non-adjacent triangles that intersect.
