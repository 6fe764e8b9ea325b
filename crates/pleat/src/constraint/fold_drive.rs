//! The fold's drive: the progress every origami hinge is driven to at a
//! step, and the largest angle a crease is driven to.

/// Largest fold angle a hinge is driven to (radians) in paper without a
/// thickness: 178 degrees, so that the layers of a flat fold meet at a small
/// angle instead of lying in one plane, where a thickness-free sheet cannot
/// tell which layer is on top. Paper with a thickness ([`FoldDrive::flat`])
/// is driven to 180, its contacts keeping the layers apart.
pub const MAX_TARGET_ANGLE: f32 = 178.0 * std::f32::consts::PI / 180.0;

/// The fold's drive at a step, the same for every hinge: what the caller
/// sets from frame to frame, read by each projection.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FoldDrive {
    /// The fold progress `c` in `[0, 1]`: driven creases go to `c` times
    /// their full angle.
    pub progress: f32,
    /// Whether the progress is held (unmoved since the last frame): a
    /// driven crease is then a stiffening spring (see [`super::hinge`]).
    pub held: bool,
    /// Whether flat folds are driven all the way to 180 degrees (paper with
    /// a thickness, whose contacts keep the layers apart), not to
    /// [`MAX_TARGET_ANGLE`].
    pub flat: bool,
}

impl FoldDrive {
    /// The largest angle a crease is driven to (radians).
    pub fn max_angle(&self) -> f32 {
        if self.flat {
            std::f32::consts::PI
        } else {
            MAX_TARGET_ANGLE
        }
    }
}
