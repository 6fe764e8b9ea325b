//! The particle pairs of the classic cloth models (Provot 1995): structural
//! pairs along mesh edges, shear pairs along grid quad diagonals, and
//! skip-one bending pairs (along grid rows and columns, or wing to wing
//! across each interior edge of other meshes), with the stiffness a pair gets
//! from the cloth's per-vertex weights.

use crate::mesh::GridSpec;
use crate::model::ClothPart;

/// What a pair of particles resists.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpringKind {
    /// Stretch: a mesh edge that is not a grid diagonal.
    Structural,
    /// Shear: a quad diagonal of a grid mesh.
    Shear,
    /// Bending: a skip-one pair.
    Bend,
}

/// A pair of particles (global indices), its kind and its stiffness weight
/// (the mean of its two vertices' weights).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringPair {
    /// The two particles (global indices).
    pub v: [u32; 2],
    /// What the pair resists.
    pub kind: SpringKind,
    /// Stiffness factor: the mean of the two vertices' weights.
    pub weight: f32,
}

/// Every structural, shear and bending pair of `cloth`.
pub fn spring_pairs(cloth: &ClothPart) -> Vec<SpringPair> {
    let edges = cloth.topology.edges.iter().map(|e| {
        let kind = if cloth.mesh.is_grid_diagonal(e.v[0], e.v[1]) {
            SpringKind::Shear
        } else {
            SpringKind::Structural
        };
        (e.v, kind)
    });
    let bends = skip_one_pairs(cloth)
        .into_iter()
        .map(|v| (v, SpringKind::Bend));
    edges
        .chain(bends)
        .map(|(v, kind)| SpringPair {
            v: v.map(|i| cloth.global(i)),
            kind,
            weight: cloth.stiffness_weight(&v),
        })
        .collect()
}

/// Skip-one bending pairs in cloth-local indices: along grid rows and
/// columns, or between the wings of adjacent triangles on other meshes.
pub fn skip_one_pairs(cloth: &ClothPart) -> Vec<[u32; 2]> {
    match cloth.mesh.grid {
        Some([cols, rows]) => {
            let spec = GridSpec::new(cols, rows, [1.0, 1.0]);
            let mut pairs = Vec::new();
            for r in 0..rows {
                for c in 0..cols {
                    if c + 2 < cols {
                        pairs.push([spec.index(r, c), spec.index(r, c + 2)]);
                    }
                    if r + 2 < rows {
                        pairs.push([spec.index(r, c), spec.index(r + 2, c)]);
                    }
                }
            }
            pairs
        }
        None => cloth
            .topology
            .pairs
            .iter()
            .map(|p| [p.v[2], p.v[3]])
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::mesh::GridOrientation;
    use crate::model::{Model, Pin};
    use crate::motion::Motion;

    fn hanging(n: usize, gradient: f32) -> Model {
        let mesh = GridSpec {
            orientation: GridOrientation::Vertical,
            ..GridSpec::new(n, n, [1.0, 1.0])
        }
        .build();
        let pins: Vec<Pin> = (0..n as u32)
            .map(|c| Pin {
                particle: c,
                compliance: 0.0,
                motion: Motion::default(),
            })
            .collect();
        let material = Material {
            stiffness_gradient: gradient,
            ..Material::default()
        };
        let mut model = Model::default();
        model.add_cloth("sheet", mesh, material, &pins, false);
        model
    }

    #[test]
    fn grid_pairs_by_kind() {
        let model = hanging(4, 0.0);
        let pairs = spring_pairs(&model.cloths[0]);
        let count = |k| pairs.iter().filter(|p| p.kind == k).count();
        // 4x4 grid: 24 row and column edges, 9 diagonals, 2 * 4 * 2 skip-one pairs.
        assert_eq!(count(SpringKind::Structural), 24);
        assert_eq!(count(SpringKind::Shear), 9);
        assert_eq!(count(SpringKind::Bend), 16);
    }

    #[test]
    fn wing_to_wing_bending_on_general_meshes() {
        let mut mesh = GridSpec::new(3, 3, [1.0, 1.0]).build();
        mesh.grid = None;
        let mut model = Model::default();
        model.add_cloth("sheet", mesh, Material::default(), &[], false);
        let cloth = &model.cloths[0];
        assert_eq!(skip_one_pairs(cloth).len(), cloth.topology.pairs.len());
    }

    #[test]
    fn gradient_softens_pairs_far_from_the_pins() {
        let model = hanging(5, 0.4);
        let pairs = spring_pairs(&model.cloths[0]);
        let top = pairs.iter().find(|p| p.v == [0, 1]).unwrap();
        let bottom = pairs.iter().find(|p| p.v == [20, 21]).unwrap();
        assert!((top.weight - 1.0).abs() < 1e-6, "{top:?}");
        assert!((bottom.weight - 0.6).abs() < 1e-6, "{bottom:?}");
    }
}
