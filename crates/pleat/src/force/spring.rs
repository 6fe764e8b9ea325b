//! A damped Hookean spring between two particles, as in the classic
//! mass-spring cloth (Provot 1995): with `d = x_a - x_b`, `n = d / |d|`,
//! the force on `a` is `f = -(ks (|d| - rest_length) + kd (v_a - v_b).n) n`
//! and `b` gets `-f`.

use glam::Vec3;

/// A damped Hookean spring between two particles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring {
    /// The two end particles.
    pub v: [u32; 2],
    /// Length at rest (m).
    pub rest_length: f32,
    /// ks (N/m).
    pub stiffness: f32,
    /// kd (N s/m), on the relative velocity along the spring.
    pub damping: f32,
}

impl Spring {
    /// A spring at rest at the current distance between its particles.
    pub fn at_rest(v: [u32; 2], positions: &[Vec3], stiffness: f32, damping: f32) -> Self {
        Spring {
            v,
            rest_length: positions[v[0] as usize].distance(positions[v[1] as usize]),
            stiffness,
            damping,
        }
    }

    /// The force on `v[0]` (the force on `v[1]` is its negative).
    #[inline]
    pub fn force(&self, x: &[Vec3], v: &[Vec3]) -> Vec3 {
        let [a, b] = self.v.map(|i| i as usize);
        let d = x[a] - x[b];
        let len = d.length();
        if len <= f32::EPSILON * self.rest_length {
            return Vec3::ZERO;
        }
        let n = d / len;
        let elastic = self.stiffness * (len - self.rest_length);
        let viscous = self.damping * (v[a] - v[b]).dot(n);
        -(elastic + viscous) * n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stretched_spring_pulls_its_ends_together() {
        let x = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0)];
        let s = Spring {
            v: [0, 1],
            rest_length: 1.5,
            stiffness: 10.0,
            damping: 0.0,
        };
        assert!(
            s.force(&x, &[Vec3::ZERO; 2])
                .distance(Vec3::new(5.0, 0.0, 0.0))
                < 1e-6
        );
    }

    #[test]
    fn damping_opposes_separation_only() {
        let x = [Vec3::ZERO, Vec3::X];
        let s = Spring::at_rest([0, 1], &x, 0.0, 2.0);
        // b moves away along the spring at 1 m/s: pulled back with kd * 1.
        let f = s.force(&x, &[Vec3::ZERO, Vec3::X]);
        assert!(f.distance(Vec3::new(2.0, 0.0, 0.0)) < 1e-6, "{f}");
        // Sideways motion is not damped.
        assert_eq!(s.force(&x, &[Vec3::ZERO, Vec3::Y]), Vec3::ZERO);
    }
}
