//! What a projection is: the [`Constraint`] trait the solvers colour and
//! project, and the [`Substep`] every projection of one substep shares
//! (its `1 / dt^2`, the live compliances and the fold's [`FoldDrive`]).

use super::compliances::AS_BUILT;
use super::fold_drive::FoldDrive;
use super::positions::Positions;
use glam::Vec3;

/// Most particles one constraint acts on.
pub const MAX_PARTICLES: usize = 4;

/// What every projection of one substep shares, read at each step so that a
/// live change takes effect without a rebuild.
#[derive(Clone, Copy, Debug)]
pub struct Substep<'a> {
    /// `1 / dt^2` of the substep.
    pub inv_dt2: f32,
    /// The live compliance table ([`super::compliances`]): a constraint's
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

pub(crate) mod sealed {
    /// Only the core's constraint kinds are [`super::Constraint`]s: the
    /// parallel solver's soundness rests on what they promise. Each kind's
    /// file implements it.
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
    /// ([`AS_BUILT`]) and the fold at `progress`, moving.
    pub fn as_built(inv_dt2: f32, progress: f32) -> Self {
        Substep {
            inv_dt2,
            compliances: AS_BUILT,
            fold: FoldDrive {
                progress,
                held: false,
                flat: false,
            },
        }
    }
}
