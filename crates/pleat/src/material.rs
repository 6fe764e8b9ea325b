//! Cloth materials: mass density, compliances (XPBD), spring constants
//! (mass-spring), stiffness factors (PBD), stiffness variation over the cloth
//! and contact thickness.

use serde::{Deserialize, Serialize};

/// How a cloth resists bending.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BendingModel {
    /// Isometric (quadratic) bending of each pair of adjacent triangles: as
    /// stiff as the dihedral model for small folds, cheaper to solve; pairs
    /// that are not flat at rest fall back to the dihedral model.
    #[default]
    Isometric,
    /// Dihedral angle of each pair of adjacent triangles, exact for any fold.
    Dihedral,
    /// Classic distance constraints that skip one vertex: along grid rows and
    /// columns, or between the wings of adjacent triangles on other meshes.
    SkipOne,
}

/// Physical properties of a cloth.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// Surface density (kg/m^2; unused on paper, whose vertices weigh
    /// [`crate::paper::PAPER_VERTEX_MASS`] each).
    pub density: f32,
    /// Compliance of structural edges (m/N; on paper per unit of edge
    /// length, 1/N); 0 is inextensible.
    pub stretch_compliance: f32,
    /// Compliance of diagonal (shear) edges of grid meshes (m/N).
    pub shear_compliance: f32,
    /// Strain limit of XPBD's stretch and shear edges (Provot 1995): the
    /// largest relative change of length an edge may take however hard it
    /// is pulled or pushed (0.01: 1 %), on top of its compliance; `None`
    /// for no limit. Hard projections enforce it after each substep's
    /// iterations, until every edge is within 1.8 times it on the CPU
    /// (two sweeps on the GPU). Paper folds with 1 %.
    pub max_strain: Option<f32>,
    /// Compliance of bending (rad^2/J for the angle models, m/N for skip-one).
    pub bend_compliance: f32,
    /// How the cloth resists bending: `isometric` (the default), `dihedral` or
    /// `skip_one`.
    pub bending: BendingModel,
    /// Distance kept from colliders (m).
    pub thickness: f32,
    /// Spring constants ks of the mass-spring solver (N/m).
    pub spring_stiffness: SpringCoefficients,
    /// Spring damping kd of the mass-spring solver (N s/m), along each spring.
    pub spring_damping: SpringCoefficients,
    /// Stiffness factors in [0, 1] of the PBD solvers (shape matching, Jacobi).
    pub pbd_stiffness: PbdStiffness,
    /// Fraction of the classic solvers' stiffness lost linearly from the
    /// nearest pin to the farthest point of the cloth, in [0, 1): 0.4 leaves
    /// 60% of the stiffness at the far edge.
    pub stiffness_gradient: f32,
}

/// One coefficient per kind of spring of the mass-spring solver.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringCoefficients {
    /// Springs along mesh edges (grid rows and columns).
    pub structural: f32,
    /// Springs along the quad diagonals of grid meshes.
    pub shear: f32,
    /// Skip-one springs: along grid rows and columns, or wing to wing.
    pub bend: f32,
}

/// Stiffness factors of the PBD solvers: the fraction of the way to the goal
/// positions each projection moves, so the effective stiffness depends on the
/// iteration count and the step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PbdStiffness {
    /// Triangle shape matching, and stretch and shear distance constraints.
    pub stretch: f32,
    /// Shape matching of triangle pairs, and skip-one distance constraints.
    pub bend: f32,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            density: 0.2,
            stretch_compliance: 0.0,
            shear_compliance: 1e-6,
            max_strain: None,
            bend_compliance: 1.0,
            bending: BendingModel::Isometric,
            thickness: 0.005,
            spring_stiffness: SpringCoefficients {
                structural: 5.0,
                shear: 1.0,
                bend: 0.2,
            },
            spring_damping: SpringCoefficients {
                structural: 0.0,
                shear: 0.0,
                bend: 0.0,
            },
            pbd_stiffness: PbdStiffness {
                stretch: 1.0,
                bend: 0.1,
            },
            stiffness_gradient: 0.0,
        }
    }
}
