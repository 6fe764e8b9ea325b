//! The view where the adapter has no compute shaders (WebGL in a browser
//! without WebGPU): the cloth drawn with egui's painter, triangles sorted
//! back to front and shaded flat by a directional light, both sides coloured
//! as pleat-render colours them, over a ground grid. Colliders are not drawn.

use crate::orbit::Projection;
use crate::session::Session;
use eframe::egui;
use glam::Vec3;

/// Direction the light comes from.
const LIGHT: Vec3 = Vec3::new(0.4, 1.0, 0.6);
/// Half the ground grid's width (m) and its line spacing.
const GROUND_HALF: f32 = 2.0;
const GROUND_STEP: f32 = 0.25;

/// Draws the ground grid and the session's cloth.
pub fn draw(painter: &egui::Painter, projection: &Projection, session: &Session) {
    painter.rect_filled(painter.clip_rect(), 0.0, egui::Color32::from_gray(40));
    ground(painter, projection);
    painter.add(egui::Shape::mesh(cloth_mesh(projection, session)));
}

fn ground(painter: &egui::Painter, projection: &Projection) {
    let stroke = egui::Stroke::new(1.0, egui::Color32::from_gray(70));
    let steps = (2.0 * GROUND_HALF / GROUND_STEP) as i32;
    for k in 0..=steps {
        let t = -GROUND_HALF + k as f32 * GROUND_STEP;
        for (a, b) in [
            (
                Vec3::new(t, 0.0, -GROUND_HALF),
                Vec3::new(t, 0.0, GROUND_HALF),
            ),
            (
                Vec3::new(-GROUND_HALF, 0.0, t),
                Vec3::new(GROUND_HALF, 0.0, t),
            ),
        ] {
            if let (Some(a), Some(b)) = (projection.to_screen(a), projection.to_screen(b)) {
                painter.line_segment([a, b], stroke);
            }
        }
    }
}

/// The cloth's triangles, farthest first, each one flat colour.
fn cloth_mesh(projection: &Projection, session: &Session) -> egui::Mesh {
    let x = &session.sim.particles.x;
    let paper = session.is_paper();
    let (front, back) = if paper {
        ([245, 242, 235], [217, 77, 64])
    } else {
        ([204, 56, 46], [235, 219, 189])
    };
    let eye = projection.eye();
    let light = LIGHT.normalize();
    let mut faces: Vec<(f32, [egui::Pos2; 3], egui::Color32)> = session
        .sim
        .model
        .triangles
        .iter()
        .filter_map(|&[a, b, c]| {
            let [pa, pb, pc] = [a, b, c].map(|i| x[i as usize]);
            let normal = (pb - pa).cross(pc - pa).normalize_or_zero();
            let centre = (pa + pb + pc) / 3.0;
            let facing = normal.dot(eye - centre) >= 0.0;
            let (base, n) = if facing {
                (front, normal)
            } else {
                (back, -normal)
            };
            let shade = 0.35 + 0.65 * n.dot(light).max(0.0);
            let color = egui::Color32::from_rgb(
                (base[0] as f32 * shade) as u8,
                (base[1] as f32 * shade) as u8,
                (base[2] as f32 * shade) as u8,
            );
            let corners = [
                projection.to_screen(pa)?,
                projection.to_screen(pb)?,
                projection.to_screen(pc)?,
            ];
            Some((projection.depth(centre), corners, color))
        })
        .collect();
    faces.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut mesh = egui::Mesh::default();
    for (_, corners, color) in faces {
        let start = mesh.vertices.len() as u32;
        for pos in corners {
            mesh.colored_vertex(pos, color);
        }
        mesh.add_triangle(start, start + 1, start + 2);
    }
    mesh
}
