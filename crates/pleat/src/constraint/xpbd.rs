//! The XPBD update, in one place for every constraint kind (Macklin et al.
//! 2016): for a constraint `C` with compliance `alpha` over a substep of
//! length `dt`,
//!
//! - `alpha~ = alpha / dt^2` ([`alpha_tilde`]),
//! - `dlambda = (-C - alpha~ lambda) / (sum_i w_i |grad_i C|^2 + alpha~)`,
//!   `lambda += dlambda` ([`lagrange_update`]),
//! - `dx_i = w_i grad_i C dlambda` ([`position_step`]).
//!
//! [`project`] chains the three for a constraint given as its value and
//! its gradients; kinds whose gradients share a direction (a distance, an
//! attachment, isometric bending) sum `w |grad C|^2` their own cheaper way
//! and call the steps themselves. The GPU kernels' `lagrange_update`
//! (pleat-gpu's shader prelude) is the same arithmetic in the same order.

use super::positions::Positions;
use super::projection::Substep;
use glam::{Vec3, Vec3A};

/// `alpha~ = alpha / dt^2` for a constraint whose compliance is
/// `compliance` times the live table's entry `slot`, rounded as every
/// backend rounds it: `compliance * (1 / dt^2 * table[slot])`.
#[inline]
pub fn alpha_tilde(compliance: f32, slot: u32, step: &Substep) -> f32 {
    compliance * (step.inv_dt2 * step.compliances[slot as usize])
}

/// The multiplier's step `dlambda = (-C - alpha~ lambda) / (sum_i w_i
/// |grad_i C|^2 + alpha~)` for a constraint of value `c`, with
/// `weighted_gradient_norm` the sum `sum_i w_i |grad_i C|^2`; adds it to
/// `lambda` and returns it. `None`, leaving `lambda`, where the
/// denominator vanishes (every particle pinned, a rigid constraint with no
/// gradient).
#[inline]
pub fn lagrange_update(
    c: f32,
    weighted_gradient_norm: f32,
    alpha_tilde: f32,
    lambda: &mut f32,
) -> Option<f32> {
    let denominator = weighted_gradient_norm + alpha_tilde;
    if denominator <= f32::MIN_POSITIVE {
        return None;
    }
    let dlambda = (-c - alpha_tilde * *lambda) / denominator;
    *lambda += dlambda;
    Some(dlambda)
}

/// The position step `dx_i = w_i grad_i C dlambda` of particle `i`, with
/// `grad_i C` given as `gradient` (or a direction, `w` then carrying the
/// gradient's length).
#[inline]
pub fn position_step(x: &Positions, i: u32, w: f32, gradient: Vec3, dlambda: f32) {
    x.add(i, gradient * (w * dlambda));
}

/// One XPBD projection of the constraint on `particles` whose value and
/// gradients are `(c, gradients)`, with `alpha~` = `alpha_tilde`.
#[inline]
pub fn project<const N: usize>(
    x: &Positions,
    particles: [u32; N],
    (c, gradients): (f32, [Vec3A; N]),
    alpha_tilde: f32,
    lambda: &mut f32,
) {
    let w = particles.map(|i| x.inv_mass(i));
    let norm: f32 = w
        .iter()
        .zip(&gradients)
        .map(|(w, g)| w * g.length_squared())
        .sum();
    let Some(dlambda) = lagrange_update(c, norm, alpha_tilde, lambda) else {
        return;
    };
    for ((&i, &w), g) in particles.iter().zip(&w).zip(gradients) {
        if w > 0.0 {
            position_step(x, i, w, Vec3::from(g), dlambda);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rigid_constraint_is_met_in_one_update() {
        // C = x1 - x0 - 1 along x, both particles free: met at once.
        let mut x = vec![Vec3::ZERO, Vec3::X * 3.0];
        let w = [1.0, 1.0];
        let view = Positions::new(&mut x, &w, &[0, 1]);
        let mut lambda = 0.0;
        let g = [Vec3A::NEG_X, Vec3A::X];
        project(&view, [0, 1], (2.0, g), 0.0, &mut lambda);
        assert!((x[1].x - x[0].x - 1.0).abs() < 1e-6, "{x:?}");
        assert_eq!(lambda, -1.0);
    }

    #[test]
    fn compliance_makes_the_update_part_way_and_lambda_carries_it() {
        // alpha~ = w: each update closes half of what is left of C - alpha~ lambda.
        let mut lambda = 0.0;
        let first = lagrange_update(1.0, 1.0, 1.0, &mut lambda).unwrap();
        assert_eq!(first, -0.5);
        let second = lagrange_update(0.5, 1.0, 1.0, &mut lambda).unwrap();
        assert_eq!(second, 0.0, "at equilibrium C = -alpha~ lambda");
    }

    #[test]
    fn pinned_particles_leave_no_update() {
        assert_eq!(lagrange_update(1.0, 0.0, 0.0, &mut 0.0), None);
    }
}
