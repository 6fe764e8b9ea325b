//! Folding a crease pattern: a [`Sheet`] wired into a [`Model`] as paper
//! ([`Model::add_paper`]), a simulation that folds it with the paper
//! defaults, and the figures of a fold (each hinge's angle against its
//! target, the largest errors, the most strained facet), and the folded
//! state written as FOLD. What paper is and why its defaults are what
//! they are: [`crate::paper`].

use std::collections::HashMap;

use glam::Vec3;
use serde::Serialize;

use crate::backend::{Backend, CpuBackend};
use crate::constraint::bending::{dihedral_angle, wrap_angle};
use crate::fold_steps::HingeTargets;
use crate::material::Material;
use crate::mesh::Mesh;
use crate::metrics::layer_order::face_orders;
use crate::metrics::strain::facet_strain;
use crate::model::{ClothPart, Model};
use crate::origami::fold::assignment_letter;
use crate::origami::{Assignment, FlatFolded, Hinge, LayerCheck, PatternError, Sheet};
pub use crate::paper::{
    full_angle, paper_material, FoldRamp, Paper, PaperStiffness, PAPER_DENSITY, PAPER_MAX_STRAIN,
    PAPER_STRETCH_COMPLIANCE, PAPER_THICKNESS, PAPER_VERTEX_MASS,
};
use crate::simulation::Simulation;
use crate::solver::SolverSettings;
use crate::world::World;

/// Solver settings that fold paper reliably (see the module documentation).
pub fn paper_solver_settings() -> SolverSettings {
    SolverSettings {
        substeps: 160,
        iterations: 1,
        damping: 10.0,
        ..SolverSettings::default()
    }
}

/// [`paper_solver_settings`] with the paper's layers kept `thickness`
/// apart (m; [`PAPER_THICKNESS`] is real paper's): self-contact between
/// facets that do not touch in the flat sheet, with continuous detection
/// and friction. A thickness of zero leaves self-contact off.
pub fn paper_solver_settings_with_contact(thickness: f32) -> SolverSettings {
    let mut settings = paper_solver_settings();
    if thickness > 0.0 {
        settings.self_collision.enabled = true;
        settings.self_collision.thickness = thickness;
    }
    settings
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
            steps: Vec::new(),
            layers: FlatFolded::solve(sheet).ok().map(|f| f.facet_sides()),
        });
        let particles = part.particles();
        self.mass[particles].fill(PAPER_VERTEX_MASS);
    }
}

/// The model and world of `sheet` folding alone with the paper defaults
/// (no gravity), for a backend built with [`paper_solver_settings`] and
/// [`paper_simulation_on`].
pub fn paper_model(sheet: &Sheet) -> (Model, World) {
    let mut model = Model::default();
    model.add_paper("paper", sheet, paper_material(), PaperStiffness::default());
    let world = World {
        gravity: Vec3::ZERO,
        ..World::default()
    };
    (model, world)
}

/// A simulation that folds `model` in `world` (from [`paper_model`]) on
/// `backend` (built for them with `settings`, [`paper_solver_settings`] or
/// [`paper_solver_settings_with_contact`]), progress ramped by `ramp`.
pub fn paper_simulation_on(
    (model, world): (Model, World),
    settings: SolverSettings,
    backend: Box<dyn Backend>,
    ramp: FoldRamp,
) -> Simulation {
    let mut sim = Simulation::with_backend(model, world, settings, backend);
    sim.fold_ramp = Some(ramp);
    sim
}

/// A simulation that folds `sheet` alone with the paper defaults on the
/// CPU backend: no gravity, [`paper_solver_settings`], progress ramped by
/// `ramp`.
pub fn paper_simulation(sheet: &Sheet, ramp: FoldRamp) -> Simulation {
    let (model, world) = paper_model(sheet);
    let settings = paper_solver_settings();
    let backend = Box::new(CpuBackend::new(&model, &settings));
    paper_simulation_on((model, world), settings, backend, ramp)
}

/// One hinge of a paper part as folded now.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HingeState {
    /// Global particle indices, as in [`Hinge::v`].
    pub v: [u32; 4],
    /// Crease assignment of the hinge: mountain, valley, flat (a facet hinge)
    /// or unassigned.
    pub assignment: Assignment,
    /// Fold angle now (radians in `(-pi, pi]`, valley positive); `None` for
    /// a degenerate pair.
    pub angle: Option<f32>,
    /// Fold angle the pattern asks of the hinge: the progress times its
    /// full angle (the hinge itself is driven to that capped at
    /// [`MAX_TARGET_ANGLE`](crate::constraint::fold_drive::MAX_TARGET_ANGLE));
    /// `None` when undriven.
    pub target: Option<f32>,
}

impl HingeState {
    /// How far the fold angle is from its target (radians, the short way
    /// round); `None` when either is missing.
    pub fn error(&self) -> Option<f32> {
        Some(wrap_angle(self.angle? - self.target?).abs())
    }

    /// The fold angle read on its target's side of +-180 degrees (a flat
    /// fold just past 180 reads 180.4, not -179.6); `None` when either is
    /// missing.
    pub fn angle_near_target(&self) -> Option<f32> {
        let target = self.target?;
        Some(target + wrap_angle(self.angle? - target))
    }
}

/// Every hinge of every paper part of `model` at positions `x` and fold
/// progress `progress`.
pub fn hinge_states(model: &Model, x: &[Vec3], progress: f32) -> Vec<HingeState> {
    hinge_states_in_step(model, x, progress, None)
}

/// As [`hinge_states`], in a step of a fold in steps whose hinges go
/// between `targets`' start and end angles (the flat sheet and the full
/// angles where `None`).
pub fn hinge_states_in_step(
    model: &Model,
    x: &[Vec3],
    progress: f32,
    targets: Option<&HingeTargets>,
) -> Vec<HingeState> {
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
                    target: match targets {
                        Some(t) => t.target(v, progress),
                        None => full_angle(h).map(|a| a * progress),
                    },
                }
            })
        })
        .collect()
}

/// Largest fold-angle error per kind of hinge, in degrees (0 where there
/// is no hinge of that kind).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FoldAngleErrors {
    /// Mountain creases.
    pub mountain: f32,
    /// Valley creases.
    pub valley: f32,
    /// Facet hinges, which should stay flat.
    pub flat: f32,
}

impl FoldAngleErrors {
    /// The largest errors of `states`, kind by kind.
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

/// The hinge furthest from its target: where a fold went wrong.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct WorstHinge {
    /// Global particle indices of the hinge's edge.
    pub edge: [u32; 2],
    /// `mountain`, `valley`, `flat` (a facet hinge) or `unassigned`.
    pub kind: &'static str,
    /// Fold angle now, read on its target's side of +-180 degrees, and its
    /// target (degrees, valley positive).
    pub angle_deg: f32,
    /// Its target (degrees, valley positive).
    pub target_deg: f32,
    /// How far the angle is from its target (degrees, the short way round).
    pub error_deg: f32,
}

impl WorstHinge {
    /// The driven hinge of `states` with the largest error; `None` when no
    /// hinge has one.
    pub fn of(states: &[HingeState]) -> Option<Self> {
        let (state, error) = states
            .iter()
            .filter_map(|s| Some((s, s.error()?)))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        Some(WorstHinge {
            edge: [state.v[0], state.v[1]],
            kind: kind_name(state.assignment),
            angle_deg: state.angle_near_target()?.to_degrees(),
            target_deg: state.target?.to_degrees(),
            error_deg: error.to_degrees(),
        })
    }
}

fn kind_name(assignment: Assignment) -> &'static str {
    match assignment {
        Assignment::Mountain => "mountain",
        Assignment::Valley => "valley",
        Assignment::Flat => "flat",
        _ => "unassigned",
    }
}

/// The most strained facet triangle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct WorstFacet {
    /// Global particle indices of the triangle.
    pub triangle: [u32; 3],
    /// Its strain ([`facet_strain`]).
    pub strain: f32,
}

/// What a report says about the paper of a simulation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FoldMetrics {
    /// Fold progress in `[0, 1]` last set: the fraction of their full angles
    /// the creases are driven to.
    pub fold_progress: f32,
    /// Largest fold-angle error per kind of hinge (degrees).
    pub max_fold_angle_error_deg: FoldAngleErrors,
    /// Largest facet strain of the paper ([`facet_strain`]).
    pub max_strain: f32,
    /// The hinge furthest from its target, if any is driven.
    pub worst_hinge: Option<WorstHinge>,
    /// The most strained facet.
    pub worst_facet: Option<WorstFacet>,
    /// For a fold in steps, the step now folding (`fold_progress` is the
    /// progress within it) and how many there are; absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fold_step: Option<FoldStepNow>,
}

/// Where a fold in steps is ([`crate::fold_steps`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FoldStepNow {
    /// The step now folding, counted from 1.
    pub step: usize,
    /// How many steps the fold has.
    pub of: usize,
}

impl FoldMetrics {
    /// The figures of `sim` now; `None` when it has no paper.
    pub fn measure(sim: &Simulation) -> Option<Self> {
        let model = &sim.model;
        let papers = model.cloths.iter().filter(|c| c.paper.is_some());
        let worst_facet = papers
            .flat_map(|cloth| {
                let range = cloth.particles();
                let strain = facet_strain(
                    &model.rest[range.clone()],
                    &sim.particles.x[range],
                    &cloth.mesh.triangles,
                );
                cloth
                    .mesh
                    .triangles
                    .iter()
                    .zip(strain)
                    .map(|(t, strain)| WorstFacet {
                        triangle: t.map(|i| cloth.global(i)),
                        strain,
                    })
                    .collect::<Vec<_>>()
            })
            // A NaN strain (a run gone non-finite) counts as the worst.
            .max_by(|a, b| a.strain.total_cmp(&b.strain))?;
        let step = sim.fold_step().map(|(_, t)| t);
        let states = hinge_states_in_step(model, &sim.particles.x, sim.fold_progress(), step);
        Some(FoldMetrics {
            fold_progress: sim.fold_progress(),
            max_fold_angle_error_deg: FoldAngleErrors::of(&states),
            max_strain: worst_facet.strain,
            worst_hinge: WorstHinge::of(&states),
            worst_facet: Some(worst_facet),
            fold_step: sim
                .fold_step()
                .zip(sim.fold_steps.as_ref())
                .map(|((k, _), s)| FoldStepNow {
                    step: k + 1,
                    of: s.len(),
                }),
        })
    }
}

/// What a report says of the layer order of a pattern that folds flat.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LayerOrderFigures {
    /// Whether the flat-folded pattern has a layer order
    /// ([`FlatFolded::solve`]).
    pub found: bool,
    /// Why not, where it has none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Facets (pieces of paper between creases), pairs of them that overlap
    /// in the flat-folded state, and the conditions on their order.
    pub facets: usize,
    /// Pairs of facets that overlap when folded flat.
    pub overlapping_pairs: usize,
    /// Of those, the pairs whose order every valid order shares (forced by
    /// the creases and conditions): the ones contacts keep in order.
    pub forced_pairs: usize,
    /// Conditions (taco-taco, taco-tortilla, transitivity) on their order.
    pub conditions: usize,
    /// The simulated paper's stacked layers now, checked against the
    /// creases and conditions; absent where no order was found.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub simulated: Option<LayerCheck>,
}

impl LayerOrderFigures {
    /// The figures of `solved` (a pattern's flat-folded state, or why it has
    /// none) against the paper part `cloth` at positions `x` (global
    /// indices).
    pub fn of(
        solved: &Result<FlatFolded, PatternError>,
        cloth: &ClothPart,
        x: &[Vec3],
    ) -> LayerOrderFigures {
        match solved {
            Ok(folded) => {
                let orders = face_orders(&x[cloth.particles()], &cloth.mesh.triangles);
                LayerOrderFigures {
                    found: true,
                    reason: None,
                    facets: folded.facet_count(),
                    overlapping_pairs: folded.overlapping_pairs(),
                    forced_pairs: folded.forced_pairs(),
                    conditions: folded.condition_count(),
                    simulated: Some(folded.check(orders.iter().map(|o| (o.f, o.g, o.s)))),
                }
            }
            Err(e) => LayerOrderFigures {
                found: false,
                reason: Some(e.to_string()),
                facets: 0,
                overlapping_pairs: 0,
                forced_pairs: 0,
                conditions: 0,
                simulated: None,
            },
        }
    }
}

/// The folded state of the paper part `cloth` at positions `x` (global
/// indices) as a FOLD object (FOLD 1.1, one frame of class `foldedForm`):
/// 3D vertex coordinates, the mesh's triangles as faces, and its edges with
/// their assignment and fold angle now (`edges_foldAngle`, degrees, valley
/// positive as the specification has it; 0 on boundary edges), and the
/// order of its stacked faces (`faceOrders`, see
/// [`crate::metrics::layer_order`]). `None` when `cloth` is not paper.
pub fn folded_state_fold(cloth: &ClothPart, x: &[Vec3]) -> Option<serde_json::Value> {
    let paper = cloth.paper.as_ref()?;
    let hinges: HashMap<[u32; 2], &Hinge> = paper
        .hinges
        .iter()
        .map(|h| ([h.v[0].min(h.v[1]), h.v[0].max(h.v[1])], h))
        .collect();
    let at = |i: u32| x[cloth.global(i) as usize];
    let (assignments, angles): (Vec<&str>, Vec<f32>) = cloth
        .topology
        .edges
        .iter()
        .map(|e| match hinges.get(&e.v) {
            Some(h) => {
                let angle = dihedral_angle(h.v.map(at)).map_or(0.0, |(a, _)| a.to_degrees());
                (assignment_letter(h.assignment), angle)
            }
            None => ("B", 0.0),
        })
        .unzip();
    let positions = &x[cloth.particles()];
    let coords: Vec<[f32; 3]> = positions.iter().map(|p| p.to_array()).collect();
    let edges: Vec<[u32; 2]> = cloth.topology.edges.iter().map(|e| e.v).collect();
    let orders: Vec<[i64; 3]> = face_orders(positions, &cloth.mesh.triangles)
        .iter()
        .map(|o| [o.f.into(), o.g.into(), o.s.into()])
        .collect();
    Some(serde_json::json!({
        "file_spec": 1.1,
        "file_creator": "pleat",
        "file_classes": ["singleModel"],
        "frame_title": cloth.name,
        "frame_classes": ["foldedForm"],
        "frame_attributes": ["3D", "convexFaces"],
        "vertices_coords": coords,
        "edges_vertices": edges,
        "edges_assignment": assignments,
        "edges_foldAngle": angles,
        "faces_vertices": cloth.mesh.triangles,
        "faceOrders": orders,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::origami::builtin;
    use std::f32::consts::PI;

    fn hinge(assignment: Assignment, fold_angle: Option<f32>) -> Hinge {
        Hinge {
            v: [0, 1, 2, 3],
            assignment,
            fold_angle,
        }
    }

    /// The built-in single crease as a paper part of a model of its own.
    fn single_line_paper() -> (Sheet, Model) {
        let sheet = Sheet::from_pattern(
            &builtin("single-line").unwrap(),
            &crate::origami::SheetOptions::default(),
        )
        .unwrap();
        let mut model = Model::default();
        model.add_paper("p", &sheet, paper_material(), PaperStiffness::default());
        (sheet, model)
    }

    #[test]
    fn a_flat_fold_just_past_180_degrees_is_measured_against_the_full_target() {
        let state = |angle: f32, progress: f32| HingeState {
            v: [0, 1, 2, 3],
            assignment: Assignment::Valley,
            angle: Some(angle.to_radians()),
            target: Some(PI * progress),
        };
        // Past flat: atan2 reads -179.6 degrees, 0.4 from the 180 asked.
        let past = state(-179.6, 1.0);
        assert!((past.error().unwrap().to_degrees() - 0.4).abs() < 1e-3);
        assert!((past.angle_near_target().unwrap().to_degrees() - 180.4).abs() < 1e-3);
        assert!((state(45.0, 0.25).error().unwrap().to_degrees()).abs() < 1e-3);
    }

    #[test]
    fn errors_are_measured_against_the_uncapped_target() {
        // The valley is driven to 178 degrees (MAX_TARGET_ANGLE), but the
        // pattern asks 180: a crease at its capped target is 2 degrees off.
        let (_, model) = single_line_paper();
        let states = hinge_states(&model, &model.rest, 1.0);
        let valley = states
            .iter()
            .find(|s| s.assignment == Assignment::Valley)
            .unwrap();
        assert_eq!(valley.target, Some(PI));
        let at_cap = HingeState {
            angle: Some(crate::constraint::fold_drive::MAX_TARGET_ANGLE),
            ..*valley
        };
        assert!((at_cap.error().unwrap().to_degrees() - 2.0).abs() < 1e-3);
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
    fn folded_state_exports_as_fold_with_angles_in_degrees() {
        let (_, model) = single_line_paper();
        let cloth = &model.cloths[0];
        let valley = cloth
            .paper
            .as_ref()
            .unwrap()
            .hinges
            .iter()
            .find(|h| h.assignment == Assignment::Valley)
            .unwrap();
        // Lift the first wing of the valley by 90 degrees about its edge.
        let mut x = model.rest.clone();
        let [a, b, wing, _] = valley.v.map(|i| x[i as usize]);
        let axis = (b - a).normalize();
        let offset = wing - a - axis * axis.dot(wing - a);
        x[valley.v[2] as usize] = a + axis * axis.dot(wing - a) + Vec3::Z * offset.length();
        let fold = folded_state_fold(cloth, &x).unwrap();
        assert_eq!(fold["frame_classes"][0], "foldedForm");
        let assignments = fold["edges_assignment"].as_array().unwrap();
        let angles = fold["edges_foldAngle"].as_array().unwrap();
        let edges = fold["edges_vertices"].as_array().unwrap();
        assert_eq!(edges.len(), cloth.topology.edges.len());
        let v = assignments.iter().position(|a| a == "V").unwrap();
        let angle = angles[v].as_f64().unwrap();
        assert!((angle.abs() - 90.0).abs() < 1e-3, "{angle}");
        assert!(assignments.iter().any(|a| a == "B"));
        assert_eq!(fold["vertices_coords"].as_array().unwrap().len(), x.len());
        let mut unfolded = model.clone();
        unfolded.cloths[0].paper = None;
        assert!(folded_state_fold(&unfolded.cloths[0], &x).is_none());
    }

    #[test]
    fn paper_part_gets_hinges_instead_of_bending() {
        let (sheet, model) = single_line_paper();
        let constraints = crate::solver::xpbd::XpbdConstraints::new(&model);
        let hinges = constraints.hinges.items();
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
