//! Small geometry and linear algebra that glam lacks: axis-aligned boxes
//! ([`Aabb`], for every broad phase) and the singular value decomposition
//! of a 3x3 matrix with the rotation of its polar decomposition ([`svd3`],
//! [`polar_rotation`]).

mod aabb;
mod svd;

pub use aabb::Aabb;
pub use svd::{polar_rotation, svd3, Svd3};
