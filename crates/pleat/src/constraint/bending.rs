//! Dihedral bending on a pair of adjacent triangles: `C = phi - rest_angle`.
//!
//! For the pair `(x0, x1, x2)`, `(x1, x0, x3)` sharing the edge `e = x1 - x0`,
//! with area-weighted normals `nA = e x (x2 - x0)` and `nB = (x3 - x0) x e`,
//! the signed fold angle is `phi = atan2((nB x nA) . e/|e|, nA . nB)`: zero
//! when flat, positive when the wings rise towards the normals (a valley seen
//! from the front). Its exact gradient (Bridson et al. 2003; Tamstorf and
//! Grinspun 2013) is
//! `grad_2 = |e| nA / |nA|^2`, `grad_3 = |e| nB / |nB|^2`,
//! `grad_0 = -(1 - s2) grad_2 - (1 - s3) grad_3`, `grad_1 = -s2 grad_2 - s3 grad_3`,
//! where `s_k = (x_k - x0) . e / |e|^2` locates the wing's foot on the edge.
//! Origami hinges use the same angle with a moving target.

use super::positions::Positions;
use super::projection::{sealed::Sealed, Constraint, Substep};
use super::xpbd::{alpha_tilde, project};
use glam::{Vec3, Vec3A};
use std::f32::consts::{PI, TAU};

/// Bending resistance of one interior edge.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct DihedralBending {
    /// Shared edge `v[0], v[1]`, wings `v[2]`, `v[3]` (see [`crate::mesh::TrianglePair`]).
    pub v: [u32; 4],
    /// Fold angle at rest (radians).
    pub rest_angle: f32,
    /// Inverse stiffness (rad^2 / J), a factor of the table entry `slot`.
    pub compliance: f32,
    /// Entry of the live compliance table this constraint's compliance is
    /// a factor of ([`super::compliances`]; slot 0: the compliance as built).
    pub slot: u32,
}

/// The signed fold angle of a triangle pair and its gradient with respect to
/// the four positions; `None` for a degenerate pair (zero-area triangle or edge).
#[inline]
pub fn dihedral_angle(p: [Vec3; 4]) -> Option<(f32, [Vec3; 4])> {
    dihedral_angle_simd(p.map(Vec3A::from)).map(|(phi, g)| (phi, g.map(Vec3::from)))
}

/// [`dihedral_angle`] on 16-byte vectors (the form the solvers call).
#[inline]
pub fn dihedral_angle_simd(p: [Vec3A; 4]) -> Option<(f32, [Vec3A; 4])> {
    let e = p[1] - p[0];
    let len2 = e.length_squared();
    let na = e.cross(p[2] - p[0]);
    let nb = (p[3] - p[0]).cross(e);
    let (a2, b2) = (na.length_squared(), nb.length_squared());
    let tiny = 1e-12 * len2 * len2;
    if len2 <= f32::MIN_POSITIVE || a2 <= tiny || b2 <= tiny {
        return None;
    }
    let len = len2.sqrt();
    let phi = fast_atan2(nb.cross(na).dot(e) / len, na.dot(nb));
    let g2 = na * (len / a2);
    let g3 = nb * (len / b2);
    let s2 = (p[2] - p[0]).dot(e) / len2;
    let s3 = (p[3] - p[0]).dot(e) / len2;
    let g0 = -(1.0 - s2) * g2 - (1.0 - s3) * g3;
    let g1 = -s2 * g2 - s3 * g3;
    Some((phi, [g0, g1, g2, g3]))
}

/// `atan2(y, x)` to within 2e-6 rad, several times faster than the libm call
/// (a minimax polynomial for atan on [0, 1] and octant reduction).
#[inline]
pub fn fast_atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let (num, den) = if ay > ax { (ax, ay) } else { (ay, ax) };
    if den == 0.0 {
        return 0.0;
    }
    let t = num / den;
    let t2 = t * t;
    // Horner form; no mul_add: without an FMA target feature it is a slow libm call.
    let poly = -0.011_721_2_f32;
    let poly = poly * t2 + 0.052_653_32;
    let poly = poly * t2 - 0.116_432_87;
    let poly = poly * t2 + 0.193_543_46;
    let poly = poly * t2 - 0.332_623_47;
    let poly = poly * t2 + 0.999_977_26;
    let mut a = t * poly;
    if ay > ax {
        a = std::f32::consts::FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    a.copysign(y)
}

/// `angle` in `(-2 pi, 2 pi]` (a difference of two fold angles) brought into `(-pi, pi]`.
#[inline]
pub fn wrap_angle(angle: f32) -> f32 {
    if angle > PI {
        angle - TAU
    } else if angle <= -PI {
        angle + TAU
    } else {
        angle
    }
}

impl DihedralBending {
    /// A constraint at rest in the current configuration.
    pub fn at_rest(v: [u32; 4], positions: &[Vec3], compliance: f32) -> Self {
        let rest_angle = dihedral_angle(v.map(|i| positions[i as usize])).map_or(0.0, |(a, _)| a);
        DihedralBending {
            v,
            rest_angle,
            compliance,
            slot: 0,
        }
    }
}

impl Sealed for DihedralBending {}

impl Constraint for DihedralBending {
    fn particles(&self) -> &[u32] {
        &self.v
    }

    #[inline]
    fn project(&self, lambda: &mut f32, x: &Positions, step: &Substep) {
        let Some((phi, grad)) = dihedral_angle_simd(self.v.map(|i| Vec3A::from(x.get(i)))) else {
            return;
        };
        let c = wrap_angle(phi - self.rest_angle);
        let alpha = alpha_tilde(self.compliance, self.slot, step);
        project(x, self.v, (c, grad), alpha, lambda);
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Central differences of `f` with respect to each coordinate of each point (in f64 steps).
    pub fn finite_difference(x: &[Vec3], f: impl Fn(&[Vec3]) -> f32) -> Vec<Vec3> {
        let h = 1e-3;
        let mut grad = vec![Vec3::ZERO; x.len()];
        for i in 0..x.len() {
            for k in 0..3 {
                let mut plus = x.to_vec();
                let mut minus = x.to_vec();
                plus[i][k] += h;
                minus[i][k] -= h;
                grad[i][k] = (f(&plus) - f(&minus)) / (2.0 * h);
            }
        }
        grad
    }

    fn pair(fold: f32) -> [Vec3; 4] {
        // Edge along x; wings at +-y, the first one lifted by `fold` radians.
        [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.1, 0.0),
            Vec3::new(0.3, 0.8 * fold.cos(), 0.8 * fold.sin()),
            Vec3::new(0.6, -0.9, 0.05),
        ]
    }

    #[test]
    fn gradient_matches_finite_differences() {
        for fold in [0.0, 0.4, 1.3, 2.5, -0.7, -2.2] {
            let p = pair(fold);
            let (_, grad) = dihedral_angle(p).unwrap();
            let fd = finite_difference(&p, |q| dihedral_angle([q[0], q[1], q[2], q[3]]).unwrap().0);
            for k in 0..4 {
                let err = (fd[k] - grad[k]).length() / grad[k].length().max(1.0);
                assert!(
                    err < 2e-3,
                    "fold {fold}, vertex {k}: fd {} vs {}",
                    fd[k],
                    grad[k]
                );
            }
        }
    }

    #[test]
    fn angle_sign_follows_valley_convention() {
        // Triangles (x0,x1,x2) and (x1,x0,x3) in the x-y plane face +z.
        let flat = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(0.5, 1.0, 0.0),
            Vec3::new(0.5, -1.0, 0.0),
        ];
        assert!(dihedral_angle(flat).unwrap().0.abs() < 1e-6);
        let mut valley = flat;
        valley[2].z = 0.5;
        valley[3].z = 0.5;
        assert!(dihedral_angle(valley).unwrap().0 > 0.5);
        let mut mountain = flat;
        mountain[2].z = -0.5;
        mountain[3].z = -0.5;
        assert!(dihedral_angle(mountain).unwrap().0 < -0.5);
    }

    #[test]
    fn projection_restores_rest_angle_without_moving_centre_of_mass() {
        let mut x = pair(1.0).to_vec();
        let c = DihedralBending {
            v: [0, 1, 2, 3],
            rest_angle: 0.2,
            compliance: 0.0,
            slot: 0,
        };
        let w = [1.0, 2.0, 1.5, 0.5];
        let com = |x: &[Vec3]| -> Vec3 { (0..4).map(|k| x[k] / w[k]).sum() };
        let before = com(&x);
        let mut lambda = 0.0;
        let step = Substep::as_built(1.0, 0.0);
        for _ in 0..20 {
            crate::constraint::projection::project_once(&c, &mut lambda, &mut x, &w, &step);
        }
        let (phi, _) = dihedral_angle([x[0], x[1], x[2], x[3]]).unwrap();
        assert!((phi - 0.2).abs() < 1e-3, "{phi}");
        assert!(com(&x).distance(before) < 1e-5);
    }

    #[test]
    fn fast_atan2_matches_libm() {
        let mut worst = 0.0f64;
        for i in 0..3600 {
            let a = i as f64 / 3600.0 * std::f64::consts::TAU;
            for r in [1e-3, 1.0, 250.0] {
                let (y, x) = ((r * a.sin()) as f32, (r * a.cos()) as f32);
                let err = (fast_atan2(y, x) as f64 - (y as f64).atan2(x as f64)).abs();
                worst = worst.max(err.min(std::f64::consts::TAU - err));
            }
        }
        assert!(worst < 2e-6, "worst error {worst}");
        assert_eq!(fast_atan2(0.0, 0.0), 0.0);
        assert_eq!(fast_atan2(0.0, -1.0), PI);
    }

    #[test]
    fn wrap_angle_range() {
        for a in [-6.0, -PI, -1.0, 0.0, 3.0, PI, 4.0, 6.2] {
            let w = wrap_angle(a);
            assert!(w > -PI - 1e-6 && w <= PI + 1e-6);
            assert!(((a - w) / TAU - ((a - w) / TAU).round()).abs() < 1e-5);
        }
    }
}
