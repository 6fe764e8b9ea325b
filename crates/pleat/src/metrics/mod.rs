//! Quality figures of a simulated state: stretch, penetrations, self-intersections.

pub mod intersections;
