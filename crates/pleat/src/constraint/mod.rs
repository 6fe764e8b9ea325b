//! Constraints: each file holds one kind, its data and its XPBD projection.
//!
//! A constraint is a function `C(x)` of a few particle positions that the
//! solver drives to zero (or keeps non-positive, for unilateral ones). XPBD
//! projects it with a compliance `alpha` (inverse stiffness) and a Lagrange
//! multiplier `lambda` per constraint:
//! `dlambda = (-C - alpha~ lambda) / (sum_i w_i |grad_i C|^2 + alpha~)`,
//! `alpha~ = alpha / dt^2`, `dx_i = w_i grad_i C dlambda` (Macklin et al.
//! 2016), written once in [`xpbd`]. Shape matching is the exception: a PBD
//! goal-position projection with a stiffness factor instead of a
//! compliance. Compliances a person tunes live come from a table
//! ([`compliances`]) read at every step, with the fold's drive, through
//! [`Substep`]. A projection reads and moves the positions through
//! [`Positions`], which keeps it to its own particles.

pub mod attachment;
pub mod bending;
pub mod compliances;
pub mod distance;
pub mod fold_drive;
pub mod hinge;
pub mod isometric_bending;
pub mod long_range;
pub mod positions;
pub mod projection;
pub mod shape_matching;
pub mod tether;
pub mod xpbd;

pub use attachment::{Attachment, Grab};
pub use bending::DihedralBending;
pub use compliances::{ComplianceKind, Compliances, ALWAYS_HELD};
pub use distance::DistanceConstraint;
pub use fold_drive::FoldDrive;
pub use hinge::OrigamiHinge;
pub use isometric_bending::IsometricBending;
pub use long_range::LongRangeLimit;
pub use positions::Positions;
pub use projection::{project_once, Constraint, Substep, MAX_PARTICLES};
pub use shape_matching::{PairShape, ShapeMatching, TriangleShape};
pub use tether::Tether;
