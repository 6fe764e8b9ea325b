//! Folding: a crease pattern's [`Sheet`] as a paper part of the [`Model`],
//! its hinges driven by the fold progress.
//!
//! Paper is a cloth whose edges keep their length (stretch compliance 0)
//! and whose bending is replaced by the sheet's hinges
//! ([`OrigamiHinge`]): mountain and valley creases fold to `c` times their
//! full angle (the pattern's own fold angle, else 180 degrees; targets are
//! capped at [`MAX_TARGET_ANGLE`](crate::constraint::hinge::MAX_TARGET_ANGLE) so that flat-folded layers stay apart), facet hinges
//! (flat, auxiliary and triangulation edges) are held flat by a stiff
//! hinge, and unassigned (undriven) hinges swing freely. Compliances are per
//! unit of hinge length, so a crease split by refinement is as stiff as the
//! whole crease. The fold progress `c` is set once
//! ([`crate::Simulation::set_fold_progress`]) or ramped over the first
//! frames ([`FoldRamp`]).
//!
//! Paper defaults ([`paper_solver_settings`], [`PaperStiffness`]) were tuned
//! on the built-in patterns and `patterns/shared` for sheets about 1 m
//! across: 40 substeps of one iteration at 60 frames per second, damping
//! 2 /s, crease compliance 0.1 and facet compliance 2e-6 (rad^2 m / J);
//! gravity is off. Creases must be far softer than the inextensible edges:
//! where the targets of several creases disagree (every pattern that is not
//! rigidly foldable with all creases at the same progress), stiffer creases
//! strain the paper and set it spinning, since Gauss-Seidel projections of
//! fighting constraints keep angular momentum only to first order. Fewer
//! substeps make the creases stiffer relative to the edges, for the same
//! reason. Hinges are projected before the edges in each iteration, so the
//! edges have the last word.

use std::f32::consts::PI;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::pattern::Assignment;
use super::sheet::{Hinge, Sheet};
use crate::constraint::bending::{dihedral_angle, wrap_angle};
use crate::constraint::OrigamiHinge;
use crate::material::Material;
use crate::mesh::Mesh;
use crate::metrics::strain::facet_strain;
use crate::model::{ClothPart, Model};
use crate::simulation::Simulation;
use crate::solver::SolverSettings;
use crate::world::World;

/// Areal density of 80 g/m^2 office paper (kg/m^2).
pub const PAPER_DENSITY: f32 = 0.08;

/// How stiff the hinges of paper are, per unit of hinge length.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PaperStiffness {
    /// Compliance of mountain and valley creases (rad^2 m / J): they must
    /// give where the targets of several creases disagree.
    pub crease_compliance: f32,
    /// Compliance of facet hinges, which keep facets flat (rad^2 m / J).
    pub facet_compliance: f32,
}

impl Default for PaperStiffness {
    fn default() -> Self {
        PaperStiffness {
            crease_compliance: 0.1,
            facet_compliance: 2e-6,
        }
    }
}

/// The hinges of a paper part, in cloth-local indices.
#[derive(Clone, Debug, PartialEq)]
pub struct Paper {
    pub hinges: Vec<Hinge>,
    pub stiffness: PaperStiffness,
}

impl Paper {
    /// The hinge constraints of `cloth` (global indices) at progress 0;
    /// unassigned hinges get none.
    pub fn hinge_constraints(&self, cloth: &ClothPart, rest: &[Vec3]) -> Vec<OrigamiHinge> {
        self.hinges
            .iter()
            .filter_map(|h| {
                let full_angle = full_angle(h)?;
                let v = h.v.map(|i| cloth.global(i));
                let length = rest[v[0] as usize].distance(rest[v[1] as usize]);
                let compliance = match h.assignment {
                    Assignment::Flat => self.stiffness.facet_compliance,
                    _ => self.stiffness.crease_compliance,
                };
                Some(OrigamiHinge::new(
                    v,
                    full_angle,
                    compliance / length.max(f32::MIN_POSITIVE),
                    rest,
                ))
            })
            .collect()
    }
}

/// The fold angle of a hinge at progress 1 (radians, valley positive):
/// zero for facets, the pattern's angle or 180 degrees for creases; `None`
/// for a hinge that is not driven.
pub fn full_angle(hinge: &Hinge) -> Option<f32> {
    match hinge.assignment {
        Assignment::Mountain | Assignment::Valley => {
            let sign = if hinge.assignment == Assignment::Valley {
                1.0
            } else {
                -1.0
            };
            let magnitude = hinge.fold_angle.map_or(PI, f32::abs);
            Some(sign * magnitude)
        }
        Assignment::Flat => Some(0.0),
        _ => None,
    }
}

/// The material of paper: 80 g/m^2, inextensible, thickness-free.
pub fn paper_material() -> Material {
    Material {
        density: PAPER_DENSITY,
        stretch_compliance: 0.0,
        shear_compliance: 0.0,
        thickness: 0.0,
        ..Material::default()
    }
}

/// Solver settings that fold paper reliably (see the module documentation).
pub fn paper_solver_settings() -> SolverSettings {
    SolverSettings {
        substeps: 40,
        iterations: 1,
        damping: 2.0,
        ..SolverSettings::default()
    }
}

impl Model {
    /// Adds `sheet` as a paper part: its triangles as a cloth of `material`
    /// whose bending is replaced by the sheet's hinges.
    pub fn add_paper(
        &mut self,
        name: &str,
        sheet: &Sheet,
        material: Material,
        stiffness: PaperStiffness,
    ) {
        let mesh = Mesh {
            positions: sheet.positions.clone(),
            triangles: sheet.triangles.clone(),
            grid: None,
        };
        self.add_cloth(name, mesh, material, &[], false);
        let part = self.cloths.last_mut().expect("just added");
        part.paper = Some(Paper {
            hinges: sheet.hinges.clone(),
            stiffness,
        });
    }
}

/// Fold progress animated linearly from 0 to `progress` over the first
/// `frames` frames, then held.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoldRamp {
    pub progress: f32,
    /// Zero sets the progress at once.
    pub frames: u32,
}

impl FoldRamp {
    /// The progress during frame `frame` (counted from 1).
    pub fn at(&self, frame: u32) -> f32 {
        if self.frames == 0 {
            return self.progress;
        }
        self.progress * frame.min(self.frames) as f32 / self.frames as f32
    }
}

/// A simulation that folds `sheet` alone with the paper defaults: no
/// gravity, [`paper_solver_settings`], progress ramped by `ramp`.
pub fn paper_simulation(sheet: &Sheet, ramp: FoldRamp) -> Simulation {
    let mut model = Model::default();
    model.add_paper("paper", sheet, paper_material(), PaperStiffness::default());
    let world = World {
        gravity: Vec3::ZERO,
        ..World::default()
    };
    let mut sim = Simulation::new(model, world, paper_solver_settings());
    sim.fold_ramp = Some(ramp);
    sim
}

/// One hinge of a paper part as folded now.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HingeState {
    /// Global particle indices, as in [`Hinge::v`].
    pub v: [u32; 4],
    pub assignment: Assignment,
    /// Fold angle now (radians in `(-pi, pi]`, valley positive); `None` for
    /// a degenerate pair.
    pub angle: Option<f32>,
    /// Fold angle the hinge is driven to; `None` when undriven.
    pub target: Option<f32>,
}

impl HingeState {
    /// How far the fold angle is from its target (radians, the short way
    /// round); `None` when either is missing.
    pub fn error(&self) -> Option<f32> {
        Some(wrap_angle(self.angle? - self.target?).abs())
    }
}

/// Every hinge of every paper part of `model` at positions `x` and fold
/// progress `progress`.
pub fn hinge_states(model: &Model, x: &[Vec3], progress: f32) -> Vec<HingeState> {
    model
        .cloths
        .iter()
        .filter_map(|cloth| Some((cloth, cloth.paper.as_ref()?)))
        .flat_map(|(cloth, paper)| {
            paper.hinges.iter().map(move |h| {
                let v = h.v.map(|i| cloth.global(i));
                HingeState {
                    v,
                    assignment: h.assignment,
                    angle: dihedral_angle(v.map(|i| x[i as usize])).map(|(a, _)| a),
                    target: full_angle(h).map(|a| OrigamiHinge::target(a, progress)),
                }
            })
        })
        .collect()
}

/// Largest fold-angle error per kind of hinge, in degrees (0 where there
/// is no hinge of that kind).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FoldAngleErrors {
    pub mountain: f32,
    pub valley: f32,
    /// Facet hinges, which should stay flat.
    pub flat: f32,
}

impl FoldAngleErrors {
    pub fn of(states: &[HingeState]) -> Self {
        let worst = |kind: Assignment| {
            states
                .iter()
                .filter(|s| s.assignment == kind)
                .filter_map(HingeState::error)
                .fold(0.0f32, f32::max)
                .to_degrees()
        };
        FoldAngleErrors {
            mountain: worst(Assignment::Mountain),
            valley: worst(Assignment::Valley),
            flat: worst(Assignment::Flat),
        }
    }
}

/// What a report says about the paper of a simulation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FoldMetrics {
    pub fold_progress: f32,
    /// Largest fold-angle error per kind of hinge (degrees).
    pub max_fold_angle_error_deg: FoldAngleErrors,
    /// Largest facet strain of the paper ([`facet_strain`]).
    pub max_strain: f32,
}

impl FoldMetrics {
    /// The figures of `sim` now; `None` when it has no paper.
    pub fn measure(sim: &Simulation) -> Option<Self> {
        let model = &sim.model;
        let papers = model.cloths.iter().filter(|c| c.paper.is_some());
        let max_strain = papers
            .map(|cloth| {
                let range = cloth.particles();
                let strain = facet_strain(
                    &model.rest[range.clone()],
                    &sim.particles.x[range],
                    &cloth.mesh.triangles,
                );
                strain.into_iter().fold(0.0, f32::max)
            })
            .reduce(f32::max)?;
        let states = hinge_states(model, &sim.particles.x, sim.fold_progress());
        Some(FoldMetrics {
            fold_progress: sim.fold_progress(),
            max_fold_angle_error_deg: FoldAngleErrors::of(&states),
            max_strain,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::origami::builtin;

    fn hinge(assignment: Assignment, fold_angle: Option<f32>) -> Hinge {
        Hinge {
            v: [0, 1, 2, 3],
            assignment,
            fold_angle,
        }
    }

    #[test]
    fn full_angles_follow_the_assignment() {
        let full = |a, f| full_angle(&hinge(a, f));
        assert_eq!(full(Assignment::Valley, None), Some(PI));
        assert_eq!(full(Assignment::Mountain, None), Some(-PI));
        assert_eq!(full(Assignment::Mountain, Some(1.0)), Some(-1.0));
        // Unsigned pattern angles take the sign of the assignment.
        assert_eq!(full(Assignment::Valley, Some(-0.5)), Some(0.5));
        assert_eq!(full(Assignment::Flat, None), Some(0.0));
        assert_eq!(full(Assignment::Unassigned, Some(1.0)), None);
    }

    #[test]
    fn ramp_is_linear_then_held() {
        let ramp = FoldRamp {
            progress: 0.8,
            frames: 4,
        };
        let at: Vec<f32> = (1..=6).map(|f| ramp.at(f)).collect();
        assert_eq!(at, [0.2, 0.4, 0.6, 0.8, 0.8, 0.8]);
        let at_once = FoldRamp {
            progress: 0.3,
            frames: 0,
        };
        assert_eq!(at_once.at(1), 0.3);
    }

    #[test]
    fn paper_part_gets_hinges_instead_of_bending() {
        let sheet = Sheet::from_pattern(
            &builtin("single-line").unwrap(),
            &crate::origami::SheetOptions::default(),
        )
        .unwrap();
        let mut model = Model::default();
        model.add_paper("p", &sheet, paper_material(), PaperStiffness::default());
        let paper = model.cloths[0].paper.as_ref().unwrap();
        let hinges = paper.hinge_constraints(&model.cloths[0], &model.rest);
        assert_eq!(hinges.len(), sheet.hinges.len());
        let valleys = hinges.iter().filter(|h| h.full_angle > 0.0).count();
        assert_eq!(valleys, 1);
        let states = hinge_states(&model, &model.rest, 0.5);
        assert_eq!(states.len(), hinges.len());
        let errors = FoldAngleErrors::of(&states);
        assert!((errors.valley - 90.0).abs() < 1e-3, "{errors:?}");
        assert_eq!((errors.mountain, errors.flat), (0.0, 0.0));
    }
}
