//! What the app tells tests about itself: frame count, the two rates (frames
//! drawn per second, simulation steps per second and simulated seconds per
//! wall second), particle count, max stretch, energy, the cloth's centroid, whether the
//! mouse holds the cloth, and the last error. The page publishes it as
//! `window.pleatState` (JSON text); the native app prints it on exit.

use crate::session::Session;
use serde::Serialize;
use std::collections::VecDeque;

/// Weight of the newest frame in the frame-rate average.
const FPS_SMOOTHING: f32 = 0.05;

/// Wall time (s) over which the simulation's rate is measured: long
/// enough for a rate of a step or two a second (software WebGPU) to be
/// counted within 10 %.
const RATE_WINDOW: f64 = 10.0;

#[derive(Clone, Debug, Default, Serialize)]
pub struct Probe {
    /// The demo's id, or the opened file's name.
    pub demo: String,
    /// Simulation frames stepped since the scene opened.
    pub frame: u64,
    /// Frames drawn per second (smoothed).
    pub fps: f32,
    /// Frames drawn since the app started.
    pub drawn: u64,
    /// Simulation steps per wall second over the last few seconds: the
    /// frames the simulation advanced, however fast the app draws.
    pub steps_per_second: f32,
    /// Simulated seconds per wall second (1: real time).
    pub sim_speed: f32,
    pub particles: usize,
    /// Largest edge length over its rest length.
    pub max_stretch: f32,
    /// Kinetic energy (J).
    pub energy: f32,
    /// Mean particle position (m).
    pub centroid: [f32; 3],
    /// `"cpu"` or `"gpu"`, and the device.
    pub backend: String,
    pub device: String,
    pub unstable: bool,
    /// What went unstable, when and where (as report.json says it), once
    /// the run has; the app then pauses.
    pub instability: Option<String>,
    /// Whether the run is paused.
    pub paused: bool,
    /// Why the backend asked for is not in use, or notes on it.
    pub notice: Option<String>,
    /// Which backend was picked as the faster for this scene, with both
    /// rates, once both are timed ([`crate::backend_trial`]).
    pub backend_pick: Option<String>,
    /// Whether the mouse holds a particle.
    pub grabbing: bool,
    /// Where (CSS pixels, window points natively) a point of the cloth is drawn.
    pub cloth_point: Option<[f32; 2]>,
    pub last_error: Option<String>,
    /// The window's size (points: CSS pixels on a page).
    pub screen: [f32; 2],
    /// Where the controls are (min x, min y, max x, max y, in points): a
    /// panel on the left, or a sheet at the bottom of a narrow window;
    /// `None` while hidden.
    pub controls: Option<[f32; 4]>,
    /// When the GPU device was lost and how the run recovered (a new
    /// device, or the CPU), until dismissed.
    pub device_lost: Option<String>,
    /// Wall time since the app started (s), summed from the frames drawn.
    #[serde(skip)]
    clock: f64,
    /// (wall time, simulation frame) at each frame drawn over the last
    /// [`RATE_WINDOW`] seconds.
    #[serde(skip)]
    window: VecDeque<(f64, u64)>,
    /// Length of a simulation step (s).
    #[serde(skip)]
    step_dt: f32,
}

impl Probe {
    /// Counts one app frame that took `dt` seconds.
    pub fn tick(&mut self, dt: f32) {
        self.drawn += 1;
        if dt > 0.0 {
            let fps = 1.0 / dt;
            self.fps = if self.fps == 0.0 {
                fps
            } else {
                self.fps + (fps - self.fps) * FPS_SMOOTHING
            };
        }
        self.clock += f64::from(dt.max(0.0));
        self.measure_steps();
    }

    /// The simulation's rate over the window: frames advanced over the wall
    /// time they took.
    fn measure_steps(&mut self) {
        self.window.push_back((self.clock, self.frame));
        while self
            .window
            .front()
            .is_some_and(|&(t, _)| self.clock - t > RATE_WINDOW)
        {
            self.window.pop_front();
        }
        let Some(&(t0, f0)) = self.window.front() else {
            return;
        };
        let elapsed = self.clock - t0;
        // A new scene starts its count again: measure from there.
        if self.frame < f0 {
            self.window.clear();
            return;
        }
        if elapsed > 0.0 {
            self.steps_per_second = ((self.frame - f0) as f64 / elapsed) as f32;
            self.sim_speed = self.steps_per_second * self.step_dt;
        }
    }

    /// Reads the session's state as last synced.
    pub fn observe(&mut self, session: &Session) {
        let sim = &session.sim;
        let x = &sim.particles.x;
        self.particles = x.len();
        self.max_stretch = pleat::metrics::stretch(&sim.model, &sim.particles).0;
        self.energy = sim.particles.kinetic_energy();
        let sum = x.iter().fold(glam::Vec3::ZERO, |a, p| a + *p);
        self.centroid = (sum / x.len().max(1) as f32).to_array();
        self.backend = sim.backend_name().to_string();
        self.device = sim.device();
        self.unstable = sim.stability.is_unstable();
        self.instability = sim.stability.verdict().map(|(time, kind, particle)| {
            let at = particle.map_or(String::new(), |p| format!(", particle {p}"));
            format!(
                "the simulation went unstable ({}) at {time:.2} s{at}",
                kind.name()
            )
        });
        self.step_dt = 1.0 / session.scene.fps;
        self.notice.clone_from(&session.notice);
    }

    /// The probe as JSON text.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }
}
