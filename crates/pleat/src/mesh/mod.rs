//! Triangle meshes: the shape of a cloth before it is simulated.
//!
//! A [`Mesh`] is positions and counter-clockwise triangles; [`Topology`]
//! derives the unique edges, the pairs of adjacent triangles (for bending and
//! hinges) and the boundary. Builders make grids ([`grid`]), read OBJ
//! files ([`obj`]) and generate closed collider meshes such as a torus knot
//! or an icosphere ([`generate`]); [`lumped_masses`] turns a surface
//! density into particle masses.

pub mod generate;
pub mod grid;
pub mod incidence;
pub mod obj;
mod topology;

pub use grid::{GridOrientation, GridSpec};
pub use topology::{Edge, Topology, TrianglePair};

use glam::Vec3;

/// A triangle mesh: positions and triangles with counter-clockwise winding.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions (m).
    pub positions: Vec<Vec3>,
    /// Triangles as vertex indices, counter-clockwise seen from the front.
    pub triangles: Vec<[u32; 3]>,
    /// For meshes built as a regular grid: vertices per row and per column,
    /// so that edges can be told apart as structural (stretch) or diagonal (shear).
    pub grid: Option<[usize; 2]>,
}

impl Mesh {
    /// Area of each triangle.
    pub fn triangle_areas(&self) -> Vec<f32> {
        self.triangles
            .iter()
            .map(|t| triangle_area(&self.positions, t))
            .collect()
    }

    /// Whether the edge between vertices `a` and `b` is a quad diagonal of a grid mesh.
    pub fn is_grid_diagonal(&self, a: u32, b: u32) -> bool {
        match self.grid {
            Some([cols, _]) => {
                let (ra, ca) = (a as usize / cols, a as usize % cols);
                let (rb, cb) = (b as usize / cols, b as usize % cols);
                ra != rb && ca != cb
            }
            None => false,
        }
    }

    /// Moves every vertex by `offset`.
    pub fn translate(&mut self, offset: Vec3) {
        for p in &mut self.positions {
            *p += offset;
        }
    }
}

/// Area of triangle `t` over `positions`.
pub fn triangle_area(positions: &[Vec3], t: &[u32; 3]) -> f32 {
    let [a, b, c] = t.map(|i| positions[i as usize]);
    0.5 * (b - a).cross(c - a).length()
}

/// Lumped particle masses: each triangle gives a third of its mass
/// (`density` in kg/m^2 times its area) to each of its vertices.
pub fn lumped_masses(mesh: &Mesh, density: f32) -> Vec<f32> {
    let mut mass = vec![0.0; mesh.positions.len()];
    for (t, area) in mesh.triangles.iter().zip(mesh.triangle_areas()) {
        for &i in t {
            mass[i as usize] += density * area / 3.0;
        }
    }
    mass
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lumped_masses_sum_to_density_times_area() {
        let mesh = GridSpec::new(9, 5, [2.0, 1.0]).build();
        let total: f32 = lumped_masses(&mesh, 0.3).iter().sum();
        assert!((total - 0.3 * 2.0).abs() < 1e-5, "{total}");
    }
}
