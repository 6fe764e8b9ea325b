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
    /// The frame from whose landing `steps_per_second` counts: the oldest
    /// step in its window.
    pub rate_since_frame: u64,
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
    /// (wall time, simulation frame) as each step landed over the last
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

    /// Counts a simulation step issued in this app frame. Its time is the
    /// frame's, the same frame that publishes the new count: taking it at
    /// the next frame's tick instead would add the draw interval after the
    /// step, which software WebGPU makes uneven (0.02 to 0.7 s), and tilt
    /// the rate by up to a tenth.
    pub fn count_step(&mut self) {
        self.frame += 1;
        self.measure_steps();
    }

    /// The simulation's rate: whole steps over their time. The window holds
    /// the wall time at which each step landed over the last
    /// [`RATE_WINDOW`] seconds, and the rate counts the steps since the
    /// oldest of them over the time since it landed. Counting from a
    /// landing, not from the window's edge, keeps a step or two a second
    /// (software WebGPU) within a few per cent of the truth; a run that
    /// stops stepping reads 0 once its last step leaves the window.
    fn measure_steps(&mut self) {
        // A new scene starts its count again: measure from there.
        if self.window.back().is_some_and(|&(_, f)| self.frame < f) {
            self.window.clear();
        }
        if self.window.back().is_none_or(|&(_, f)| self.frame != f) {
            self.window.push_back((self.clock, self.frame));
        }
        while self.window.len() > 1
            && self
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
        self.rate_since_frame = f0;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Draws `seconds` of frames `draw` s apart while the simulation lands
    /// a step every `step` s, and gives the rate's worst relative error as
    /// read just after each step, once the window has filled.
    fn worst_error(seconds: f64, draw: f64, step: f64) -> f64 {
        let mut probe = Probe {
            step_dt: 1.0 / 60.0,
            ..Probe::default()
        };
        let (mut t, mut next_step, mut worst) = (0.0, step, 0.0f64);
        while t < seconds {
            t += draw;
            let landed = t >= next_step;
            if landed {
                probe.frame += 1;
                next_step += step;
            }
            probe.tick(draw as f32);
            if landed && t > RATE_WINDOW + 1.0 {
                let error = (f64::from(probe.steps_per_second) * step - 1.0).abs();
                worst = worst.max(error);
            }
        }
        worst
    }

    #[test]
    fn a_slow_simulation_is_counted_in_whole_steps() {
        // 1.416 steps a second drawn at 10 fps, as software WebGPU runs the
        // wind demo: counting from the window's edge read 15 steps in 10 s
        // at some phases (1.5, 7 % high); from a landing it is whole steps
        // over their time, off only by when the draw saw the step.
        let error = worst_error(60.0, 0.1, 0.706);
        assert!(error < 0.015, "{:.1} % off", error * 100.0);
    }

    #[test]
    fn a_fast_simulation_is_counted_within_a_per_cent() {
        let error = worst_error(30.0, 1.0 / 60.0, 1.0 / 60.0);
        assert!(error < 0.01, "{:.1} % off", error * 100.0);
    }

    #[test]
    fn the_rate_is_what_an_observer_of_the_published_frames_counts() {
        // Draws as uneven as software WebGPU's (0.02 to 0.7 s), a step
        // issued in some of them: the panel's rate must be the published
        // count over the published times, as the browser test counts it.
        let mut probe = Probe::default();
        let (mut t, mut seed, mut seen) = (0.0f64, 12345u32, Vec::new());
        while t < 40.0 {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let unit = f64::from(seed >> 8) / f64::from(1u32 << 24);
            let draw = 0.02 + 0.68 * unit;
            t += draw;
            probe.tick(draw as f32);
            if unit > 0.4 {
                probe.count_step();
                seen.push((t, probe.frame));
            }
            let Some(&(now, frame)) = seen.last().filter(|_| unit > 0.4 && t > 12.0) else {
                continue;
            };
            let &(t0, f0) = seen.iter().find(|&&(s, _)| now - s <= RATE_WINDOW).unwrap();
            assert_eq!(probe.rate_since_frame, f0);
            let counted = (frame - f0) as f64 / (now - t0);
            let error = (f64::from(probe.steps_per_second) / counted - 1.0).abs();
            assert!(
                error < 1e-3,
                "at {t:.2} s: panel {}, counted {counted}",
                probe.steps_per_second
            );
        }
    }

    #[test]
    fn a_stopped_simulation_reads_zero_once_its_steps_leave_the_window() {
        let mut probe = Probe::default();
        for _ in 0..100 {
            probe.frame += 1;
            probe.tick(0.1);
        }
        assert!(probe.steps_per_second > 9.0);
        for _ in 0..101 {
            probe.tick(0.1);
        }
        assert_eq!(probe.steps_per_second, 0.0);
    }

    #[test]
    fn a_new_scene_counts_from_its_first_step() {
        let mut probe = Probe::default();
        for _ in 0..50 {
            probe.frame += 1;
            probe.tick(0.1);
        }
        probe.frame = 0;
        for _ in 0..20 {
            probe.tick(0.05);
            probe.frame += 1;
        }
        assert!(
            (probe.steps_per_second - 20.0).abs() < 0.5,
            "{}",
            probe.steps_per_second
        );
    }
}
