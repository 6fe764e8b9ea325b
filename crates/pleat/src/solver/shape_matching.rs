//! Position-based dynamics with shape matching (Müller et al. 2005, 2007):
//! every triangle (stretch and shear) and every pair of adjacent triangles
//! (bending) is pulled towards its rest shape, turned by the best rotation,
//! with a stiffness factor in [0, 1]. Groups are graph-coloured like XPBD's
//! constraints and each colour is projected in parallel (Gauss-Seidel
//! between colours), for the configured iterations per substep.

use super::parallel::ColoredConstraints;
use super::position_based::{inverse_masses, PbdLoop};
use super::{SolverKind, SolverSettings, StageTimes};
use crate::constraint::{PairShape, ShapeMatching, Substep, TriangleShape};
use crate::control::Control;
use crate::model::{ClothPart, Model};
use crate::particles::Particles;
use crate::world::World;
use glam::Vec3;

/// Position-based dynamics with shape matching of triangles and of adjacent
/// pairs.
pub struct PbdShapeMatching {
    frame: PbdLoop,
    triangles: ColoredConstraints<TriangleShape>,
    pairs: ColoredConstraints<PairShape>,
}

impl PbdShapeMatching {
    /// The solver for `model`: a shape-matching group per triangle and per pair
    /// of adjacent triangles.
    pub fn new(model: &Model, settings: &SolverSettings) -> Self {
        let n = model.particle_count();
        let inv_mass = inverse_masses(model);
        let mut triangles = Vec::new();
        let mut pairs = Vec::new();
        for cloth in &model.cloths {
            let stiffness = cloth.material.pbd_stiffness;
            triangles.extend(
                cloth
                    .mesh
                    .triangles
                    .iter()
                    .map(|t| shape(cloth, *t, &model.rest, &inv_mass, stiffness.stretch)),
            );
            pairs.extend(
                cloth
                    .topology
                    .pairs
                    .iter()
                    .map(|p| shape(cloth, p.v, &model.rest, &inv_mass, stiffness.bend)),
            );
        }
        PbdShapeMatching {
            frame: PbdLoop::new(model, settings),
            triangles: ColoredConstraints::new(triangles, n),
            pairs: ColoredConstraints::new(pairs, n),
        }
    }
}

/// The shape of the cloth-local vertices `local`, its stiffness scaled by their weights.
fn shape<const N: usize>(
    cloth: &ClothPart,
    local: [u32; N],
    rest: &[Vec3],
    inv_mass: &[f32],
    stiffness: f32,
) -> ShapeMatching<N> {
    let k = (stiffness * cloth.stiffness_weight(&local)).min(1.0);
    ShapeMatching::at_rest(local.map(|i| cloth.global(i)), rest, inv_mass, k)
}

impl super::Solver for PbdShapeMatching {
    fn kind(&self) -> SolverKind {
        SolverKind::PbdShapeMatching
    }

    fn constraint_count(&self) -> usize {
        self.triangles.len() + self.pairs.len() + self.frame.pin_count()
    }

    fn set_settings(&mut self, settings: &SolverSettings) {
        self.frame.set_settings(settings);
    }

    fn step(
        &mut self,
        particles: &mut Particles,
        world: &mut World,
        control: &Control,
        stages: &mut StageTimes,
    ) {
        let (triangles, pairs) = (&mut self.triangles, &mut self.pairs);
        // Shape matching has no compliance: the substep's figures are unused.
        let step = Substep::as_built(0.0, 0.0);
        self.frame.step(particles, (world, control), stages, |p| {
            triangles.solve(&mut p.x, &p.inv_mass, &step);
            pairs.solve(&mut p.x, &p.inv_mass, &step);
        });
    }
}
