//! The particles resting on a collider in a substep (moved by its contact,
//! and by less than [`RESTING`] self-contact thicknesses in all), which
//! the next substep's self-contacts weigh as immovable where the other
//! side of a contact can give way ([`ContactMasses::of`]): the collider
//! stands behind them.
//! Without it a cloth lying on the floor is pushed into the floor by a
//! cloth landing on it, and the floor's contact then lifts it back up
//! through the cloth above: a cloth thrown at 8 m/s onto one lying on the
//! floor passed through it. A particle carried faster is left out: a
//! towel swept off its rail at 10 m/s would stand immovable for a substep
//! where it no longer was. The GPU backend has no such rule yet.

use crate::collide::ContactMasses;
use glam::Vec3;

/// Self-contact thicknesses within which a particle that a collider's
/// contact moved rests on it: how far it may have moved in the substep.
pub const RESTING: f32 = 0.5;

/// Which particles rested on the colliders in the last substep.
#[derive(Clone, Debug, Default)]
pub struct ColliderHeld {
    held: Vec<bool>,
    /// The positions before the colliders' contacts.
    before: Vec<Vec3>,
}

impl ColliderHeld {
    /// The self-contacts' masses: `inv_mass`, with the particles a
    /// collider held in the last substep.
    pub fn masses<'a>(&'a self, inv_mass: &'a [f32]) -> ContactMasses<'a> {
        ContactMasses {
            inv_mass,
            held: &self.held,
        }
    }

    /// Notes the positions before the colliders' contacts.
    pub fn before_colliders(&mut self, x: &[Vec3]) {
        self.before.clear();
        self.before.extend_from_slice(x);
    }

    /// Notes the particles the colliders' contacts moved from where
    /// [`ColliderHeld::before_colliders`] saw them that moved less than
    /// [`RESTING`] times `thickness` (the self-contacts') from `x_prev`
    /// in the substep.
    pub fn after_colliders(&mut self, x: &[Vec3], x_prev: &[Vec3], thickness: f32) {
        let resting = RESTING * thickness;
        let held = x
            .iter()
            .zip(&self.before)
            .zip(x_prev)
            .map(|((&p, &before), &start)| p != before && p.distance(start) < resting);
        self.held.clear();
        self.held.extend(held);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vertex (particle 0) over a triangle (1, 2, 3), its contact point
    /// at the triangle's centre.
    const V: [u32; 4] = [0, 1, 2, 3];
    const SHARES: [f32; 4] = [1.0, -1.0 / 3.0, -1.0 / 3.0, -1.0 / 3.0];

    fn held_after_moving(moved: &[usize]) -> ColliderHeld {
        let mut held = ColliderHeld::default();
        let mut x = vec![Vec3::ZERO; 4];
        held.before_colliders(&x);
        for &k in moved {
            x[k].y += 0.001;
        }
        held.after_colliders(&x, &[Vec3::ZERO; 4], 0.01);
        held
    }

    #[test]
    fn a_side_a_collider_held_gives_no_way() {
        let inv_mass = [1.0, 2.0, 3.0, 4.0];
        let none = held_after_moving(&[]);
        assert_eq!(none.masses(&inv_mass).of(V, SHARES), inv_mass);
        let triangle = held_after_moving(&[1, 2, 3]);
        assert_eq!(
            triangle.masses(&inv_mass).of(V, SHARES),
            [1.0, 0.0, 0.0, 0.0]
        );
        let vertex = held_after_moving(&[0]);
        assert_eq!(vertex.masses(&inv_mass).of(V, SHARES), [0.0, 2.0, 3.0, 4.0]);
    }

    #[test]
    fn a_particle_carried_fast_is_not_held() {
        let mut held = ColliderHeld::default();
        let x_prev = [Vec3::ZERO; 4];
        let mut x = vec![Vec3::new(0.0, -0.01, 0.0); 4];
        held.before_colliders(&x);
        x[1].y = 0.0;
        x[2].y = 0.0;
        // Particle 3 was carried 9 mm by the collider: not resting on it.
        x[3] = Vec3::new(0.009, 0.0, 0.0);
        held.after_colliders(&x, &x_prev, 0.01);
        let inv_mass = [1.0; 4];
        assert_eq!(held.masses(&inv_mass).of(V, SHARES), inv_mass);
        x[3] = Vec3::new(0.004, 0.0, 0.0);
        held.after_colliders(&x, &x_prev, 0.01);
        assert_eq!(held.masses(&inv_mass).of(V, SHARES), [1.0, 0.0, 0.0, 0.0]);
    }

    #[test]
    fn a_side_partly_held_or_both_sides_held_keep_their_masses() {
        let inv_mass = [1.0, 2.0, 3.0, 4.0];
        let corner = held_after_moving(&[1]);
        assert_eq!(corner.masses(&inv_mass).of(V, SHARES), inv_mass);
        let all = held_after_moving(&[0, 1, 2, 3]);
        assert_eq!(all.masses(&inv_mass).of(V, SHARES), inv_mass);
        // A corner with no share in the point need not be held.
        let edge = held_after_moving(&[1, 2]);
        let on_edge = [1.0, -0.5, -0.5, 0.0];
        assert_eq!(edge.masses(&inv_mass).of(V, on_edge), [1.0, 0.0, 0.0, 4.0]);
    }
}
