//! The model: every cloth of a simulation assembled into one particle index
//! space, with rest shapes, masses, topology, materials and pins. Solvers
//! build their constraints from it.

use crate::material::Material;
use crate::mesh::{lumped_masses, Mesh, Topology};
use crate::motion::Motion;
use crate::paper::Paper;
use glam::Vec3;
use rayon::prelude::*;
use std::ops::Range;

/// A particle held by an attachment: exactly (compliance 0) or softly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pin {
    /// The held particle: cloth-local when passed to [`Model::add_cloth`],
    /// global in [`Model::pins`].
    pub particle: u32,
    /// Inverse stiffness of the attachment (m/N); zero holds the particle
    /// exactly.
    pub compliance: f32,
    /// Script that moves the particle's target.
    pub motion: Motion,
}

/// One cloth inside the model.
#[derive(Clone, Debug)]
pub struct ClothPart {
    /// Name of the cloth, from the scene.
    pub name: String,
    /// The mesh in its rest shape, with cloth-local indices.
    pub mesh: Mesh,
    /// Unique edges and adjacent triangle pairs of the mesh.
    pub topology: Topology,
    /// The cloth's material.
    pub material: Material,
    /// First particle of this cloth in the model.
    pub offset: u32,
    /// Long-range attachments from this cloth's pins.
    pub tethers: bool,
    /// For paper (a crease pattern, see [`Model::add_paper`]): the hinges
    /// that replace the material's bending.
    pub paper: Option<Paper>,
    /// Per vertex: factor on the classic solvers' stiffness, from the
    /// material's stiffness gradient times the scene's per-vertex weights.
    pub stiffness_weights: Vec<f32>,
}

impl ClothPart {
    /// The cloth's particles, as a range of global indices.
    pub fn particles(&self) -> Range<usize> {
        self.offset as usize..self.offset as usize + self.mesh.positions.len()
    }

    /// Global index of a cloth-local vertex.
    pub fn global(&self, local: u32) -> u32 {
        self.offset + local
    }

    /// Stiffness factor of an element on cloth-local vertices: the mean of their weights.
    pub fn stiffness_weight(&self, local: &[u32]) -> f32 {
        let sum: f32 = local
            .iter()
            .map(|&i| self.stiffness_weights[i as usize])
            .sum();
        sum / local.len() as f32
    }
}

/// Weights falling linearly from 1 at the pins to `1 - gradient` at the
/// vertex farthest from any pin (rest distances); all 1 without pins.
fn gradient_weights(mesh: &Mesh, gradient: f32, pins: &[Pin]) -> Vec<f32> {
    let distance_to_pins: Vec<f32> = mesh
        .positions
        .iter()
        .map(|x| {
            pins.iter()
                .map(|p| x.distance(mesh.positions[p.particle as usize]))
                .fold(f32::INFINITY, f32::min)
        })
        .collect();
    let far = distance_to_pins.iter().copied().fold(0.0, f32::max);
    distance_to_pins
        .iter()
        .map(|&d| {
            if gradient == 0.0 || !(far > 0.0 && d.is_finite()) {
                1.0
            } else {
                1.0 - gradient * d / far
            }
        })
        .collect()
}

/// An edge of the rest mesh, for stretch measurements.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestEdge {
    /// The two end particles (global indices).
    pub v: [u32; 2],
    /// Length at rest (m).
    pub rest_length: f32,
}

/// All cloths of a simulation.
#[derive(Clone, Debug, Default)]
pub struct Model {
    /// The cloths, in the order they were added.
    pub cloths: Vec<ClothPart>,
    /// Rest positions of all particles (m).
    pub rest: Vec<Vec3>,
    /// Particle masses; zero for particles pinned with compliance zero.
    pub mass: Vec<f32>,
    /// Per particle: distance kept from colliders.
    pub thickness: Vec<f32>,
    /// All triangles, in global indices.
    pub triangles: Vec<[u32; 3]>,
    /// All unique edges with their rest lengths.
    pub edges: Vec<RestEdge>,
    /// All pins, in global indices.
    pub pins: Vec<Pin>,
}

impl Model {
    /// Adds a cloth; `pins` use cloth-local vertex indices.
    pub fn add_cloth(
        &mut self,
        name: &str,
        mesh: Mesh,
        material: Material,
        pins: &[Pin],
        tethers: bool,
    ) {
        let offset = self.rest.len() as u32;
        let topology = Topology::new(&mesh);
        let mut mass = lumped_masses(&mesh, material.density);
        for pin in pins {
            if pin.compliance == 0.0 {
                mass[pin.particle as usize] = 0.0;
            }
            self.pins.push(Pin {
                particle: pin.particle + offset,
                ..*pin
            });
        }
        self.mass.extend(mass);
        self.thickness.extend(std::iter::repeat_n(
            material.thickness,
            mesh.positions.len(),
        ));
        self.triangles
            .extend(mesh.triangles.iter().map(|t| t.map(|i| i + offset)));
        self.edges
            .par_extend(topology.edges.par_iter().map(|e| RestEdge {
                v: e.v.map(|i| i + offset),
                rest_length:
                    mesh.positions[e.v[0] as usize].distance(mesh.positions[e.v[1] as usize]),
            }));
        self.rest.extend_from_slice(&mesh.positions);
        let stiffness_weights = gradient_weights(&mesh, material.stiffness_gradient, pins);
        self.cloths.push(ClothPart {
            name: name.to_string(),
            mesh,
            topology,
            material,
            offset,
            tethers,
            paper: None,
            stiffness_weights,
        });
    }

    /// Number of particles of all cloths.
    pub fn particle_count(&self) -> usize {
        self.rest.len()
    }

    /// Particles held exactly, in the given cloth.
    pub fn hard_pins_of(&self, cloth: &ClothPart) -> Vec<u32> {
        let range = cloth.particles();
        self.pins
            .iter()
            .filter(|p| p.compliance == 0.0 && range.contains(&(p.particle as usize)))
            .map(|p| p.particle)
            .collect()
    }
}
