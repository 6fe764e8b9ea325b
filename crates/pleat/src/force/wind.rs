//! Aerodynamic wind on triangles (after Keckeisen et al. 2004 and Wilson et
//! al. 2014): for a triangle of area `A`, unit normal `n` and velocity relative
//! to the air `u`,
//! drag `F_d = -1/2 rho C_d A |u|^2 |n.û| û` and
//! lift `F_l = 1/2 rho C_l A |u|^2 (n.û) ((n x û) x û)`,
//! shared equally by the three vertices. The air moves with the mean wind
//! plus a turbulent part: smooth noise in space advected by the wind and
//! varying in time.

use super::noise::value_noise;
use crate::mesh::incidence::Incidence;
use crate::particles::Particles;
use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// A wind field and the aerodynamic coefficients of the cloth.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Wind {
    /// Mean air velocity (m/s).
    pub velocity: Vec3,
    /// Drag coefficient C_D (dimensionless): the force against the relative air
    /// velocity, `C_D |cos| rho A |u|^2 / 2`; default 1.
    pub drag: f32,
    /// Lift coefficient C_L (dimensionless): the force across the relative air
    /// velocity, `C_L cos rho A |u|^2 / 2`; default 0.5.
    pub lift: f32,
    /// kg/m^3.
    pub air_density: f32,
    /// Turbulent speed as a fraction of the mean speed.
    pub turbulence: f32,
    /// Size of turbulent eddies (m).
    pub turbulence_scale: f32,
    /// How fast the turbulence changes (Hz).
    pub turbulence_frequency: f32,
}

impl Default for Wind {
    fn default() -> Self {
        Wind {
            velocity: Vec3::ZERO,
            drag: 1.0,
            lift: 0.5,
            air_density: 1.2,
            turbulence: 0.0,
            turbulence_scale: 0.5,
            turbulence_frequency: 1.0,
        }
    }
}

impl Wind {
    /// Air velocity at `p` and time `t`.
    pub fn air_velocity(&self, p: Vec3, t: f32) -> Vec3 {
        if self.turbulence == 0.0 {
            return self.velocity;
        }
        let speed = self.velocity.length();
        let q = (p - self.velocity * t) / self.turbulence_scale;
        let w = self.turbulence_frequency * t;
        let swirl = Vec3::new(
            value_noise(q + Vec3::new(w, 0.0, 0.0), 1),
            value_noise(q + Vec3::new(0.0, w, 0.0), 2),
            value_noise(q + Vec3::new(0.0, 0.0, w), 3),
        );
        self.velocity + swirl * (self.turbulence * speed)
    }

    /// Force on the triangle `p` moving with vertex velocities `v` at time `t`.
    pub fn triangle_force(&self, p: [Vec3; 3], v: [Vec3; 3], t: f32) -> Vec3 {
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let double_area = cross.length();
        if !double_area.is_normal() {
            return Vec3::ZERO;
        }
        let n = cross / double_area;
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let u = (v[0] + v[1] + v[2]) / 3.0 - self.air_velocity(centroid, t);
        let speed2 = u.length_squared();
        if !speed2.is_normal() {
            return Vec3::ZERO;
        }
        let u_hat = u / speed2.sqrt();
        let cos = n.dot(u_hat);
        let q = 0.25 * self.air_density * double_area * speed2; // 1/2 rho A |u|^2
        let drag = -self.drag * q * cos.abs() * u_hat;
        let lift = self.lift * q * cos * n.cross(u_hat).cross(u_hat);
        drag + lift
    }
}

/// Per-vertex wind forces, with the vertex-to-triangle adjacency needed to
/// gather them in parallel without write conflicts.
#[derive(Clone, Debug, Default)]
pub struct WindForces {
    triangle_force: Vec<Vec3>,
    /// Compressed rows: triangles around vertex `i` are `around[start[i]..start[i+1]]`.
    start: Vec<u32>,
    around: Vec<u32>,
}

impl WindForces {
    /// Empty forces and the vertex-to-triangle adjacency of `triangles` over
    /// `vertex_count` vertices.
    pub fn new(triangles: &[[u32; 3]], vertex_count: usize) -> Self {
        let incidence = Incidence::new(triangles, vertex_count, |t| t.as_slice());
        let (start, slots) = incidence.rows();
        WindForces {
            triangle_force: vec![Vec3::ZERO; triangles.len()],
            start: start.to_vec(),
            around: slots.iter().map(|s| s.element).collect(),
        }
    }

    /// Applies the wind to the velocities over `dt`. The velocity change of a
    /// particle is capped at its speed relative to the air, so that drag can
    /// bring a particle to the wind's speed but never past it (stable for any
    /// step, mass or wind strength).
    pub fn apply(
        &mut self,
        wind: &Wind,
        triangles: &[[u32; 3]],
        p: &mut Particles,
        t: f32,
        dt: f32,
    ) {
        let (x, v, inv_mass) = (&p.x, &mut p.v, &p.inv_mass);
        self.triangle_force
            .par_iter_mut()
            .zip(triangles)
            .with_min_len(1024)
            .for_each(|(f, tri)| {
                *f = wind.triangle_force(tri.map(|i| x[i as usize]), tri.map(|i| v[i as usize]), t)
            });
        let (start, around, forces) = (&self.start, &self.around, &self.triangle_force);
        v.par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(i, vi)| {
                let w = inv_mass[i];
                if w == 0.0 {
                    return;
                }
                let tris = &around[start[i] as usize..start[i + 1] as usize];
                let force: Vec3 = tris.iter().map(|&k| forces[k as usize]).sum::<Vec3>() / 3.0;
                let dv = force * (w * dt);
                let cap = (*vi - wind.air_velocity(x[i], t)).length();
                let len = dv.length();
                *vi += if len > cap { dv * (cap / len) } else { dv };
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn still_air_wind() -> Wind {
        Wind::default()
    }

    #[test]
    fn drag_opposes_motion_through_the_face() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let f = still_air_wind().triangle_force(p, [Vec3::Z; 3], 0.0);
        // Moving along its normal at 1 m/s: pure drag 1/2 rho C_d A.
        assert!(
            f.distance(Vec3::new(0.0, 0.0, -0.5 * 1.2 * 0.5)) < 1e-5,
            "{f}"
        );
        // Moving in its own plane: no force.
        let f = still_air_wind().triangle_force(p, [Vec3::X; 3], 0.0);
        assert!(f.length() < 1e-6, "{f}");
    }

    #[test]
    fn oblique_flow_pushes_along_normal_side() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let wind = Wind {
            velocity: Vec3::new(1.0, 0.0, -1.0),
            ..Wind::default()
        };
        let f = wind.triangle_force(p, [Vec3::ZERO; 3], 0.0);
        assert!(f.z < 0.0 && f.x > 0.0, "blown downwind: {f}");
    }

    #[test]
    fn velocity_change_never_passes_the_wind() {
        let tri = [[0u32, 1, 2]];
        let mut p = Particles::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[1e-6; 3]);
        let wind = Wind {
            velocity: Vec3::new(0.0, 0.0, 2500.0),
            ..Wind::default()
        };
        let mut forces = WindForces::new(&tri, 3);
        forces.apply(&wind, &tri, &mut p, 0.0, 1.0 / 30.0);
        for vi in p.v {
            assert!(
                vi.is_finite() && vi.z > 0.0 && vi.z <= 2500.0 + 1e-3,
                "{vi}"
            );
        }
    }

    #[test]
    fn turbulence_varies_in_space_and_time() {
        let wind = Wind {
            velocity: Vec3::X * 5.0,
            turbulence: 0.5,
            ..Wind::default()
        };
        let a = wind.air_velocity(Vec3::ZERO, 0.0);
        assert_ne!(a, wind.air_velocity(Vec3::new(0.0, 0.7, 0.0), 0.0));
        assert_ne!(a, wind.air_velocity(Vec3::ZERO, 0.3));
        assert!((a - wind.velocity).length() <= 0.5 * 5.0 * 3f32.sqrt() + 1e-4);
    }
}
