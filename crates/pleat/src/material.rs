//! Cloth materials: mass density, compliances and contact thickness.

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
    /// Surface density (kg/m^2).
    pub density: f32,
    /// Compliance of structural edges (m/N); 0 is inextensible.
    pub stretch_compliance: f32,
    /// Compliance of diagonal (shear) edges of grid meshes (m/N).
    pub shear_compliance: f32,
    /// Compliance of bending (rad^2/J for the angle models, m/N for skip-one).
    pub bend_compliance: f32,
    pub bending: BendingModel,
    /// Distance kept from colliders (m).
    pub thickness: f32,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            density: 0.2,
            stretch_compliance: 0.0,
            shear_compliance: 1e-6,
            bend_compliance: 1.0,
            bending: BendingModel::Isometric,
            thickness: 0.005,
        }
    }
}
