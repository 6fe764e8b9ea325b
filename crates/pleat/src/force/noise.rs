//! Smooth pseudo-random value noise in three dimensions, deterministic and
//! allocation free, for wind turbulence.

use glam::Vec3;

/// Value noise in [-1, 1], smooth (quintic interpolation of hashed lattice values).
pub fn value_noise(p: Vec3, seed: u32) -> f32 {
    let cell = p.floor();
    let f = p - cell;
    let s = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    let [x, y, z] = [cell.x as i32, cell.y as i32, cell.z as i32];
    let corner = |dx: i32, dy: i32, dz: i32| lattice(x + dx, y + dy, z + dz, seed);
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(corner(0, 0, 0), corner(1, 0, 0), s.x);
    let x10 = lerp(corner(0, 1, 0), corner(1, 1, 0), s.x);
    let x01 = lerp(corner(0, 0, 1), corner(1, 0, 1), s.x);
    let x11 = lerp(corner(0, 1, 1), corner(1, 1, 1), s.x);
    lerp(lerp(x00, x10, s.y), lerp(x01, x11, s.y), s.z)
}

/// Hash of a lattice point mapped to [-1, 1].
fn lattice(x: i32, y: i32, z: i32, seed: u32) -> f32 {
    let mut h = (x as u32).wrapping_mul(0x8da6_b343)
        ^ (y as u32).wrapping_mul(0xd816_3841)
        ^ (z as u32).wrapping_mul(0xcb1a_b31f)
        ^ seed.wrapping_mul(0x2545_f491);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297a_2d39);
    h ^= h >> 15;
    (h as f32 / u32::MAX as f32) * 2.0 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounded_and_continuous() {
        let mut prev = value_noise(Vec3::ZERO, 7);
        for i in 1..2000 {
            let p = Vec3::new(i as f32 * 0.01, i as f32 * 0.003, -(i as f32) * 0.007);
            let n = value_noise(p, 7);
            assert!((-1.0..=1.0).contains(&n));
            assert!((n - prev).abs() < 0.1, "jump at {p}");
            prev = n;
        }
        assert_ne!(
            value_noise(Vec3::splat(0.5), 1),
            value_noise(Vec3::splat(0.5), 2)
        );
    }
}
