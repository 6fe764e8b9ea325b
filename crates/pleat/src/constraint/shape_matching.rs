//! Shape matching of a small group of particles (Müller et al. 2005): a
//! triangle (stretch and shear) or the four points of two adjacent triangles
//! (bending) is matched to its rest shape by the best rotation.
//!
//! With rest offsets `q_i = x0_i - c0` about the mass-weighted rest centroid
//! and current offsets `p_i = x_i - c`, the rotation `R` is the polar
//! rotation of `A_pq = sum_i m_i p_i q_iᵀ` (from its SVD, reflections
//! removed); the goal positions are `g_i = R q_i + c` and each dynamic
//! particle moves `stiffness * (g_i - x_i)`, with the stiffness in [0, 1].
//! Pinned particles act as very heavy ones, so the shape turns about them.

use super::positions::Positions;
use super::projection::{sealed::Sealed, Constraint, Substep};
use crate::math::polar_rotation;
use glam::{Mat3, Vec3};

/// Weight of a pinned particle, relative to the heaviest dynamic one of the group.
const PINNED_WEIGHT: f32 = 1e4;

/// A group of `N` particles kept in its rest shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeMatching<const N: usize> {
    /// The group's particles.
    pub v: [u32; N],
    /// Rest offsets `q_i` from the weighted rest centroid.
    pub rest_offsets: [Vec3; N],
    /// Normalised centroid weights (masses, pins heavy), summing to one.
    pub weights: [f32; N],
    /// Fraction of the way to the goal positions moved per projection, in [0, 1].
    pub stiffness: f32,
}

/// A triangle kept in its rest shape (stretch and shear).
pub type TriangleShape = ShapeMatching<3>;
/// Two adjacent triangles kept in their rest shape (bending).
pub type PairShape = ShapeMatching<4>;

impl<const N: usize> ShapeMatching<N> {
    /// A group at rest in the configuration `positions`.
    pub fn at_rest(v: [u32; N], positions: &[Vec3], inv_mass: &[f32], stiffness: f32) -> Self {
        let weights = centroid_weights(v.map(|i| inv_mass[i as usize]));
        let x = v.map(|i| positions[i as usize]);
        let c0 = weighted_centroid(&x, &weights);
        ShapeMatching {
            v,
            rest_offsets: x.map(|xi| xi - c0),
            weights,
            stiffness,
        }
    }

    /// Goal positions `R q_i + c` for the current positions `x`.
    pub fn goals(&self, x: &[Vec3; N]) -> [Vec3; N] {
        let c = weighted_centroid(x, &self.weights);
        let mut a_pq = Mat3::ZERO;
        for ((xk, q), w) in x.iter().zip(&self.rest_offsets).zip(&self.weights) {
            let p = *xk - c;
            a_pq += Mat3::from_cols(p * q.x, p * q.y, p * q.z) * *w;
        }
        let r = polar_rotation(a_pq);
        self.rest_offsets.map(|q| r * q + c)
    }
}

/// Masses normalised to sum to one; pinned particles (inverse mass zero)
/// weigh `PINNED_WEIGHT` times the heaviest dynamic one.
fn centroid_weights<const N: usize>(inv_mass: [f32; N]) -> [f32; N] {
    let heaviest = inv_mass
        .iter()
        .filter(|&&w| w > 0.0)
        .map(|&w| 1.0 / w)
        .fold(0.0, f32::max);
    let pinned = if heaviest > 0.0 {
        heaviest * PINNED_WEIGHT
    } else {
        1.0
    };
    let mass = inv_mass.map(|w| if w > 0.0 { 1.0 / w } else { pinned });
    let total: f32 = mass.iter().sum();
    mass.map(|m| m / total)
}

fn weighted_centroid<const N: usize>(x: &[Vec3; N], weights: &[f32; N]) -> Vec3 {
    x.iter().zip(weights).map(|(x, w)| *x * *w).sum()
}

impl<const N: usize> Sealed for ShapeMatching<N> {}

impl<const N: usize> Constraint for ShapeMatching<N> {
    fn particles(&self) -> &[u32] {
        &self.v
    }

    /// Moves the dynamic particles towards their goals; `lambda` and the
    /// substep are unused (PBD has no compliance).
    fn project(&self, _lambda: &mut f32, x: &Positions, _step: &Substep) {
        let current = self.v.map(|i| x.get(i));
        let goals = self.goals(&current);
        for k in 0..N {
            let i = self.v[k];
            if x.inv_mass(i) > 0.0 {
                x.add(i, (goals[k] - current[k]) * self.stiffness);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn project<const N: usize>(c: &ShapeMatching<N>, x: &mut [Vec3], inv_mass: &[f32]) {
        crate::constraint::projection::project_once(
            c,
            &mut 0.0,
            x,
            inv_mass,
            &Substep::as_built(0.0, 0.0),
        );
    }

    fn distances(x: &[Vec3]) -> Vec<f32> {
        let mut d = Vec::new();
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                d.push(x[i].distance(x[j]));
            }
        }
        d
    }

    fn assert_same_shape(a: &[Vec3], b: &[Vec3]) {
        for (da, db) in distances(a).iter().zip(distances(b)) {
            assert!((da - db).abs() < 1e-4, "{a:?} vs {b:?}");
        }
    }

    fn signed_volume(x: &[Vec3]) -> f32 {
        (x[1] - x[0]).cross(x[2] - x[0]).dot(x[3] - x[0])
    }

    const REST: [Vec3; 3] = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.2, 0.8, 0.0),
    ];

    #[test]
    fn sheared_triangle_is_restored_at_full_stiffness() {
        let inv_mass = [1.0, 2.0, 0.5];
        let c = TriangleShape::at_rest([0, 1, 2], &REST, &inv_mass, 1.0);
        let shear = Mat3::from_cols(Vec3::X, Vec3::new(0.9, 1.0, 0.3), Vec3::Z);
        let mut x: Vec<Vec3> = REST.iter().map(|&p| shear * p + Vec3::Y).collect();
        project(&c, &mut x, &inv_mass);
        assert_same_shape(&x, &REST);
    }

    #[test]
    fn inverted_triangle_is_restored() {
        let inv_mass = [1.0; 3];
        let c = TriangleShape::at_rest([0, 1, 2], &REST, &inv_mass, 1.0);
        // Mirrored through the y-z plane and squashed: its winding is reversed.
        let mut x: Vec<Vec3> = REST
            .iter()
            .map(|p| Vec3::new(-p.x, 0.5 * p.y, 0.0))
            .collect();
        project(&c, &mut x, &inv_mass);
        assert_same_shape(&x, &REST);
    }

    #[test]
    fn reflected_pair_gets_its_handedness_back() {
        let rest = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(0.4, 0.9, 0.2),
            Vec3::new(0.6, -0.8, 0.3),
        ];
        let inv_mass = [1.0; 4];
        let c = PairShape::at_rest([0, 1, 2, 3], &rest, &inv_mass, 1.0);
        let mut x: Vec<Vec3> = rest.iter().map(|p| Vec3::new(p.x, p.y, -p.z)).collect();
        assert!(signed_volume(&x) * signed_volume(&rest) < 0.0);
        project(&c, &mut x, &inv_mass);
        assert_same_shape(&x, &rest);
        assert!(signed_volume(&x) * signed_volume(&rest) > 0.0);
    }

    #[test]
    fn partial_stiffness_moves_part_way_and_pins_stay() {
        let inv_mass = [0.0, 1.0, 1.0];
        let c = TriangleShape::at_rest([0, 1, 2], &REST, &inv_mass, 0.5);
        let mut x = REST.to_vec();
        x[2] += Vec3::new(0.0, 0.6, 0.0);
        let before = x.clone();
        project(&c, &mut x, &inv_mass);
        assert_eq!(x[0], before[0]);
        let error = |x: &[Vec3]| x[0].distance(x[2]) - REST[0].distance(REST[2]);
        assert!(error(&x) > 0.0 && error(&x) < error(&before), "{x:?}");
    }
}
