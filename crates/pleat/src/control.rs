//! The inputs a caller changes from frame to frame (the frame's length,
//! the fold's drive, the grabbed particle), handed to every step as one
//! value beside the settings, so that no backend keeps a copy of its own.

use crate::constraint::{FoldDrive, Grab};
use glam::Vec3;

/// What one step is driven by, besides the world and the settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Control {
    /// Length of the frame to step (s).
    pub frame_dt: f32,
    /// The fold progress origami hinges are driven to, and whether it is held.
    pub fold: FoldDrive,
    /// The particle a person drags, and where to by the frame's end.
    pub grab: Option<Grab>,
    /// Where the grab's target was when the frame began (the last frame's
    /// target, for the same particle): the target moves from there to
    /// `grab`'s over the frame's substeps, as a hand does, instead of the
    /// whole frame's motion at the first substep. `None`: it is there from
    /// the first.
    pub grab_from: Option<Vec3>,
}

impl Control {
    /// A frame of `frame_dt` with the fold flat and held, nothing grabbed.
    pub fn frame(frame_dt: f32) -> Self {
        Control {
            frame_dt,
            fold: FoldDrive {
                progress: 0.0,
                held: true,
                flat: false,
            },
            grab: None,
            grab_from: None,
        }
    }

    /// The control of substep `k` (from 0) of `substeps`: the grab's target
    /// `(k + 1) / substeps` of the way from `grab_from` to the frame's.
    pub fn at_substep(&self, k: u32, substeps: u32) -> Control {
        let along = (k + 1) as f32 / substeps.max(1) as f32;
        let grab = self.grab.map(|g| Grab {
            target: self
                .grab_from
                .map_or(g.target, |from| from.lerp(g.target, along)),
            ..g
        });
        Control { grab, ..*self }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grab_target_moves_evenly_over_the_substeps_and_ends_on_the_frames() {
        let grab = Grab {
            particle: 3,
            target: Vec3::new(0.0, 1.0, 0.0),
            compliance: 0.0,
        };
        let control = Control {
            grab: Some(grab),
            grab_from: Some(Vec3::ZERO),
            ..Control::frame(1.0 / 60.0)
        };
        let target = |k| control.at_substep(k, 4).grab.unwrap().target.y;
        assert_eq!([0, 1, 2, 3].map(target), [0.25, 0.5, 0.75, 1.0]);
        let jump = Control {
            grab_from: None,
            ..control
        };
        assert_eq!(jump.at_substep(0, 4).grab, Some(grab));
        assert_eq!(Control::frame(0.1).at_substep(0, 4).grab, None);
    }
}
