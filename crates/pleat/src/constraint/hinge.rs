//! Origami hinge: the dihedral fold angle of a triangle pair driven to a
//! target, `C = phi - target`, with
//! `target = start_angle + c * (full_angle - start_angle)` for the fold
//! progress `c` of the step's [`FoldDrive`], capped at [`MAX_TARGET_ANGLE`]. A fold in one go starts flat
//! (`start_angle` 0, so the target is `c * full_angle`); a fold in steps
//! ([`crate::fold_steps`]) rewrites both angles at each step, the
//! progress running from 0 to 1 within the step.
//!
//! The angle and its exact gradient are those of dihedral bending
//! ([`dihedral_angle_simd`], valley positive). `atan2` wraps at +-pi, so a
//! hinge folded past 180 degrees would read as folded the other way and be
//! driven all the way round: each hinge keeps the continuous angle it had at
//! the end of the last substep and reads the new angle as the nearest
//! branch to it ([`OrigamiHinge::unwrap`]); 179 degrees going to 181 reads
//! 181, not -179, and flat folds can be approached from either side.
//! The tracked angle saturates at 225 degrees either way.
//!
//! While the fold is held (the progress has not moved since the last
//! frame, [`FoldDrive::held`]), a driven crease is a stiffening
//! spring ([`stiffened_error`]): its restoring moment `C dC/de` is 1.15
//! times the linear one 30 degrees from the target and 2.7 times at 90
//! degrees, easing back to 1.33 times at 180. Creases whose targets cannot
//! all be met then share the error instead of leaving a few far off (the
//! compromise moves toward the smallest largest error), as MERLIN's
//! enhanced rotational springs stiffen a crease far from its rest angle
//! (Liu and Paulino 2017). It is a continuation: while the fold moves, the
//! linear creases choose how the flaps go (stiffened then, creases that
//! must wait for others fold first and jam the flapping bird and the map
//! fold); once held, the stiffening moves the compromise along that branch.
//! A crease more than 90 degrees off is on another branch (folded the
//! other way, jammed): its stiffening eases off so that it does not push
//! its neighbours away from their targets. Flat hinges (facet diagonals,
//! target 0) stay linear: they are paper's bending, not creases.

use super::bending::dihedral_angle_simd;
use super::fold_drive::{FoldDrive, MAX_TARGET_ANGLE};
use super::positions::Positions;
use super::projection::{sealed::Sealed, Constraint, Substep};
use super::xpbd::{alpha_tilde, project};
use glam::{Vec3, Vec3A};
use std::f32::consts::{PI, TAU};

/// Fold-angle error (radians) at which a driven crease's stiffening peaks:
/// its constraint rises with twice the slope it has at its target there,
/// and with the target's slope again from twice this angle on
/// ([`stiffened_error`]).
pub const STIFFENING_ANGLE: f32 = PI / 2.0;

/// Largest tracked fold angle (225 degrees): wings that have passed
/// through each other further than that are driven back the way they came
/// rather than by an ever larger correction.
const MAX_TRACKED_ANGLE: f32 = 1.25 * PI;

/// A fold line of a crease pattern, or a facet diagonal kept flat.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct OrigamiHinge {
    /// Shared edge `v[0], v[1]`, wings `v[2]`, `v[3]` (see [`crate::mesh::TrianglePair`]).
    pub v: [u32; 4],
    /// Fold angle at full progress `c = 1` (radians, valley positive): the
    /// end of the fold, or of its current step.
    pub full_angle: f32,
    /// Fold angle at progress `c = 0` (radians, valley positive): 0 for a
    /// fold from the flat sheet, the previous step's end for a fold in
    /// steps. Beside `full_angle`, so that a backend can rewrite the two at
    /// once without touching the tracked `angle`.
    pub start_angle: f32,
    /// Inverse stiffness (rad^2 / J), a factor of the table entry `slot`.
    pub compliance: f32,
    /// Continuous fold angle at the end of the last substep (radians, may
    /// leave `(-pi, pi]`).
    pub angle: f32,
    /// Entry of the live compliance table this constraint's compliance is
    /// a factor of ([`super::compliances`]; slot 0: the compliance as built).
    pub slot: u32,
}

impl OrigamiHinge {
    /// A hinge at progress 0 whose tracked angle starts from `positions`.
    pub fn new(v: [u32; 4], full_angle: f32, compliance: f32, positions: &[Vec3]) -> Self {
        let mut hinge = OrigamiHinge {
            v,
            full_angle,
            start_angle: 0.0,
            compliance,
            angle: 0.0,
            slot: 0,
        };
        hinge.track(|i| positions[i as usize]);
        hinge
    }

    /// `c * full_angle`, capped at [`MAX_TARGET_ANGLE`] either way.
    pub fn target(full_angle: f32, c: f32) -> f32 {
        Self::target_between(0.0, full_angle, c, MAX_TARGET_ANGLE)
    }

    /// `start + c * (end - start)`, capped at `max_angle` either way.
    pub fn target_between(start: f32, end: f32, c: f32, max_angle: f32) -> f32 {
        (start + c * (end - start)).clamp(-max_angle, max_angle)
    }

    /// Whether the hinge is a driven crease (stiffened while held): one
    /// whose start or end angle is not flat.
    #[inline]
    pub fn driven(&self) -> bool {
        self.full_angle != 0.0 || self.start_angle != 0.0
    }

    /// The continuous angle for an `atan2` reading `phi`: the branch
    /// `phi + 2 pi k` nearest the tracked angle.
    #[inline]
    pub fn unwrap(&self, phi: f32) -> f32 {
        self.angle + (phi - self.angle + PI).rem_euclid(TAU) - PI
    }

    /// Updates the tracked angle to the configuration `position` gives
    /// (unchanged for a degenerate pair), within +-`MAX_TRACKED_ANGLE`.
    pub fn track(&mut self, position: impl Fn(u32) -> Vec3) {
        if let Some((phi, _)) = dihedral_angle_simd(self.v.map(|i| Vec3A::from(position(i)))) {
            self.angle = self
                .unwrap(phi)
                .clamp(-MAX_TRACKED_ANGLE, MAX_TRACKED_ANGLE);
        }
    }

    /// `C` and its gradient with respect to the four positions under the
    /// fold's drive: the fold angle's error, stiffened for a driven crease
    /// while the fold is held ([`stiffened_error`]).
    #[inline]
    pub fn evaluate(&self, p: [Vec3A; 4], fold: FoldDrive) -> Option<(f32, [Vec3A; 4])> {
        let target = Self::target_between(
            self.start_angle,
            self.full_angle,
            fold.progress,
            fold.max_angle(),
        );
        self.evaluate_to(p, target, fold.held)
    }

    /// `C` and its gradient for the hinge driven to `target`, stiffened
    /// while `held` for a driven crease.
    #[inline]
    pub fn evaluate_to(&self, p: [Vec3A; 4], target: f32, held: bool) -> Option<(f32, [Vec3A; 4])> {
        dihedral_angle_simd(p).map(|(phi, grad)| {
            let error = self.unwrap(phi) - target;
            if !self.driven() || !held {
                return (error, grad);
            }
            let (c, slope) = stiffened_error(error);
            (c, grad.map(|g| g * slope))
        })
    }
}

impl Sealed for OrigamiHinge {}

impl Constraint for OrigamiHinge {
    fn particles(&self) -> &[u32] {
        &self.v
    }

    #[inline]
    fn project(&self, lambda: &mut f32, x: &Positions, step: &Substep) {
        let p = self.v.map(|i| Vec3A::from(x.get(i)));
        if let Some(c_grad) = self.evaluate(p, step.fold) {
            let alpha = alpha_tilde(self.compliance, self.slot, step);
            project(x, self.v, c_grad, alpha, lambda);
        }
    }
}

/// The stiffening spring's constraint for a fold-angle error `e` and its
/// slope `dC/de`, odd in `e`: for `a = |e|` and `theta_s` =
/// [`STIFFENING_ANGLE`], the slope is `1 + a^2 / theta_s^2` up to
/// `theta_s`, `1 + (2 theta_s - a)^2 / theta_s^2` down from there to
/// `2 theta_s`, and 1 beyond.
#[inline]
pub fn stiffened_error(e: f32) -> (f32, f32) {
    let s = STIFFENING_ANGLE;
    let k = 1.0 / (s * s);
    let a = e.abs();
    let (c, slope) = if a <= s {
        (a + a * a * a * k / 3.0, 1.0 + a * a * k)
    } else if a <= 2.0 * s {
        let r = 2.0 * s - a;
        (
            a + s / 3.0 + (s * s * s - r * r * r) * k / 3.0,
            1.0 + r * r * k,
        )
    } else {
        (a + 2.0 * s / 3.0, 1.0)
    };
    (c.copysign(e), slope)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraint::bending::tests::finite_difference;
    use crate::constraint::projection::project_once;

    /// Edge along x; the first wing lifted by `fold` radians about it, the
    /// second wing flat: the valley fold angle is `fold`.
    fn pair(fold: f32) -> [Vec3; 4] {
        [
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(0.4, 0.8 * fold.cos(), 0.8 * fold.sin()),
            Vec3::new(0.6, -0.9, 0.0),
        ]
    }

    fn hinge_at(fold: f32) -> OrigamiHinge {
        OrigamiHinge::new([0, 1, 2, 3], PI, 0.0, &pair(fold))
    }

    #[test]
    fn pair_folds_by_the_given_angle() {
        for fold in [0.3, -1.2, 2.9] {
            assert!((hinge_at(fold).angle - fold).abs() < 1e-5);
        }
    }

    #[test]
    fn gradient_matches_finite_differences_across_pi() {
        // Folds near +-pi: the raw atan2 jumps there, the unwrapped angle does not.
        for fold in [0.5, 2.0, 3.1, PI, 3.2, -3.13, -0.8] {
            let h = hinge_at(fold);
            let held = FoldDrive {
                progress: 0.9,
                held: true,
                flat: false,
            };
            let p = pair(fold);
            let (c, grad) = h.evaluate(p.map(Vec3A::from), held).unwrap();
            assert!((c - stiffened_error(h.angle - 0.9 * PI).0).abs() < 1e-5);
            let fd = finite_difference(&p, |q| {
                let q = [q[0], q[1], q[2], q[3]].map(Vec3A::from);
                h.evaluate(q, held).unwrap().0
            });
            for k in 0..4 {
                let g = Vec3::from(grad[k]);
                let err = (fd[k] - g).length() / g.length().max(1.0);
                assert!(err < 2e-3, "fold {fold}, vertex {k}: fd {} vs {g}", fd[k]);
            }
        }
    }

    #[test]
    fn tracked_angle_unwraps_across_pi() {
        let mut h = hinge_at(179f32.to_radians());
        for deg in [179.5f32, 180.0, 180.5, 181.0] {
            h.track(|i| pair(deg.to_radians())[i as usize]);
        }
        assert!((h.angle.to_degrees() - 181.0).abs() < 1e-3, "{}", h.angle);
        // And back, through pi, to the other side of zero.
        for deg in (0..=36).rev().map(|k| k as f32 * 5.0).chain([-10.0]) {
            h.track(|i| pair(deg.to_radians())[i as usize]);
        }
        assert!((h.angle.to_degrees() + 10.0).abs() < 1e-3, "{}", h.angle);
        // Spun on through -180 and beyond, it saturates.
        for deg in (2..=36).map(|k| -(k as f32) * 10.0) {
            h.track(|i| pair(deg.to_radians())[i as usize]);
        }
        assert_eq!(h.angle, -MAX_TRACKED_ANGLE);
    }

    #[test]
    fn projection_reaches_a_target_past_pi_from_below() {
        let mut x = pair(170f32.to_radians()).to_vec();
        let mut h = OrigamiHinge::new([0, 1, 2, 3], 0.0, 0.0, &x);
        let w = [1.0; 4];
        for _ in 0..30 {
            let view = Positions::new(&mut x, &w, &h.v);
            let p = h.v.map(|i| Vec3A::from(view.get(i)));
            let c_grad = h.evaluate_to(p, 185f32.to_radians(), false).unwrap();
            project(&view, h.v, c_grad, 0.0, &mut 0.0);
            h.track(|i| x[i as usize]);
        }
        assert!((h.angle.to_degrees() - 185.0).abs() < 0.1, "{}", h.angle);
    }

    #[test]
    fn progress_scales_the_full_angle() {
        assert_eq!(OrigamiHinge::target(-PI, 0.25), -PI / 4.0);
        assert_eq!(OrigamiHinge::target(-PI, 1.0), -MAX_TARGET_ANGLE);
        // A hinge at its target for the drive has no error.
        let h = OrigamiHinge::new([0, 1, 2, 3], 2.0, 0.0, &pair(0.5));
        let fold = FoldDrive {
            progress: 0.25,
            held: false,
            flat: false,
        };
        let (c, _) = h.evaluate(pair(0.5).map(Vec3A::from), fold).unwrap();
        assert!(c.abs() < 1e-5, "{c}");
    }

    #[test]
    fn the_stiffening_slope_is_the_derivative_and_continuous() {
        let h = 1e-3;
        for e in [
            -3.5, -2.0, -1.2, -0.3, 0.0, 0.4, 1.5, 1.57, 1.58, 2.5, 3.1, 3.15, 3.5,
        ] {
            let (c, slope) = stiffened_error(e);
            let fd = (stiffened_error(e + h).0 - stiffened_error(e - h).0) / (2.0 * h);
            assert!((fd - slope).abs() < 1e-2, "e {e}: fd {fd} vs slope {slope}");
            assert!(c * e >= 0.0 && c.abs() >= e.abs(), "e {e}: c {c}");
        }
        assert_eq!(stiffened_error(0.0), (0.0, 1.0));
        // Twice the slope at the stiffening angle, the target's again from
        // twice it on; odd in e.
        assert!((stiffened_error(STIFFENING_ANGLE).1 - 2.0).abs() < 1e-6);
        assert_eq!(stiffened_error(3.5).1, 1.0);
        assert_eq!(stiffened_error(-2.5).0, -stiffened_error(2.5).0);
    }

    /// The fold angle where two driven creases on one fold line, driven to
    /// `t1 < t2` with compliances `a1`, `a2`, balance their moments
    /// `C C' / alpha` (bisection).
    fn balanced_angle(t1: f32, a1: f32, t2: f32, a2: f32) -> f32 {
        let moment = |e: f32, a: f32| {
            let (c, slope) = stiffened_error(e);
            c * slope / a
        };
        let (mut lo, mut hi) = (t1, t2);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if moment(mid - t1, a1) + moment(mid - t2, a2) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        0.5 * (lo + hi)
    }

    #[test]
    fn two_creases_that_fight_share_the_error() {
        // Two creases on one fold line driven to 0.2 and 2.6 rad, the
        // second four times as compliant. Light particles, a multiplier
        // reset each step (quasi-static XPBD): the fold settles where the
        // stiffening moments balance. Linear springs would leave the softer
        // crease 1.92 rad from its target (4/5 of the 2.4 between them).
        let mut x = pair(1.0).to_vec();
        let driven = |full: f32, compliance: f32, x: &[Vec3]| {
            OrigamiHinge::new([0, 1, 2, 3], full, compliance, x)
        };
        let mut pair_of = [driven(0.2, 1.0, &x), driven(2.6, 4.0, &x)];
        let w = [2e-4; 4];
        let held = Substep {
            fold: FoldDrive {
                progress: 1.0,
                held: true,
                flat: false,
            },
            ..Substep::as_built(1.0, 1.0)
        };
        for _ in 0..100_000 {
            for h in &mut pair_of {
                project_once(&*h, &mut 0.0, &mut x, &w, &held);
                h.track(|i| x[i as usize]);
            }
        }
        let angle = pair_of[0].angle;
        let expected = balanced_angle(0.2, 1.0, 2.6, 4.0);
        assert!((angle - expected).abs() < 2e-3, "{angle} vs {expected}");
        let largest = (2.6 - angle).max(angle - 0.2);
        assert!(largest < 1.65, "largest error {largest} rad (linear: 1.92)");
    }

    #[test]
    fn flat_hinges_stay_linear() {
        let mut h = hinge_at(1.2);
        h.full_angle = 0.0;
        let held = FoldDrive {
            progress: 1.0,
            held: true,
            flat: false,
        };
        let (c, grad) = h.evaluate(pair(1.2).map(Vec3A::from), held).unwrap();
        let (_, raw) = dihedral_angle_simd(pair(1.2).map(Vec3A::from)).unwrap();
        assert!((c - 1.2).abs() < 1e-5);
        assert_eq!(grad, raw);
    }
}
