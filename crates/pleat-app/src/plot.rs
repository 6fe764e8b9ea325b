//! A live plot of the run's health: max stretch and kinetic energy over the
//! last seconds, each scaled to its own range.

use eframe::egui;
use std::collections::VecDeque;

/// Samples kept (ten seconds at 60 frames per second).
const SAMPLES: usize = 600;

/// Recent values of max stretch and kinetic energy.
#[derive(Default)]
pub struct History {
    samples: VecDeque<(f32, f32)>,
}

impl History {
    /// Adds one frame's values.
    pub fn push(&mut self, max_stretch: f32, energy: f32) {
        if self.samples.len() == SAMPLES {
            self.samples.pop_front();
        }
        self.samples.push_back((max_stretch, energy));
    }

    /// Forgets everything (a new scene).
    pub fn clear(&mut self) {
        self.samples.clear();
    }

    /// Draws both series in a strip as wide as `ui`.
    pub fn show(&self, ui: &mut egui::Ui) {
        let (rect, _) =
            ui.allocate_exact_size(egui::vec2(ui.available_width(), 90.0), egui::Sense::hover());
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 2.0, ui.visuals().extreme_bg_color);
        let stretch = egui::Color32::from_rgb(230, 120, 60);
        let energy = egui::Color32::from_rgb(90, 170, 240);
        self.series(&painter, rect, |s| s.0, stretch);
        self.series(&painter, rect, |s| s.1, energy);
        if let Some(&(s, e)) = self.samples.back() {
            let font = egui::FontId::monospace(11.0);
            painter.text(
                rect.left_top() + egui::vec2(4.0, 2.0),
                egui::Align2::LEFT_TOP,
                format!("max stretch {s:.4}"),
                font.clone(),
                stretch,
            );
            painter.text(
                rect.left_top() + egui::vec2(4.0, 16.0),
                egui::Align2::LEFT_TOP,
                format!("energy {e:.3e} J"),
                font,
                energy,
            );
        }
    }

    fn series(
        &self,
        painter: &egui::Painter,
        rect: egui::Rect,
        value: impl Fn(&(f32, f32)) -> f32,
        color: egui::Color32,
    ) {
        let values: Vec<f32> = self
            .samples
            .iter()
            .map(value)
            .filter(|v| v.is_finite())
            .collect();
        let (lo, hi) = values
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        if values.len() < 2 {
            return;
        }
        let span = (hi - lo).max(1e-9);
        let points = values
            .iter()
            .enumerate()
            .map(|(k, v)| {
                let x = rect.left() + rect.width() * k as f32 / (SAMPLES - 1) as f32;
                let y = rect.bottom() - 4.0 - (rect.height() - 34.0) * (v - lo) / span;
                egui::pos2(x, y)
            })
            .collect();
        painter.add(egui::Shape::line(points, egui::Stroke::new(1.5, color)));
    }
}
