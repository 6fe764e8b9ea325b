//! The simulated state: particle positions, velocities and inverse masses,
//! stored as structure of arrays.

use glam::Vec3;

/// Particles of every cloth in a simulation, one index space.
#[derive(Clone, Debug, Default)]
pub struct Particles {
    /// Positions (the predicted positions while a substep is being solved).
    pub x: Vec<Vec3>,
    /// Positions at the start of the current substep.
    pub x_prev: Vec<Vec3>,
    /// Velocities (m/s).
    pub v: Vec<Vec3>,
    /// Inverse masses; zero for pinned (kinematic) particles.
    pub inv_mass: Vec<f32>,
}

impl Particles {
    /// Particles at rest at `positions` with the given masses (zero mass pins).
    pub fn new(positions: Vec<Vec3>, mass: &[f32]) -> Self {
        let inv_mass = mass
            .iter()
            .map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 })
            .collect();
        Particles {
            x_prev: positions.clone(),
            v: vec![Vec3::ZERO; positions.len()],
            x: positions,
            inv_mass,
        }
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there are no particles.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Total linear momentum of the dynamic particles.
    pub fn momentum(&self) -> Vec3 {
        self.v
            .iter()
            .zip(&self.inv_mass)
            .filter(|(_, &w)| w > 0.0)
            .map(|(v, w)| *v / *w)
            .sum()
    }

    /// Total angular momentum of the dynamic particles about their centre
    /// of mass.
    pub fn angular_momentum(&self) -> Vec3 {
        let dynamic = || {
            (0..self.len())
                .filter(|&i| self.inv_mass[i] > 0.0)
                .map(|i| (i, 1.0 / self.inv_mass[i]))
        };
        let mass: f32 = dynamic().map(|(_, m)| m).sum();
        if mass <= 0.0 {
            return Vec3::ZERO;
        }
        let centre = dynamic().map(|(i, m)| self.x[i] * m).sum::<Vec3>() / mass;
        dynamic()
            .map(|(i, m)| (self.x[i] - centre).cross(self.v[i]) * m)
            .sum()
    }

    /// Kinetic energy of the dynamic particles.
    pub fn kinetic_energy(&self) -> f32 {
        self.v
            .iter()
            .zip(&self.inv_mass)
            .filter(|(_, &w)| w > 0.0)
            .map(|(v, w)| 0.5 * v.length_squared() / w)
            .sum()
    }

    /// Whether any position or velocity is NaN or infinite.
    pub fn has_non_finite(&self) -> bool {
        self.x.iter().chain(&self.v).any(|p| !p.is_finite())
    }
}
