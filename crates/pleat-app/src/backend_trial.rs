//! Which backend steps a scene faster, measured as it opens: the scene runs
//! a little while on the backend it opened on, then on the other, each
//! timed in simulation steps per wall second after a few frames to warm up
//! (pipelines compiled, buffers filled), and the faster is kept. Which is
//! faster depends on the scene and the machine: a crease pattern of a few
//! dozen vertices folds faster on the CPU, a large cloth on a GPU, and a
//! software WebGPU (no GPU in the machine) loses to the CPU on most
//! scenes. The verdict, with both rates, is shown on the panel.

use crate::session::BackendChoice;

/// Frames and wall time (s) on a backend before its clock starts, both at
/// least: a browser's WebGPU compiles a pipeline when it first runs it.
const WARM_UP: u64 = 3;
const WARM_UP_SECONDS: f64 = 0.5;
/// Wall time (s) and frames a backend is timed over, at least.
const TRIAL_SECONDS: f64 = 1.5;
const TRIAL_FRAMES: u64 = 3;
/// Wall time (s) after which a backend too slow to give its frames is
/// timed on what it gave.
const LONGEST_TRIAL: f64 = 10.0;
/// How much faster the other backend must be to be taken (timings of a
/// second or two vary by a few percent).
const MARGIN: f32 = 1.1;

/// A backend's measured rate: steps per wall second, or `None` where it
/// could not run the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rate {
    pub backend: BackendChoice,
    pub steps_per_second: Option<f32>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// Waiting for `on` to run the scene, then for it to warm up from the
    /// frame and the time it was first seen running at.
    Settling {
        on: BackendChoice,
        since: Option<(u64, f64)>,
    },
    /// Counting `on`'s frames from `frame` at wall time `start`.
    Timing {
        on: BackendChoice,
        start: f64,
        frame: u64,
    },
    Decided(BackendChoice),
}

/// The trial of both backends on one opened scene.
#[derive(Clone, Debug, PartialEq)]
pub struct BackendTrial {
    phase: Phase,
    rates: Vec<Rate>,
}

/// What the simulation is doing, as the trial sees it each frame.
#[derive(Clone, Copy, Debug)]
pub struct Running {
    /// Wall time (s).
    pub now: f64,
    /// The backend stepping the simulation.
    pub backend: BackendChoice,
    /// Whether a move to another backend waits for the state.
    pub moving: bool,
    /// Frames stepped since the scene opened.
    pub frame: u64,
    /// Whether the run plays (a paused run is not timed).
    pub playing: bool,
}

impl BackendTrial {
    /// A trial that starts with the backend the scene opened on.
    pub fn new(first: BackendChoice) -> Self {
        BackendTrial {
            phase: Phase::Settling {
                on: first,
                since: None,
            },
            rates: Vec::new(),
        }
    }

    /// The backend kept, once both are timed.
    pub fn decided(&self) -> Option<BackendChoice> {
        match self.phase {
            Phase::Decided(choice) => Some(choice),
            _ => None,
        }
    }

    /// The rates measured so far.
    pub fn rates(&self) -> &[Rate] {
        &self.rates
    }

    /// Takes this frame's state; returns the backend to move to, if any.
    pub fn observe(&mut self, run: Running) -> Option<BackendChoice> {
        match self.phase {
            Phase::Decided(_) => None,
            // A change waits (a rebuild): the clock runs on, and the trial
            // asks for no move over it.
            Phase::Timing { .. } if run.moving && run.playing => None,
            // Paused, or the move not made yet: warm up again afterwards.
            Phase::Settling { on, .. } | Phase::Timing { on, .. } if run.moving || !run.playing => {
                self.phase = Phase::Settling { on, since: None };
                None
            }
            Phase::Settling { on, .. } if run.backend != on => {
                // The move was refused (no GPU that runs the scene).
                self.rates.push(Rate {
                    backend: on,
                    steps_per_second: None,
                });
                self.next(run.backend)
            }
            Phase::Settling { on, since } => {
                let since = since.unwrap_or((run.frame, run.now));
                let warm = run.frame >= since.0 + WARM_UP && run.now >= since.1 + WARM_UP_SECONDS;
                self.phase = match warm {
                    true => Phase::Timing {
                        on,
                        start: run.now,
                        frame: run.frame,
                    },
                    false => Phase::Settling {
                        on,
                        since: Some(since),
                    },
                };
                None
            }
            Phase::Timing { on, start, frame } => {
                let (seconds, frames) = (run.now - start, run.frame.saturating_sub(frame));
                let enough = seconds >= TRIAL_SECONDS && frames >= TRIAL_FRAMES;
                if !enough && seconds < LONGEST_TRIAL {
                    return None;
                }
                self.rates.push(Rate {
                    backend: on,
                    steps_per_second: Some(frames as f32 / seconds as f32),
                });
                self.next(run.backend)
            }
        }
    }

    /// After a backend's rate: the other backend's turn, or the verdict;
    /// the backend to move to, if any (`running` runs now).
    fn next(&mut self, running: BackendChoice) -> Option<BackendChoice> {
        let other = running.other();
        if !self.rates.iter().any(|r| r.backend == other) {
            self.phase = Phase::Settling {
                on: other,
                since: None,
            };
            return Some(other);
        }
        let best = self.best();
        self.phase = Phase::Decided(best);
        (best != running).then_some(best)
    }

    /// The faster backend: the one timed first unless the other was
    /// [`MARGIN`] times faster.
    fn best(&self) -> BackendChoice {
        let rate = |r: &Rate| r.steps_per_second.unwrap_or(-1.0);
        match self.rates.as_slice() {
            [first, second] if rate(second) > MARGIN * rate(first).max(0.0) => second.backend,
            [first, ..] if first.steps_per_second.is_some() => first.backend,
            [.., last] => last.backend,
            [] => BackendChoice::Cpu,
        }
    }

    /// The verdict for the panel: the backend kept and both rates.
    pub fn verdict(&self) -> Option<String> {
        let kept = self.decided()?;
        let rate = |r: &Rate| match r.steps_per_second {
            Some(s) => format!("{} {s:.1} steps/s", r.backend.name()),
            None => format!("{} could not run it", r.backend.name()),
        };
        let rates: Vec<String> = self.rates.iter().map(rate).collect();
        Some(format!("picked {}: {}", kept.name(), rates.join(", ")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use BackendChoice::{Cpu, Gpu};

    /// Runs `trial` on a simulation whose backends step at `cpu` and `gpu`
    /// frames per second (0: that backend is refused), a frame each
    /// 1/60 s of wall time at most; the backend it ends on, and the time.
    fn run(
        trial: &mut BackendTrial,
        first: BackendChoice,
        cpu: f64,
        gpu: f64,
    ) -> (BackendChoice, f64) {
        let (mut now, mut frame, mut backend) = (0.0, 0u64, first);
        let mut moving = false;
        while trial.decided().is_none() && now < 100.0 {
            let rate = if backend == Cpu { cpu } else { gpu };
            now += 1.0 / rate.clamp(0.01, 60.0);
            frame += 1;
            let running = Running {
                now,
                backend,
                moving,
                frame,
                playing: true,
            };
            moving = false;
            if let Some(to) = trial.observe(running) {
                moving = true;
                // A refused move leaves the run where it was.
                if (if to == Cpu { cpu } else { gpu }) > 0.0 {
                    backend = to;
                }
            }
        }
        (backend, now)
    }

    #[test]
    fn the_faster_backend_is_kept_whichever_the_scene_opened_on() {
        for first in [Cpu, Gpu] {
            let mut trial = BackendTrial::new(first);
            assert_eq!(run(&mut trial, first, 50.0, 20.0).0, Cpu);
            let rates = trial.rates();
            assert_eq!(rates.len(), 2);
            let cpu = rates.iter().find(|r| r.backend == Cpu).unwrap();
            let cpu = cpu.steps_per_second.unwrap();
            assert!((cpu - 50.0).abs() < 2.0, "{rates:?}");
            let mut trial = BackendTrial::new(first);
            assert_eq!(run(&mut trial, first, 5.0, 40.0).0, Gpu);
            let verdict = trial.verdict().unwrap();
            assert!(verdict.starts_with("picked GPU"), "{verdict}");
            assert!(verdict.contains("CPU 5.0 steps/s"), "{verdict}");
        }
    }

    #[test]
    fn near_equal_rates_keep_the_backend_the_scene_opened_on() {
        let mut trial = BackendTrial::new(Gpu);
        assert_eq!(run(&mut trial, Gpu, 31.0, 30.0).0, Gpu);
    }

    #[test]
    fn a_refused_backend_leaves_the_one_that_runs() {
        let mut trial = BackendTrial::new(Cpu);
        assert_eq!(run(&mut trial, Cpu, 30.0, 0.0).0, Cpu);
        let verdict = trial.verdict().unwrap();
        assert!(verdict.contains("GPU could not run it"), "{verdict}");
    }

    #[test]
    fn a_very_slow_backend_is_timed_within_the_longest_trial() {
        let mut trial = BackendTrial::new(Gpu);
        let (kept, took) = run(&mut trial, Gpu, 30.0, 0.2);
        assert_eq!(kept, Cpu);
        // The slow backend's warm-up frames and at most the longest trial.
        assert!(
            took < (WARM_UP + 1) as f64 / 0.2 + LONGEST_TRIAL + 5.0,
            "{took} s"
        );
    }

    #[test]
    fn a_paused_run_is_not_timed() {
        let mut trial = BackendTrial::new(Cpu);
        let mut at = |now: f64, frame: u64, playing: bool| {
            trial.observe(Running {
                now,
                backend: Cpu,
                moving: false,
                frame,
                playing,
            })
        };
        for frame in 0..4 {
            at(frame as f64 * 0.1, frame, true);
        }
        // Paused for a minute: the clock starts again after it.
        at(60.0, 4, false);
        let (mut frame, mut moved) = (4, None);
        while moved.is_none() && frame < 100 {
            frame += 1;
            moved = at(60.0 + frame as f64 * 0.1, frame, true);
        }
        assert_eq!(moved, Some(Gpu));
        let rate = trial.rates()[0].steps_per_second.unwrap();
        assert!((rate - 10.0).abs() < 0.5, "{rate} steps/s");
    }
}
