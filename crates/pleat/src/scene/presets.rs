//! Scenes defined in code: the standard benchmark cloth of `pleat bench`.

use super::{ClothSpec, Corner, GridMeshSpec, MeshSpec, PinSpec, Scene};
use crate::material::Material;
use crate::mesh::GridOrientation;
use crate::solver::SolverSettings;
use glam::Vec3;

/// The standard hanging cloth: an `n x n` grid, 1 m x 1 m, in the vertical
/// plane, pinned at its two top corners; stretch (compliance 0), shear and
/// bending; gravity -9.81; 60 frames per second.
pub fn hanging_cloth(n: u32, substeps: u32, tethers: bool) -> Scene {
    Scene {
        name: format!("hanging_{n}"),
        frames: 300,
        fps: 60.0,
        gravity: Vec3::new(0.0, -9.81, 0.0),
        solver: SolverSettings {
            substeps,
            ..SolverSettings::default()
        },
        cloths: vec![ClothSpec {
            name: "sheet".into(),
            mesh: MeshSpec::Grid(GridMeshSpec {
                resolution: [n, n],
                size: [1.0, 1.0],
                orientation: GridOrientation::Vertical,
                center: Vec3::new(0.0, 1.5, 0.0),
                alternate_diagonals: true,
            }),
            material: Material::default(),
            pins: vec![PinSpec {
                corners: vec![Corner::TopLeft, Corner::TopRight],
                ..PinSpec::default()
            }],
            tethers,
            stiffness_weights: Vec::new(),
        }],
        colliders: Vec::new(),
        wind: None,
        fold: None,
        render: None,
    }
}
