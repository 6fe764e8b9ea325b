//! The side panel: demo and pattern menus, play / pause / step / reset,
//! backend, view, every parameter of [`crate::params`], timings, the live
//! plot and export.

use crate::app::{Command, PleatApp};
use crate::demos::{pattern_choices, DEMOS};
use crate::params::{Section, PARAMS};
use crate::session::{BackendChoice, Pending};
use eframe::egui;
use pleat::solver::SolverKind;
use pleat_render::View;

impl PleatApp {
    /// Draws the side panel's contents; changes the app or queues commands.
    pub(crate) fn side_panel(&mut self, ui: &mut egui::Ui) {
        let app = self;
        // Both ways: a long label on a narrow panel scrolls, never cut off.
        egui::ScrollArea::both().show(ui, |ui| {
            ui.heading("pleat");
            scene_menus(ui, app);
            ui.separator();
            transport(ui, app);
            ui.separator();
            backend_and_view(ui, app);
            for (section, title) in [
                (Section::Solver, "Solver"),
                (Section::Material, "Material"),
                (Section::Paper, "Paper"),
                (Section::Contact, "Contact"),
                (Section::Forces, "Gravity and wind"),
                (Section::Fold, "Fold"),
            ] {
                parameters(ui, app, section, title);
            }
            ui.separator();
            statistics(ui, app);
            ui.separator();
            ui.horizontal(|ui| {
                if ui.button("Export OBJ").clicked() {
                    app.commands.push(Command::Export("obj"));
                }
                if ui.button("Export glb").clicked() {
                    app.commands.push(Command::Export("glb"));
                }
            });
            ui.small("Drop a scene (.json), a mesh (.obj) or a crease pattern (.cp, .fold, .svg) on the window.");
        });
    }
}

fn scene_menus(ui: &mut egui::Ui, app: &mut PleatApp) {
    let current = app.demo.map_or("(dropped file)", |d| d.title);
    egui::ComboBox::from_label("demo")
        .selected_text(current)
        .width(180.0)
        .show_ui(ui, |ui| {
            for demo in DEMOS {
                if ui
                    .selectable_label(app.demo == Some(demo), demo.title)
                    .clicked()
                {
                    app.commands.push(Command::Demo(demo.id.to_string()));
                }
            }
        });
    if app.demo.is_some_and(|d| d.id == "fold") {
        let label = app
            .pattern
            .map_or("(scene's own)".to_string(), |p| p.label());
        egui::ComboBox::from_label("pattern")
            .selected_text(label)
            .width(180.0)
            .show_ui(ui, |ui| {
                for choice in pattern_choices() {
                    if ui
                        .selectable_label(app.pattern == Some(choice), choice.label())
                        .clicked()
                    {
                        app.commands.push(Command::Pattern(choice));
                    }
                }
            });
    }
    if let Some(session) = &app.session {
        ui.label(format!("scene: {}", session.scene.name));
    }
}

fn transport(ui: &mut egui::Ui, app: &mut PleatApp) {
    ui.horizontal(|ui| {
        let label = if app.playing { "Pause" } else { "Play" };
        if ui.button(label).clicked() {
            app.playing = !app.playing;
        }
        if ui.button("Step").clicked() {
            app.commands.push(Command::Step);
        }
        if ui.button("Reset").clicked() {
            app.commands.push(Command::Reset);
        }
    });
}

fn backend_and_view(ui: &mut egui::Ui, app: &mut PleatApp) {
    let Some(session) = &mut app.session else {
        return;
    };
    ui.horizontal(|ui| {
        ui.label("backend");
        for choice in BackendChoice::ALL {
            if ui
                .selectable_label(session.backend == choice, choice.name())
                .clicked()
                && session.backend != choice
            {
                session.request(Pending::Backend(choice));
                // The person's choice ends the trial of both.
                app.trial = None;
            }
        }
    });
    if app.trial.is_some() {
        let verdict = app.probe.backend_pick.as_deref();
        ui.label(verdict.unwrap_or("timing both backends on this scene..."));
    }
    ui.label(format!("device: {}", session.sim.device()));
    if let Some(dispatches) = session.sim.backend().dispatches_per_frame() {
        // A small sheet's frame runs in one workgroup: a handful of dispatches.
        ui.label(format!("GPU dispatches a frame: {dispatches}"));
    }
    if let Some(notice) = &session.notice {
        ui.colored_label(egui::Color32::from_rgb(230, 180, 60), notice);
    }
    let kind = session.sim.settings.kind;
    egui::ComboBox::from_label("solver")
        .selected_text(kind.name())
        .show_ui(ui, |ui| {
            for k in SolverKind::ALL {
                if ui.selectable_label(kind == k, k.name()).clicked() && kind != k {
                    session.scene.solver.kind = k;
                    session.sim.settings.kind = k;
                    session.request(Pending::Rebuild);
                }
            }
        });
    let mut self_collision = session.scene.solver.self_collision.enabled;
    if ui.checkbox(&mut self_collision, "self-collision").changed() {
        session.scene.solver.self_collision.enabled = self_collision;
        session.request(Pending::Rebuild);
    }
    egui::ComboBox::from_label("view")
        .selected_text(app.viewport.view.to_string())
        .show_ui(ui, |ui| {
            for (name, view) in View::ALL {
                ui.selectable_value(&mut app.viewport.view, view, name);
            }
        });
}

fn parameters(ui: &mut egui::Ui, app: &mut PleatApp, section: Section, title: &str) {
    let Some(session) = &mut app.session else {
        return;
    };
    let shown: Vec<_> = PARAMS
        .iter()
        .filter(|p| p.section == section)
        .filter_map(|p| (p.get)(session).map(|v| (p, v)))
        .collect();
    if shown.is_empty() {
        return;
    }
    egui::CollapsingHeader::new(title)
        .default_open(true)
        .show(ui, |ui| {
            for (param, value) in shown {
                let mut edited = value;
                // Values outside the range (a scene may have them) stay until edited.
                let slider = egui::Slider::new(&mut edited, param.min..=param.max)
                    .logarithmic(param.logarithmic)
                    .clamping(egui::SliderClamping::Edits)
                    .text(param.label);
                let slider = if param.integer {
                    slider.integer()
                } else {
                    slider.custom_formatter(|v, _| format_value(v))
                };
                // A change that rebuilds waits for the slider's release.
                let response = ui.add(slider);
                if response.changed() && edited != value {
                    param.apply(session, edited, !response.dragged());
                } else if response.drag_stopped() {
                    param.apply(session, value, true);
                }
            }
        });
}

/// Short numbers for values that span decades (1e-6, 0.25, 120).
fn format_value(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-2 || v.abs() >= 1e4) {
        format!("{v:.2e}")
    } else {
        format!("{v:.3}")
    }
}

fn statistics(ui: &mut egui::Ui, app: &mut PleatApp) {
    let probe = &app.probe;
    // Two short lines: a narrow panel shows them whole.
    ui.label(format!("drawn {:.0} fps, frame {}", probe.fps, probe.frame));
    ui.label(format!(
        "simulated {:.1} steps/s ({:.2} x real time)",
        probe.steps_per_second, probe.sim_speed
    ));
    let Some(session) = &app.session else { return };
    ui.label(format!(
        "{} particles, {} constraints",
        session.sim.particles.len(),
        session.sim.constraint_count()
    ));
    if let Some(frames) = app.stage_frames.filter(|&n| n > 0) {
        let per_frame = |d: std::time::Duration| d.as_secs_f64() * 1e3 / frames as f64;
        let st = &app.stage_window;
        egui::Grid::new("stages").show(ui, |ui| {
            for (name, time) in [
                ("forces", st.forces),
                ("predict", st.predict),
                ("constraints", st.constraints),
                ("collisions", st.collisions),
                ("self-collision", st.self_collision),
            ] {
                ui.label(name);
                ui.label(format!("{:.2} ms", per_frame(time)));
                ui.end_row();
            }
        });
    }
    app.history.show(ui);
}
