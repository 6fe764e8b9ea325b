//! Legends over the 3D view: the strain colour map's range and the current
//! maximum, or the colours of the constraint kinds.

use eframe::egui;
use pleat_render::{Renderer, View};

/// Draws the legend of `view` in the bottom-left corner of `rect`.
/// `max_stretch` is the state's largest edge stretch (the probe measures it).
pub fn draw(ui: &egui::Ui, rect: egui::Rect, view: View, renderer: &Renderer, max_stretch: f32) {
    let painter = ui.painter_at(rect);
    let corner = rect.left_bottom() + egui::vec2(12.0, -12.0);
    let font = egui::FontId::proportional(13.0);
    let text = egui::Color32::WHITE;
    match view {
        View::Strain => {
            let range = renderer.strain_range();
            let (width, height) = (160.0, 12.0);
            let bar = egui::Rect::from_min_size(
                corner - egui::vec2(0.0, height),
                egui::vec2(width, height),
            );
            let steps = 32;
            for k in 0..steps {
                let t = k as f32 / steps as f32;
                let cell = egui::Rect::from_min_size(
                    bar.min + egui::vec2(t * width, 0.0),
                    egui::vec2(width / steps as f32 + 0.5, height),
                );
                painter.rect_filled(cell, 0.0, strain_color(t));
            }
            let max = max_stretch - 1.0;
            painter.text(
                bar.left_top() - egui::vec2(0.0, 4.0),
                egui::Align2::LEFT_BOTTOM,
                format!(
                    "strain 0 to {:.1} %   (max {:.2} %)",
                    range * 100.0,
                    max * 100.0
                ),
                font,
                text,
            );
        }
        View::Constraints => {
            let kinds = renderer.constraint_kinds();
            for (k, (name, rgb)) in kinds.iter().rev().enumerate() {
                let at = corner - egui::vec2(0.0, 18.0 * k as f32);
                let color: egui::Color32 = egui::Rgba::from_rgb(rgb[0], rgb[1], rgb[2]).into();
                painter.rect_filled(
                    egui::Rect::from_min_size(at - egui::vec2(0.0, 12.0), egui::vec2(12.0, 12.0)),
                    2.0,
                    color,
                );
                painter.text(
                    at + egui::vec2(18.0, 0.0),
                    egui::Align2::LEFT_BOTTOM,
                    *name,
                    font.clone(),
                    text,
                );
            }
        }
        _ => {}
    }
}

/// The strain map's colour at `t` (blue 0 through cyan, green and yellow
/// to red 1), as common.wgsl of pleat-render draws it.
fn strain_color(t: f32) -> egui::Color32 {
    let x = t.clamp(0.0, 1.0) * 4.0;
    let r = (x - 2.0).clamp(0.0, 1.0);
    let g = x.clamp(0.0, 1.0) - (x - 3.0).clamp(0.0, 1.0);
    let b = 1.0 - (x - 1.0).clamp(0.0, 1.0);
    egui::Rgba::from_rgb(r, g, b).into()
}
