//! The camera and the light: framing the scene by default, the projection
//! both the GPU and the tests use, and the light's shadow-map projection.

use glam::{Mat4, Vec2, Vec3};

/// Axis-aligned bounds of what is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Bounds {
    /// The bounds of `points`; `None` when there are none or one is not finite.
    pub fn of(points: impl IntoIterator<Item = Vec3>) -> Option<Bounds> {
        let mut bounds: Option<Bounds> = None;
        for p in points {
            if !p.is_finite() {
                return None;
            }
            bounds = Some(match bounds {
                Some(b) => Bounds {
                    min: b.min.min(p),
                    max: b.max.max(p),
                },
                None => Bounds { min: p, max: p },
            });
        }
        bounds
    }

    /// The smallest bounds holding both.
    pub fn union(self, other: Bounds) -> Bounds {
        Bounds {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Centre of the box.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Radius of the sphere around the box (at least 1 mm).
    pub fn radius(&self) -> f32 {
        ((self.max - self.min).length() * 0.5).max(1e-3)
    }
}

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (m).
    pub position: Vec3,
    /// Point looked at (m).
    pub target: Vec3,
    /// Vertical field of view (degrees).
    pub fov_y_degrees: f32,
}

/// Default vertical field of view (degrees).
pub const DEFAULT_FOV_DEGREES: f32 = 40.0;

impl Camera {
    /// A camera in front of the scene, a little above and to the right,
    /// far enough back that the bounding sphere of `bounds` fills the view
    /// of aspect ratio `aspect` (width over height).
    pub fn framing(bounds: &Bounds, aspect: f32) -> Camera {
        let fov_y = DEFAULT_FOV_DEGREES.to_radians();
        let fov_x = 2.0 * ((fov_y * 0.5).tan() * aspect).atan();
        let half = fov_y.min(fov_x) * 0.5;
        let distance = bounds.radius() / half.sin() * 0.95;
        let direction = Vec3::new(0.45, 0.5, 1.0).normalize();
        Camera {
            position: bounds.center() + direction * distance,
            target: bounds.center(),
            fov_y_degrees: DEFAULT_FOV_DEGREES,
        }
    }

    /// World to clip space (depth 0 to 1) for an image of aspect ratio
    /// `aspect`, with near and far planes around a scene of `radius` metres.
    pub fn view_proj(&self, aspect: f32, radius: f32) -> Mat4 {
        let forward = self.target - self.position;
        let distance = forward.length().max(1e-4);
        let up = if forward.normalize_or_zero().y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let near = (distance * 0.01).max(1e-3);
        let far = distance + radius * 60.0;
        let proj = Mat4::perspective_rh(self.fov_y_degrees.to_radians(), aspect, near, far);
        proj * Mat4::look_at_rh(self.position, self.target, up)
    }
}

/// Where the point `p` lands in a `width` x `height` image drawn with
/// `view_proj` (pixels from the top-left corner); `None` behind the camera.
pub fn project(view_proj: &Mat4, p: Vec3, width: u32, height: u32) -> Option<Vec2> {
    let clip = *view_proj * p.extend(1.0);
    (clip.w > 0.0).then(|| {
        let ndc = clip.truncate() / clip.w;
        Vec2::new(
            (ndc.x * 0.5 + 0.5) * width as f32,
            (0.5 - ndc.y * 0.5) * height as f32,
        )
    })
}

/// A directional light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Direction the light travels (from the light into the scene).
    pub direction: Vec3,
    /// Colour times intensity (linear RGB).
    pub color: Vec3,
}

impl Default for Light {
    fn default() -> Self {
        Light {
            direction: Vec3::new(-0.35, -1.0, -0.3).normalize(),
            color: Vec3::splat(0.9),
        }
    }
}

impl Light {
    /// World to light clip space for the shadow map: an orthographic box
    /// along the light that holds a sphere of `radius` around `center`
    /// with room for the ground around it.
    pub fn view_proj(&self, center: Vec3, radius: f32) -> Mat4 {
        let to_light = -self.direction.normalize_or(Vec3::NEG_Y);
        let up = if to_light.y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let extent = radius * 1.6;
        let eye = center + to_light * radius * 4.0;
        Mat4::orthographic_rh(-extent, extent, -extent, extent, radius * 0.5, radius * 8.0)
            * Mat4::look_at_rh(eye, center, up)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn framing_puts_the_scene_in_the_middle_of_the_picture() {
        let bounds = Bounds::of([Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 1.0, 1.0)]).unwrap();
        let camera = Camera::framing(&bounds, 1.5);
        let vp = camera.view_proj(1.5, bounds.radius());
        let centre = project(&vp, bounds.center(), 300, 200).unwrap();
        assert!(centre.distance(Vec2::new(150.0, 100.0)) < 1e-3, "{centre}");
        for corner in [bounds.min, bounds.max] {
            let p = project(&vp, corner, 300, 200).unwrap();
            assert!(
                (0.0..300.0).contains(&p.x) && (0.0..200.0).contains(&p.y),
                "{p}"
            );
        }
        assert!(Bounds::of([Vec3::NAN]).is_none());
    }
}
