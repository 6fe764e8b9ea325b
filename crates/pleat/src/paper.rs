//! Paper: a crease pattern's hinges as a part of the model, its material
//! and how stiff its creases are, and the fold progress they are driven by.
//!
//! Paper is a cloth whose edges hardly stretch (a small stretch compliance
//! per unit of edge length) and whose bending is replaced by the sheet's
//! hinges ([`crate::constraint::OrigamiHinge`]): mountain and valley creases fold to `c` times
//! their full angle (the pattern's own fold angle, else 180 degrees;
//! targets are capped at
//! [`MAX_TARGET_ANGLE`](crate::constraint::fold_drive::MAX_TARGET_ANGLE) so that
//! flat-folded layers stay apart; fold-angle errors are measured against
//! the uncapped `c` times the full angle), facet hinges (flat, auxiliary
//! and triangulation edges) are held flat by a stiffer hinge, and unassigned
//! (undriven) hinges swing freely. Compliances are per unit of hinge or
//! edge length, so a crease split by refinement is as stiff as the whole
//! crease. The fold progress `c` is set once
//! ([`crate::Simulation::set_fold_progress`]) or ramped over the first
//! frames ([`FoldRamp`]).
//!
//! Paper defaults ([`paper_material`],
//! [`crate::folding::paper_solver_settings`], [`PaperStiffness`]) were measured on Origami Simulator's example library,
//! the built-in patterns and `patterns/shared` (docs/folding.md,
//! docs/design-notes.md) for sheets
//! 1 m across (every sheet is scaled to that size, so a pattern drawn in
//! px, mm or m folds alike): 160 substeps of one iteration at 60 frames per
//! second, damping 10 /s, crease and facet compliance 1 (rad^2 m / J),
//! stretch compliance 1.6e-2 per unit of edge length (1/N) within a strain
//! limit of 1 % ([`PAPER_MAX_STRAIN`]), every vertex 1 g
//! ([`PAPER_VERTEX_MASS`]); gravity is off.
//!
//! Where the targets of several creases disagree (every pattern that is not
//! rigidly foldable with all creases at the same progress), the paper must
//! find a compromise. Edges that give a little let a sheet pass between
//! states that inextensible paper cannot reach from the flat sheet with
//! every crease driven at once (with inextensible edges the flapping bird
//! jams at 178 degrees from its target; with these it folds within 3). The
//! strain limit keeps that give small once the fold is held: the edges are
//! soft within 1 % of their length and inextensible beyond it (20 times
//! that while the progress moves, and swept back within it over the
//! positions alone when the fold comes to rest,
//! [`crate::solver::xpbd::MOVING_FOLD_STRAIN_SCALE`]), so the compromise is taken by
//! the creases and by facets bending (as soft as the creases: the crane
//! ends 87 degrees from its worst target, against 127 with facets ten times
//! stiffer and no limit). Without the limit, stiff creases strain the
//! paper. Gauss-Seidel sweeps of fighting constraints turn the sheet a
//! little every substep; the solver takes that turn back
//! ([`crate::solver::momentum`]), so a held fold does not spin. Fewer substeps
//! make the hinges stiffer relative to the edges, since one Gauss-Seidel
//! iteration a substep adds about `dt^2 sum w |grad C|^2` to every
//! compliance. Damping of 10 /s lets a single crease settle within a
//! degree of its target in the second after the ramp (at 6 /s it keeps
//! swinging by up to 2 degrees at 160 substeps). Hinges are projected
//! before the edges in each iteration, and the strain limits have sweeps
//! of their own after it (two, and more on the CPU while an edge is beyond
//! 1.8 times its limit, as in the dense sheets jammed by creases that
//! fight), so the edges have the last word.

use std::f32::consts::PI;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::material::Material;
use crate::origami::{Assignment, FacetSides, Hinge};

/// Areal density of 80 g/m^2 office paper (kg/m^2).
pub const PAPER_DENSITY: f32 = 0.08;

/// Mass of every vertex of paper (kg), whatever the material's density.
/// Folding is quasi-static and the mass a device of the solver: one XPBD
/// iteration a substep adds `dt^2 sum w |grad C|^2` to every compliance,
/// so with the sheet's mass shared among its vertices the finest patterns
/// (light vertices) would be the softest, and with masses lumped by area
/// the small triangles where creases meet would be (the hypar's centre
/// stretched 5.2 % at half progress, HexSpiralTess's 6,149 vertices tore).
/// One gram a vertex, as Origami Simulator gives every node the same mass.
pub const PAPER_VERTEX_MASS: f32 = 1e-3;

/// Stretch compliance of paper's edges per unit of edge length (1/N: an
/// edge of length `L` has compliance `L` times this, m/N).
pub const PAPER_STRETCH_COMPLIANCE: f32 = 1.6e-2;

/// Strain limit of paper's edges: compliant within 1 % of their rest
/// length, inextensible beyond it.
pub const PAPER_MAX_STRAIN: f32 = 0.01;

/// Paper's thickness on the 1 m sheet (m), where its layers are kept apart
/// ([`crate::folding::paper_solver_settings_with_contact`]): real paper's
/// 0.1 mm on a 20 cm sheet.
pub const PAPER_THICKNESS: f32 = 5e-4;

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
            crease_compliance: 1.0,
            facet_compliance: 1.0,
        }
    }
}

/// The hinges of a paper part, in cloth-local indices.
#[derive(Clone, Debug, PartialEq)]
pub struct Paper {
    /// The hinges of the part: its creases and the facet hinges that keep
    /// facets flat.
    pub hinges: Vec<Hinge>,
    /// Compliance of the creases and of the facet hinges.
    pub stiffness: PaperStiffness,
    /// A fold in steps: per step, each hinge's angle at the step's end
    /// (radians, valley positive, `None` when undriven; in the order of
    /// `hinges`). Empty: the part folds in one go ([`crate::fold_steps`]).
    pub steps: Vec<Vec<Option<f32>>>,
    /// The layer order of the pattern folded flat, where it has one
    /// ([`crate::origami::FlatFolded`]): self-contacts keep each facet on
    /// its side of the facets it overlaps there.
    pub layers: Option<FacetSides>,
}

impl Paper {
    /// Elastic energy the driven creases of `cloth` hold when flat with
    /// their targets at progress 1 (J): `sum L theta^2 / (2 alpha)` over
    /// hinges of length `L`, full angle `theta` and compliance `alpha` per
    /// unit length, with `rest` the part's own rest positions (local
    /// indices). Folding can turn at most this much into motion.
    pub fn crease_energy(&self, rest: &[Vec3]) -> f32 {
        self.hinges
            .iter()
            .filter(|h| matches!(h.assignment, Assignment::Mountain | Assignment::Valley))
            .filter_map(|h| {
                let theta = full_angle(h)?;
                let [a, b] = [h.v[0], h.v[1]].map(|i| rest[i as usize]);
                Some(a.distance(b) * theta * theta / (2.0 * self.stiffness.crease_compliance))
            })
            .sum()
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

/// The material of paper: 80 g/m^2, edges of stretch compliance
/// [`PAPER_STRETCH_COMPLIANCE`] per unit length within a strain limit of
/// [`PAPER_MAX_STRAIN`], thickness-free.
pub fn paper_material() -> Material {
    Material {
        density: PAPER_DENSITY,
        stretch_compliance: PAPER_STRETCH_COMPLIANCE,
        max_strain: Some(PAPER_MAX_STRAIN),
        shear_compliance: 0.0,
        thickness: 0.0,
        ..Material::default()
    }
}

/// Fold progress animated linearly from 0 to `progress` over the first
/// `frames` frames, then held.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoldRamp {
    /// Fold progress in `[0, 1]` reached at the end of the ramp.
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
