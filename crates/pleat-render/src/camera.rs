//! The camera and the light: framing the scene by default (and folded
//! paper face-on, along the way most of its area faces), the
//! projection both the GPU and the tests use, and the light's shadow-map
//! projection.

use glam::{Mat3, Mat4, Vec2, Vec3};

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

/// The direction, from the scene, of the default camera: in front, a
/// little above and to the right. Face-on framing keeps to its side of
/// the paper and tilts towards it.
pub const DEFAULT_VIEW_DIRECTION: Vec3 = Vec3::new(0.45, 0.5, 1.0);

/// How far a face-on view tilts from the paper's normal (radians, 22
/// degrees): enough to read as 3-D, little enough to see every layer.
pub const FACE_ON_TILT: f32 = 0.384;

/// An area facing the current view axis within this factor of the most
/// facing any way keeps the axis (hysteresis: the view does not flip
/// between two nearly equal ways from one picture to the next).
const AXIS_HYSTERESIS: f32 = 1.5;

/// The principal axes of the faces' normals, weighted by area: the
/// eigenvectors of `sum(area * n n^T)` over the triangles of `points`, with
/// its eigenvalues (the area facing each way), from the most facing to the
/// least. A flat sheet, folded flat or not, faces along its normal with all
/// of its area. `None` for no triangle with an area, or a point that is not
/// finite.
pub fn facing_axes(points: &[Vec3], triangles: &[[u32; 3]]) -> Option<[(Vec3, f32); 3]> {
    let mut c = [[0.0f32; 3]; 3];
    let mut total = 0.0;
    for t in triangles {
        let [a, b, d] = t.map(|i| points.get(i as usize).copied().unwrap_or(Vec3::NAN));
        let twice_area = (b - a).cross(d - a);
        let length = twice_area.length();
        if !length.is_finite() {
            return None;
        }
        if length == 0.0 {
            continue;
        }
        total += length;
        let n = twice_area.to_array();
        for (i, row) in c.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v += n[i] * n[j] / length;
            }
        }
    }
    if total == 0.0 {
        return None;
    }
    let (values, vectors) = symmetric_eigen(c);
    let mut axes = [0, 1, 2].map(|i| (vectors.col(i).normalize_or(Vec3::Z), values[i]));
    axes.sort_by(|a, b| b.1.total_cmp(&a.1));
    Some(axes)
}

/// Eigenvalues and eigenvectors (columns) of the symmetric matrix `a` by
/// cyclic Jacobi rotations.
fn symmetric_eigen(mut a: [[f32; 3]; 3]) -> ([f32; 3], Mat3) {
    let mut v = [[1.0f32, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale = (0..3)
        .map(|i| a[i][i].abs())
        .sum::<f32>()
        .max(f32::MIN_POSITIVE);
    for _sweep in 0..32 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off <= scale * 1e-9 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() <= f32::MIN_POSITIVE {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let cos = 1.0 / (t * t + 1.0).sqrt();
            let sin = t * cos;
            for row in &mut a {
                let (akp, akq) = (row[p], row[q]);
                row[p] = cos * akp - sin * akq;
                row[q] = sin * akp + cos * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            a[p] = [0, 1, 2].map(|k| cos * rp[k] - sin * rq[k]);
            a[q] = [0, 1, 2].map(|k| sin * rp[k] + cos * rq[k]);
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = cos * vp - sin * vq;
                row[q] = sin * vp + cos * vq;
            }
        }
    }
    let columns = Mat3::from_cols_array_2d(&v).transpose();
    ([a[0][0], a[1][1], a[2][2]], columns)
}

/// The up vector [`Camera::view_proj`] uses when looking along `forward`.
fn up_for(forward: Vec3) -> Vec3 {
    if forward.normalize_or_zero().y.abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}

/// The axis a face-on view of the paper (`points` and its `triangles`)
/// looks along (from the paper to the eye, not yet tilted): the way most of
/// its area faces ([`facing_axes`]), on the side of
/// [`DEFAULT_VIEW_DIRECTION`] (a stable sign). With `previous` (the axis of
/// the last picture), that axis is kept while the area facing it stays
/// within [`AXIS_HYSTERESIS`] of the most. `None` as for [`facing_axes`].
pub fn face_on_axis(
    points: &[Vec3],
    triangles: &[[u32; 3]],
    previous: Option<Vec3>,
) -> Option<Vec3> {
    let axes = facing_axes(points, triangles)?;
    let most = axes[0];
    let axis = previous
        .and_then(|prev| {
            let kept = axes
                .iter()
                .max_by(|a, b| a.0.dot(prev).abs().total_cmp(&b.0.dot(prev).abs()))?;
            (kept.1 * AXIS_HYSTERESIS >= most.1).then_some(kept.0)
        })
        .unwrap_or(most.0);
    let side = DEFAULT_VIEW_DIRECTION.normalize();
    let facing = axis.dot(side);
    Some(if facing < 0.0 || (facing == 0.0 && axis.y < 0.0) {
        -axis
    } else {
        axis
    })
}

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

    /// A camera looking at `points` face-on: from the side of `axis` (from
    /// [`face_on_axis`]), tilted [`FACE_ON_TILT`] towards
    /// [`DEFAULT_VIEW_DIRECTION`] so the picture reads as 3-D, its target
    /// the middle of the points as seen from there and back just far enough
    /// that every point lies in the view of aspect ratio `aspect` (with a
    /// 5 % margin). `None` for no points or one that is not finite.
    pub fn facing(points: &[Vec3], axis: Vec3, aspect: f32) -> Option<Camera> {
        if points.is_empty() || points.iter().any(|p| !p.is_finite()) || !axis.is_finite() {
            return None;
        }
        let axis = axis.normalize_or(Vec3::Z);
        let side = DEFAULT_VIEW_DIRECTION.normalize();
        let across = (side - axis * side.dot(axis)).normalize_or_zero();
        let across = if across == Vec3::ZERO {
            axis.any_orthonormal_vector()
        } else {
            across
        };
        let to_eye = (axis * FACE_ON_TILT.cos() + across * FACE_ON_TILT.sin()).normalize();
        let forward = -to_eye;
        let right = forward.cross(up_for(forward)).normalize();
        let up = right.cross(forward);
        // The points' extent in the view's axes.
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in points {
            let v = Vec3::new(p.dot(right), p.dot(up), p.dot(to_eye));
            lo = lo.min(v);
            hi = hi.max(v);
        }
        let mid = (lo + hi) * 0.5;
        let target = right * mid.x + up * mid.y + to_eye * mid.z;
        let tan_y = (DEFAULT_FOV_DEGREES.to_radians() * 0.5).tan() / 1.05;
        let tan_x = tan_y * aspect;
        // Each point needs the eye at least this far from the target's plane.
        let mut distance = ((hi - lo).length() * 0.5).max(1e-3);
        for p in points {
            let v = Vec3::new(p.dot(right), p.dot(up), p.dot(to_eye)) - mid;
            distance = distance
                .max(v.z + v.x.abs() / tan_x)
                .max(v.z + v.y.abs() / tan_y);
        }
        Some(Camera {
            position: target + to_eye * distance,
            target,
            fov_y_degrees: DEFAULT_FOV_DEGREES,
        })
    }

    /// World to clip space (depth 0 to 1) for an image of aspect ratio
    /// `aspect`, with near and far planes around a scene of `radius` metres.
    pub fn view_proj(&self, aspect: f32, radius: f32) -> Mat4 {
        let forward = self.target - self.position;
        let distance = forward.length().max(1e-4);
        let up = up_for(forward);
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

    /// A flat-folded sheet: points scattered over a square in a plane
    /// tilted arbitrarily, a few layers a paper's thickness apart, and
    /// triangles joining them three by three.
    fn flat_folded_sheet(normal: Vec3, offset: Vec3) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        let mut state = 12345u32;
        let mut random = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32 - 0.5
        };
        let points = (0..400)
            .map(|_| offset + u * 0.3 * random() + v * 0.2 * random() + normal * 0.002 * random())
            .collect();
        (
            points,
            (0..133).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect(),
        )
    }

    #[test]
    fn framing_a_flat_folded_sheet_looks_along_its_normal_and_holds_every_point() {
        for (normal, offset) in [
            (Vec3::new(0.3, -0.8, 0.5), Vec3::new(1.0, 2.0, -3.0)),
            (Vec3::new(-1.0, 0.1, 0.05), Vec3::ZERO),
            (Vec3::Y, Vec3::new(0.0, 0.5, 0.0)),
            (Vec3::Z, Vec3::ZERO),
        ] {
            let normal = normal.normalize();
            let (points, triangles) = flat_folded_sheet(normal, offset);
            let axis = face_on_axis(&points, &triangles, None).unwrap();
            assert!(axis.dot(normal).abs() > 0.999, "{axis} for {normal}");
            assert!(axis.dot(DEFAULT_VIEW_DIRECTION) >= 0.0, "sign: {axis}");
            let (w, h) = (640, 480);
            let aspect = w as f32 / h as f32;
            let camera = Camera::facing(&points, axis, aspect).unwrap();
            let forward = (camera.target - camera.position).normalize();
            let off_normal = forward.dot(-axis).clamp(-1.0, 1.0).acos();
            assert!(
                (off_normal - FACE_ON_TILT).abs() < 1e-3,
                "looks {} degrees off the normal",
                off_normal.to_degrees()
            );
            let vp = camera.view_proj(aspect, 1.0);
            let mut span = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
            for p in &points {
                let clip = vp * p.extend(1.0);
                let ndc = clip.truncate() / clip.w;
                assert!(
                    clip.w > 0.0 && ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0,
                    "{ndc}"
                );
                assert!((0.0..=1.0).contains(&ndc.z), "depth {}", ndc.z);
                let px = project(&vp, *p, w, h).unwrap();
                span = (span.0.min(px), span.1.max(px));
            }
            // Face-on, the sheet fills the picture rather than a sliver.
            let size = span.1 - span.0;
            assert!(size.x > 0.6 * w as f32 || size.y > 0.6 * h as f32, "{size}");
            assert!(size.x > 0.3 * w as f32 && size.y > 0.3 * h as f32, "{size}");
        }
    }

    /// A right triangle of legs `a` and `b` from `origin`, appended to `points`.
    fn right_triangle(points: &mut Vec<Vec3>, origin: Vec3, a: Vec3, b: Vec3) -> [u32; 3] {
        let i = points.len() as u32;
        points.extend([origin, origin + a, origin + b]);
        [i, i + 1, i + 2]
    }

    #[test]
    fn the_face_on_axis_keeps_its_choice_between_near_equal_areas() {
        // 1.0 of area faces x, 1.2 faces z.
        let mut points = Vec::new();
        let triangles = [
            right_triangle(&mut points, Vec3::ZERO, Vec3::Y, Vec3::Z * 2.0),
            right_triangle(&mut points, Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 1.2),
        ];
        let fresh = face_on_axis(&points, &triangles, None).unwrap();
        assert!(fresh.dot(Vec3::Z).abs() > 0.99, "{fresh}");
        let kept = face_on_axis(&points, &triangles, Some(Vec3::X)).unwrap();
        assert!(kept.dot(Vec3::X).abs() > 0.99, "{kept}");
        assert!(face_on_axis(&[], &[], None).is_none());
        assert!(
            face_on_axis(&points, &[[0, 0, 1]], None).is_none(),
            "no area"
        );
        assert!(face_on_axis(&[Vec3::NAN; 3], &[[0, 1, 2]], None).is_none());
        assert!(Camera::facing(&[Vec3::NAN], Vec3::Z, 1.0).is_none());
    }

    #[test]
    fn a_long_strip_folded_in_layers_is_seen_across_its_layers() {
        // A strip 1 m long and 2 cm wide folded flat in three layers 3 cm
        // apart (Rabbit Ear's two-bird pattern ends so): its points spread
        // least across its width, which would show it edge-on; its faces
        // all face along the layers' normal.
        let (along, across, normal) =
            (Vec3::X, Vec3::new(0.0, 0.6, 0.8), Vec3::new(0.0, 0.8, -0.6));
        let mut points = Vec::new();
        let mut triangles = Vec::new();
        for layer in 0..3 {
            for k in 0..10 {
                let origin = along * (k as f32 * 0.1) + normal * (layer as f32 * 0.03);
                triangles.push(right_triangle(
                    &mut points,
                    origin,
                    along * 0.1,
                    across * 0.02,
                ));
            }
        }
        let axis = face_on_axis(&points, &triangles, None).unwrap();
        assert!(axis.dot(normal).abs() > 0.999, "looks along {axis}");
    }
}
