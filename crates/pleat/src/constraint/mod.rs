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
pub mod hinge;
pub mod isometric_bending;
pub mod positions;
pub mod shape_matching;
pub mod tether;
pub mod xpbd;

pub use attachment::{Attachment, Grab};
pub use bending::DihedralBending;
pub use compliances::{ComplianceKind, Compliances};
pub use distance::DistanceConstraint;
pub use hinge::{FoldDrive, OrigamiHinge};
pub use isometric_bending::IsometricBending;
pub use positions::Positions;
pub use shape_matching::{PairShape, ShapeMatching, TriangleShape};
pub use tether::Tether;

use glam::Vec3;

/// Most particles one constraint acts on.
pub const MAX_PARTICLES: usize = 4;

/// What every projection of one substep shares, read at each step so that a
/// live change takes effect without a rebuild.
#[derive(Clone, Copy, Debug)]
pub struct Substep<'a> {
    /// `1 / dt^2` of the substep.
    pub inv_dt2: f32,
    /// The live compliance table ([`compliances`]): a constraint's
    /// compliance is a factor of its entry.
    pub compliances: &'a [f32],
    /// The fold progress origami hinges are driven to.
    pub fold: FoldDrive,
}

impl<'a> Substep<'a> {
    /// A substep of length `dt` with the live `compliances` and the fold's drive.
    pub fn new(dt: f32, compliances: &'a [f32], fold: FoldDrive) -> Self {
        Substep {
            inv_dt2: 1.0 / (dt * dt),
            compliances,
            fold,
        }
    }
}

mod sealed {
    /// Only the core's constraint kinds are [`super::Constraint`]s: the
    /// parallel solver's soundness rests on what they promise.
    pub trait Sealed {}
}

/// A constraint kind the solvers colour and project.
///
/// Sealed: the parallel solver relies on [`Constraint::particles`] being
/// the same list at every call (it colours by it once).
pub trait Constraint: sealed::Sealed + Send + Sync {
    /// The particles the projection reads and moves (used for colouring);
    /// it may also read pinned particles.
    fn particles(&self) -> &[u32];

    /// Projects the constraint once over `x`, updating its Lagrange
    /// multiplier `lambda` (unused by kinds without one).
    fn project(&self, lambda: &mut f32, x: &Positions, step: &Substep);
}

macro_rules! sealed {
    ($($t:ty),+) => { $(impl sealed::Sealed for $t {})+ };
}
sealed!(
    Attachment,
    DihedralBending,
    DistanceConstraint,
    OrigamiHinge,
    IsometricBending,
    Tether
);
impl<const N: usize> sealed::Sealed for ShapeMatching<N> {}

/// Projects `c` once over all of `x` on this thread (tests, serial
/// callers); the solvers project colours in parallel.
pub fn project_once<C: Constraint + ?Sized>(
    c: &C,
    lambda: &mut f32,
    x: &mut [Vec3],
    inv_mass: &[f32],
    step: &Substep,
) {
    c.project(lambda, &Positions::new(x, inv_mass, c.particles()), step);
}

impl Substep<'static> {
    /// A substep with `1 / dt^2` = `inv_dt2`, every compliance as built
    /// ([`compliances::AS_BUILT`]) and the fold at `progress`, moving.
    pub fn as_built(inv_dt2: f32, progress: f32) -> Self {
        Substep {
            inv_dt2,
            compliances: compliances::AS_BUILT,
            fold: FoldDrive {
                progress,
                held: false,
            },
        }
    }
}
