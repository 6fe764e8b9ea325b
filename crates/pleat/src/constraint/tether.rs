//! Long-range attachments (Kim, Chentanez and Müller 2012): each particle may
//! be no farther from a pinned particle than it was at rest,
//! `C = |x - x_pin| - max_length <= 0`. They stop the stretch that builds up
//! far from the pins when a few iterations cannot propagate it.

use super::positions::Positions;
use super::projection::{sealed::Sealed, Constraint, Substep};
use glam::Vec3;
use std::ops::Range;

/// A long-range attachment: a particle kept within its rest distance of a pin.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Tether {
    /// The tethered particle (the only one the projection moves).
    pub particle: [u32; 1],
    /// The pinned particle it hangs from (read only).
    pub pin: u32,
    /// The particle's rest distance from the pin: the farthest it may go (m).
    pub max_length: f32,
}

impl Tether {
    /// Tethers from every dynamic particle in `particles` to its `per_particle`
    /// nearest `pins`, with the rest distance as the length limit.
    pub fn from_pins(
        rest: &[Vec3],
        inv_mass: &[f32],
        particles: Range<usize>,
        pins: &[u32],
        per_particle: usize,
    ) -> Vec<Tether> {
        let mut tethers = Vec::new();
        let mut nearest: Vec<(f32, u32)> = Vec::with_capacity(pins.len());
        for i in particles.filter(|&i| inv_mass[i] > 0.0) {
            nearest.clear();
            nearest.extend(
                pins.iter()
                    .map(|&k| (rest[i].distance(rest[k as usize]), k)),
            );
            nearest.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            tethers.extend(nearest.iter().take(per_particle).map(|&(d, pin)| Tether {
                particle: [i as u32],
                pin,
                max_length: d,
            }));
        }
        tethers
    }
}

impl Sealed for Tether {}

impl Constraint for Tether {
    fn particles(&self) -> &[u32] {
        &self.particle
    }

    #[inline]
    fn project(&self, _lambda: &mut f32, x: &Positions, _step: &Substep) {
        let i = self.particle[0];
        if x.inv_mass(i) == 0.0 {
            return;
        }
        let d = x.get(i) - x.get(self.pin);
        let len = d.length();
        if len > self.max_length {
            x.add(i, d * ((self.max_length - len) / len));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tether_caps_distance_only() {
        let rest = [Vec3::ZERO, Vec3::X, Vec3::new(3.0, 0.0, 0.0)];
        let inv_mass = [0.0, 1.0, 1.0];
        let tethers = Tether::from_pins(&rest, &inv_mass, 0..3, &[0], 1);
        assert_eq!(tethers.len(), 2);
        let mut x = vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
        ];
        let step = Substep::as_built(1.0, 0.0);
        for t in &tethers {
            crate::constraint::projection::project_once(t, &mut 0.0, &mut x, &inv_mass, &step);
        }
        assert!(
            (x[1].x - 1.0).abs() < 1e-6,
            "stretched tether is pulled back"
        );
        assert!((x[2].x - 2.0).abs() < 1e-6, "slack tether does nothing");
    }
}
