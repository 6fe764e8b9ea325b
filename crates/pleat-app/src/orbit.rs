//! An orbiting camera: yaw and pitch around a target, a distance, the rays
//! through the picture that picking and dragging follow, and where it draws
//! world points on a view's rectangle ([`Projection`]).

use eframe::egui;
use glam::{Mat4, Vec2, Vec3, Vec4Swizzles};
use pleat_render::Camera;

/// Steepest pitch (radians): the camera never looks straight down, and
/// stays below asin(0.99), where `Camera::view_proj` changes its up vector.
const MAX_PITCH: f32 = 1.4;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    pub target: Vec3,
    pub yaw: f32,
    pub pitch: f32,
    pub distance: f32,
    pub fov_y_degrees: f32,
}

impl From<Camera> for Orbit {
    fn from(camera: Camera) -> Self {
        let offset = camera.position - camera.target;
        let distance = offset.length().max(1e-3);
        Orbit {
            target: camera.target,
            yaw: offset.x.atan2(offset.z),
            pitch: (offset.y / distance).clamp(-1.0, 1.0).asin(),
            distance,
            fov_y_degrees: camera.fov_y_degrees,
        }
    }
}

impl Orbit {
    /// The camera this orbit places.
    pub fn camera(&self) -> Camera {
        let direction = Vec3::new(
            self.pitch.cos() * self.yaw.sin(),
            self.pitch.sin(),
            self.pitch.cos() * self.yaw.cos(),
        );
        Camera {
            position: self.target + direction * self.distance,
            target: self.target,
            fov_y_degrees: self.fov_y_degrees,
        }
    }

    /// Turns around the target (radians).
    pub fn rotate(&mut self, yaw: f32, pitch: f32) {
        self.yaw -= yaw;
        self.pitch = (self.pitch + pitch).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Moves the target across the view by fractions of the view's height.
    pub fn pan(&mut self, right: f32, up: f32) {
        let camera = self.camera();
        let forward = (camera.target - camera.position).normalize();
        let side = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        let above = side.cross(forward);
        let height = 2.0 * self.distance * (self.fov_y_degrees.to_radians() * 0.5).tan();
        self.target += (-side * right + above * up) * height;
    }

    /// Multiplies the distance (below 1 comes closer).
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).clamp(1e-3, 1e4);
        }
    }

    /// The ray (origin, unit direction) through `uv` (0 to 1 from the
    /// picture's top-left corner) of a picture of aspect ratio `aspect`.
    pub fn ray(&self, uv: Vec2, aspect: f32) -> (Vec3, Vec3) {
        let camera = self.camera();
        let inverse: Mat4 = camera.view_proj(aspect, self.distance).inverse();
        let ndc = Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
        let unproject = |z: f32| {
            let p = inverse * ndc.extend(z).extend(1.0);
            p.xyz() / p.w
        };
        let (near, far) = (unproject(0.0), unproject(1.0));
        (camera.position, (far - near).normalize_or(Vec3::NEG_Z))
    }
}

/// Where the orbit's camera draws world points on the view's rectangle.
pub struct Projection {
    orbit: Orbit,
    view_proj: Mat4,
    rect: egui::Rect,
}

impl Projection {
    pub fn new(orbit: Orbit, rect: egui::Rect) -> Self {
        // Near and far planes do not move points across the screen.
        let view_proj = orbit
            .camera()
            .view_proj(rect.aspect_ratio(), orbit.distance);
        Projection {
            orbit,
            view_proj,
            rect,
        }
    }

    /// The window point where `p` is drawn; `None` behind the camera.
    pub fn to_screen(&self, p: Vec3) -> Option<egui::Pos2> {
        let clip = self.view_proj * p.extend(1.0);
        (clip.w > 1e-6).then(|| {
            let ndc = clip.truncate() / clip.w;
            egui::pos2(
                self.rect.left() + (ndc.x * 0.5 + 0.5) * self.rect.width(),
                self.rect.top() + (0.5 - ndc.y * 0.5) * self.rect.height(),
            )
        })
    }

    /// Distance of `p` in front of the camera (m).
    pub fn depth(&self, p: Vec3) -> f32 {
        (self.view_proj * p.extend(1.0)).w
    }

    /// The camera's position and the direction of the ray through `pos`.
    pub fn ray(&self, pos: egui::Pos2) -> (Vec3, Vec3) {
        let uv = (pos - self.rect.min) / self.rect.size();
        self.orbit
            .ray(Vec2::new(uv.x, uv.y), self.rect.aspect_ratio())
    }

    /// The camera's position.
    pub fn eye(&self) -> Vec3 {
        self.orbit.camera().position
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pleat_render::project;

    fn orbit() -> Orbit {
        Orbit::from(Camera {
            position: Vec3::new(1.0, 2.0, 3.0),
            target: Vec3::new(0.0, 0.5, 0.0),
            fov_y_degrees: 40.0,
        })
    }

    #[test]
    fn a_camera_round_trips_through_the_orbit() {
        let camera = orbit().camera();
        assert!((camera.position - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-5);
    }

    #[test]
    fn the_ray_through_a_projected_point_passes_through_it() {
        let o = orbit();
        let (w, h) = (800, 600);
        let view_proj = o.camera().view_proj(w as f32 / h as f32, o.distance);
        let p = Vec3::new(0.3, 0.2, -0.4);
        let pixel = project(&view_proj, p, w, h).unwrap();
        let (origin, direction) = o.ray(pixel / Vec2::new(w as f32, h as f32), w as f32 / h as f32);
        let along = (p - origin).dot(direction);
        assert!((origin + direction * along - p).length() < 1e-4);
    }

    #[test]
    fn zoom_and_pan_move_as_asked() {
        let mut o = orbit();
        let d = o.distance;
        o.zoom(0.5);
        assert!((o.distance - d * 0.5).abs() < 1e-5);
        o.zoom(f32::NAN);
        assert!((o.distance - d * 0.5).abs() < 1e-5);
        let target = o.target;
        o.pan(0.1, 0.0);
        assert!((o.target - target).length() > 0.0);
        o.rotate(0.0, 10.0);
        assert!(o.pitch <= MAX_PITCH);
    }
}
