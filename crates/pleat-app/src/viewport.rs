//! The 3D view: pleat-render draws the cloth into a texture on the app's own
//! wgpu device (straight from the GPU backend's buffer when it runs there),
//! egui shows it; the mouse (or a finger) orbits, pans and zooms the camera,
//! or grabs the cloth and drags it (an attachment to the cursor, let go on
//! release).

use crate::orbit::{Orbit, Projection};
use crate::session::Session;
use eframe::egui;
use glam::Vec3;
use pleat::constraint::Grab;
use pleat_render::{Positions, RenderSettings, Renderer, View};

/// How far (points) from the cursor a particle can be grabbed.
const GRAB_RADIUS: f32 = 24.0;
/// Compliance of the attachment to the cursor (m/N): stiff, not rigid.
const GRAB_COMPLIANCE: f32 = 1e-5;

/// The drawn view and the camera.
pub struct Viewport {
    renderer: Option<Renderer>,
    texture: Option<egui::TextureId>,
    /// The scene (counted by the app) the camera frames, and the model the
    /// renderer was built for.
    framed: u64,
    built_for: u64,
    pub view: View,
    orbit: Option<Orbit>,
    /// The grabbed particle and its depth along the view direction.
    grabbed: Option<(u32, f32)>,
    /// Where (window points) the particle nearest the cloth's centroid is
    /// drawn: a place a test can grab.
    pub cloth_point: Option<[f32; 2]>,
}

impl Viewport {
    pub fn new() -> Self {
        Viewport {
            renderer: None,
            texture: None,
            framed: u64::MAX,
            built_for: u64::MAX,
            view: View::Shaded,
            orbit: None,
            grabbed: None,
            cloth_point: None,
        }
    }

    /// The viewport for a new device (after a loss): the same camera and
    /// view, the renderer built anew.
    pub fn on_new_device(&self) -> Self {
        Viewport {
            framed: self.framed,
            view: self.view,
            orbit: self.orbit,
            ..Viewport::new()
        }
    }

    /// Whether a particle is held by the mouse.
    pub fn is_grabbing(&self) -> bool {
        self.grabbed.is_some()
    }

    /// Draws the view over the rest of `ui` and handles the mouse, with
    /// pleat-render on `wgpu`'s device, or, where the adapter has no compute
    /// shaders (WebGL), with egui's painter ([`crate::software`]);
    /// `max_stretch` goes on the strain legend. Returns an error message if
    /// the renderer could not be built.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        wgpu: &eframe::egui_wgpu::RenderState,
        session: &mut Session,
        [opened, generation]: [u64; 2],
        compute: bool,
        max_stretch: f32,
    ) -> Result<(), String> {
        let rect = ui.available_rect_before_wrap();
        if rect.width() < 1.0 || rect.height() < 1.0 {
            return Ok(()); // Not laid out yet, or minimised.
        }
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        let ppp = ui.ctx().pixels_per_point();
        let max = wgpu.device.limits().max_texture_dimension_2d;
        let size = [rect.width(), rect.height()].map(|s| ((s * ppp).round() as u32).clamp(1, max));
        if self.framed != opened {
            self.orbit = None;
            self.grabbed = None;
            self.framed = opened;
        }
        if compute {
            self.prepare(wgpu, session, generation, size)?;
        }
        let orbit = self.orbit.get_or_insert_with(|| {
            let bounds = scene_bounds(session);
            Orbit::from(pleat_render::Camera::framing(&bounds, rect.aspect_ratio()))
        });
        let seen = Projection::new(*orbit, rect);
        self.grabbed = grab(&response, session, &seen, self.grabbed);
        handle_camera(ui, &response, orbit, self.grabbed.is_some());
        let projection = Projection::new(*orbit, rect);
        if let Some(renderer) = self.renderer.as_mut().filter(|_| compute) {
            renderer.set_camera(orbit.camera());
            let positions = match session.gpu_positions() {
                Some(buffer) => Positions::Gpu(buffer),
                None => Positions::Cpu(&session.sim.particles.x),
            };
            renderer
                .draw(positions, &session.sim.world)
                .map_err(|e| e.to_string())?;
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            if let Some(texture) = self.texture {
                ui.painter().image(texture, rect, uv, egui::Color32::WHITE);
            }
            crate::legend::draw(ui, rect, self.view, renderer, max_stretch);
        } else {
            crate::software::draw(&ui.painter_at(rect), &projection, session);
        }
        self.cloth_point = central_particle(&session.sim.particles.x)
            .and_then(|p| projection.to_screen(p))
            .map(|p| [p.x, p.y]);
        Ok(())
    }

    /// Builds the renderer for the session's model, or resizes it, and
    /// hands its picture to egui.
    fn prepare(
        &mut self,
        wgpu: &eframe::egui_wgpu::RenderState,
        session: &Session,
        generation: u64,
        size: [u32; 2],
    ) -> Result<(), String> {
        let rebuilt = self.built_for != generation
            || self.renderer.as_ref().map(|r| r.settings().view) != Some(self.view);
        if rebuilt {
            let settings = RenderSettings {
                width: size[0],
                height: size[1],
                view: self.view,
                camera: self.orbit.map(|o| o.camera()),
                ..RenderSettings::default()
            };
            let renderer = Renderer::new(
                wgpu.device.clone(),
                wgpu.queue.clone(),
                &session.sim.model,
                &session.sim.world,
                settings,
            )
            .map_err(|e| format!("cannot draw this scene: {e}"))?;
            if self.orbit.is_none() {
                self.orbit = Some(Orbit::from(renderer.camera()));
            }
            self.renderer = Some(renderer);
            self.built_for = generation;
        }
        let renderer = self.renderer.as_mut().expect("built above");
        let resized = renderer.settings().width != size[0] || renderer.settings().height != size[1];
        if resized {
            renderer
                .resize(size[0], size[1])
                .map_err(|e| e.to_string())?;
        }
        if rebuilt || resized || self.texture.is_none() {
            let view = renderer
                .picture()
                .create_view(&wgpu::TextureViewDescriptor::default());
            let mut egui_renderer = wgpu.renderer.write();
            let filter = wgpu::FilterMode::Linear;
            match self.texture {
                Some(id) => egui_renderer.update_egui_texture_from_wgpu_texture(
                    &wgpu.device,
                    &view,
                    filter,
                    id,
                ),
                None => {
                    self.texture =
                        Some(egui_renderer.register_native_texture(&wgpu.device, &view, filter))
                }
            }
        }
        Ok(())
    }
}

/// Orbit with the secondary button (or the primary one off the cloth),
/// pan with the middle button or shift, zoom with the wheel or a pinch.
fn handle_camera(ui: &egui::Ui, response: &egui::Response, orbit: &mut Orbit, grabbing: bool) {
    let delta = response.drag_delta();
    let shift = ui.input(|i| i.modifiers.shift);
    let pan = response.dragged_by(egui::PointerButton::Middle)
        || (shift && response.dragged_by(egui::PointerButton::Primary));
    if pan {
        orbit.pan(
            delta.x / response.rect.height(),
            delta.y / response.rect.height(),
        );
    } else if response.dragged_by(egui::PointerButton::Secondary)
        || (response.dragged_by(egui::PointerButton::Primary) && !grabbing)
    {
        orbit.rotate(delta.x * 0.01, delta.y * 0.01);
    }
    if response.hovered() {
        let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
        orbit.zoom((-scroll * 0.002).exp() / zoom);
    }
}

/// Grabs the particle nearest the cursor when a primary drag starts on the
/// cloth, drags it to the cursor while the button is down, lets go on
/// release. Returns the grabbed particle and its depth.
fn grab(
    response: &egui::Response,
    session: &mut Session,
    projection: &Projection,
    grabbed: Option<(u32, f32)>,
) -> Option<(u32, f32)> {
    let shift = response.ctx.input(|i| i.modifiers.shift);
    let primary = response.dragged_by(egui::PointerButton::Primary) && !shift;
    let pointer = response.interact_pointer_pos();
    let grabbed = match (grabbed, primary, pointer) {
        (Some(held), true, Some(_)) => Some(held),
        (None, true, Some(pos)) if response.drag_started() => {
            // Pick where the button went down: a quick flick (or a slow
            // frame) may already have moved the pointer off the cloth.
            let origin = response
                .ctx
                .input(|i| i.pointer.press_origin())
                .unwrap_or(pos);
            nearest_particle(&session.sim.particles.x, projection, origin, GRAB_RADIUS).map(|i| {
                let (eye, _) = projection.ray(origin);
                let depth = (session.sim.particles.x[i as usize] - eye).length();
                (i, depth)
            })
        }
        _ => None,
    };
    match (grabbed, pointer) {
        (Some((particle, depth)), Some(pos)) => {
            let (eye, direction) = projection.ray(pos);
            session.sim.grab(Some(Grab {
                particle,
                target: eye + direction * depth,
                compliance: GRAB_COMPLIANCE,
            }));
        }
        _ => session.sim.grab(None),
    }
    grabbed
}

/// The particle nearest the centroid of `x`.
fn central_particle(x: &[Vec3]) -> Option<Vec3> {
    let centroid = x.iter().copied().sum::<Vec3>() / x.len().max(1) as f32;
    x.iter().copied().min_by(|a, b| {
        a.distance_squared(centroid)
            .total_cmp(&b.distance_squared(centroid))
    })
}

/// The particle drawn nearest to `cursor` (window points) within
/// `radius` points, the nearer to the camera among those about as near.
fn nearest_particle(
    x: &[Vec3],
    projection: &Projection,
    cursor: egui::Pos2,
    radius: f32,
) -> Option<u32> {
    x.iter()
        .enumerate()
        .filter_map(|(i, &p)| {
            let distance = projection.to_screen(p)?.distance(cursor);
            let depth = projection.depth(p);
            (distance <= radius).then_some((i as u32, distance, depth))
        })
        .min_by(|a, b| {
            let key = |(_, d, w): &(u32, f32, f32)| (d / radius * 0.25).round() * 1e6 + w;
            key(a).total_cmp(&key(b))
        })
        .map(|(i, _, _)| i)
}

/// The bounds of the cloth and the colliders, for the first camera.
fn scene_bounds(session: &Session) -> pleat_render::Bounds {
    pleat_render::Bounds::of(session.sim.particles.x.iter().copied()).unwrap_or(
        pleat_render::Bounds {
            min: Vec3::splat(-0.5),
            max: Vec3::splat(0.5),
        },
    )
}
