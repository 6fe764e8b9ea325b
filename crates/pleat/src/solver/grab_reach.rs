//! Long-range attachments to a grabbed particle (after Kim, Chentanez and
//! Müller 2012): while a person drags a particle, every other particle of
//! its cloth stays within its rest distance of it (times one plus the
//! cloth's strain limit), so the cloth comes along at once instead of the
//! grabbed point pulling out a spike that one sweep a substep only slowly
//! draws the rest after. It holds where the hierarchy's levels do
//! ([`super::hierarchy`]): on a cloth other than paper whose stretch
//! compliance is zero now, or that has a strain limit.

use super::hierarchy::strain_scale;
use crate::constraint::{ComplianceKind, Compliances, ALWAYS_HELD};
use crate::model::Model;
use glam::{Vec3, Vec4};
use rayon::prelude::*;

/// Smallest number of particles a rayon task takes on.
const MIN_TASK: usize = 4096;

/// Each particle's rest position and reach factor (w: one plus its cloth's
/// strain limit; 0 on paper), and its cloth's compliance slot that decides
/// whether the reach holds ([`Compliances::held_slot`]), which tells the cloths apart.
#[derive(Clone, Debug, Default)]
pub struct GrabReach {
    /// Rest position (xyz) and reach factor (w), per particle.
    pub rest: Vec<Vec4>,
    /// Each particle's cloth: its stretch compliance slot, and 1 where a
    /// strain limit holds the reach whatever the compliance (else 0).
    pub cloth: Vec<[u32; 2]>,
}

impl GrabReach {
    /// The reach of every particle of `model`.
    pub fn new(model: &Model) -> Self {
        let n = model.particle_count();
        let mut reach = GrabReach {
            rest: model.rest.iter().map(|r| r.extend(0.0)).collect(),
            cloth: vec![[0; 2]; n],
        };
        for (index, cloth) in model.cloths.iter().enumerate() {
            let scale = match cloth.paper {
                None => strain_scale(cloth),
                Some(_) => 0.0,
            };
            let stretch = Compliances::slot(index, ComplianceKind::Stretch);
            let always = (Compliances::held_slot(cloth, index) == ALWAYS_HELD) as u32;
            for i in cloth.particles() {
                reach.rest[i].w = scale;
                reach.cloth[i] = [stretch, always];
            }
        }
        reach
    }

    /// Pulls every dynamic particle of the grabbed particle's cloth that is
    /// farther from it than its reach back onto that reach (the grabbed
    /// particle itself stays), where the reach holds with the live
    /// `compliances`.
    pub fn project(&self, x: &mut [Vec3], inv_mass: &[f32], grabbed: u32, compliances: &[f32]) {
        let g = grabbed as usize;
        let (Some(&held), Some(&cloth)) = (self.rest.get(g), self.cloth.get(g)) else {
            return;
        };
        let [slot, always] = cloth;
        let inextensible = compliances.get(slot as usize) == Some(&0.0);
        if held.w == 0.0 || g >= x.len() || (always == 0 && !inextensible) {
            return;
        }
        let at = x[g];
        x.par_iter_mut()
            .zip(inv_mass)
            .zip(self.rest.par_iter().zip(&self.cloth))
            .with_min_len(MIN_TASK)
            .for_each(|((p, &w), (rest, &c))| {
                if c == cloth && w > 0.0 {
                    *p = within_reach(*p, at, *rest, held.truncate());
                }
            });
    }
}

/// `p` moved towards `at` until it is no farther from it than `rest.w`
/// times the rest distance between `rest` and `held`.
pub fn within_reach(p: Vec3, at: Vec3, rest: Vec4, held: Vec3) -> Vec3 {
    let reach = rest.w * rest.truncate().distance(held);
    let d = p - at;
    let len = d.length();
    if len > reach {
        at + d * (reach / len)
    } else {
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_particle_beyond_its_reach_comes_back_to_it_and_no_nearer() {
        let rest = Vec4::new(1.0, 0.0, 0.0, 1.0);
        let held = Vec3::ZERO;
        let at = Vec3::new(0.0, 5.0, 0.0);
        let p = within_reach(Vec3::new(0.0, 2.0, 0.0), at, rest, held);
        assert!((p - Vec3::new(0.0, 4.0, 0.0)).length() < 1e-6, "{p}");
        let near = Vec3::new(0.3, 5.0, 0.0);
        assert_eq!(within_reach(near, at, rest, held), near);
        // Its own rest position: no reach at all.
        assert_eq!(
            within_reach(Vec3::ONE, Vec3::ONE * 2.0, rest, rest.truncate()),
            Vec3::ONE * 2.0
        );
    }
}
