//! report.json: what a run measured (DESIGN.md section 5).

use pleat::folding::{FoldMetrics, LayerOrderFigures};
use pleat::origami::FlatFoldability;
use pleat::scene::Scene;
use pleat::solver::{SolverKind, StageTimes};
use pleat::Simulation;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Duration;

#[derive(Serialize)]
pub struct Report {
    pub scene: String,
    pub backend: String,
    /// The device that stepped the simulation (a GPU adapter's name).
    pub device: String,
    /// Serialised by its scene-file name (`xpbd`, ...).
    pub solver: SolverKind,
    pub frames: u32,
    pub frame_dt: f32,
    pub substeps: u32,
    pub iterations: u32,
    pub threads: usize,
    pub particles: usize,
    pub triangles: usize,
    pub constraints: usize,
    pub ms_per_frame: FrameTimes,
    pub stages_ms: StagesMs,
    pub contacts_per_frame: f64,
    /// Self-collision and cloth-cloth contacts that acted, per frame.
    pub self_contacts_per_frame: f64,
    /// Candidate self-contacts the broad phase found, per frame.
    pub self_contact_candidates_per_frame: f64,
    /// Builds of the self-contact candidates per frame, where the backend
    /// keeps them over substeps (the GPU); null where it builds them every
    /// substep (the CPU).
    pub self_contact_builds_per_frame: Option<f64>,
    /// Compute dispatches a frame on a GPU (mean over the run); null on the CPU.
    pub dispatches_per_frame: Option<f64>,
    pub max_stretch: f32,
    pub mean_stretch: f32,
    pub nan: bool,
    /// NaN/inf or runaway energy at any frame of the run.
    pub unstable: bool,
    /// Simulated time (s) of the first instability, if any.
    pub unstable_at: Option<f32>,
    /// What it was: `non_finite`, `runaway` (energy) or `torn` (paper
    /// stretched past 25 %, an inextensible cloth blown apart:
    /// [`pleat::stability::CLOTH_TEAR_SHARE`] of its edges past three
    /// times their length).
    pub unstable_kind: Option<&'static str>,
    /// Where it showed: the first non-finite particle, else the fastest.
    pub unstable_particle: Option<u32>,
    pub self_intersections: usize,
    /// Self-intersections counted at every N-th frame too (`pleat run
    /// --check-every N`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub self_intersections_every: Option<CheckedCrossings>,
    pub collider_penetrations: usize,
    pub kinetic_energy: f32,
    /// Fold progress, largest fold-angle errors and strain of paper parts.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub origami: Option<FoldMetrics>,
    /// Kawasaki's and Maekawa's theorems at the crease pattern's interior
    /// vertices (`pleat fold` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flat_foldability: Option<FlatFoldability>,
    /// The layer order of a pattern that folds flat, and the folded paper's
    /// layers checked against it (`pleat fold` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layer_order: Option<LayerOrderFigures>,
}

/// Self-intersections counted at every `every`-th frame of a run, not
/// only at its end: a simulation that passes through itself and comes
/// apart again ends clean.
#[derive(Serialize, Clone, Debug, PartialEq, Eq)]
pub struct CheckedCrossings {
    pub every: u32,
    /// The counts at frames `every`, `2 every`, ...
    pub counts: Vec<usize>,
}

impl CheckedCrossings {
    pub fn new(every: u32) -> Self {
        CheckedCrossings {
            every: every.max(1),
            counts: Vec::new(),
        }
    }

    /// Counts the self-intersections of `sim` (reading its state back) if
    /// `frame` is one to check.
    pub fn frame(&mut self, frame: u32, sim: &mut Simulation) {
        if frame % self.every == 0 {
            sim.sync();
            self.counts.push(sim.metrics().self_intersections);
        }
    }

    /// The most at a checked frame, and the first frame with that many.
    pub fn most(&self) -> Option<(usize, u32)> {
        let most = *self.counts.iter().max()?;
        let first = self.counts.iter().position(|&c| c == most)?;
        Some((most, (first as u32 + 1) * self.every))
    }

    /// One line for the terminal.
    pub fn line(&self) -> String {
        let checks = format!(
            "self-intersections checked at {} frames (every {})",
            self.counts.len(),
            self.every
        );
        let crossed = self.counts.iter().filter(|&&c| c > 0).count();
        match self.most() {
            Some((most, frame)) if most > 0 => {
                format!("{checks}: most {most} (frame {frame}), {crossed} frames with any")
            }
            _ => format!("{checks}: none"),
        }
    }
}

/// Milliseconds per frame over the run.
#[derive(Serialize)]
pub struct FrameTimes {
    pub mean: f64,
    pub p50: f64,
    pub p95: f64,
}

impl FrameTimes {
    pub fn from(frames: &[Duration]) -> Self {
        let mut ms: Vec<f64> = frames.iter().map(|d| d.as_secs_f64() * 1e3).collect();
        ms.sort_by(f64::total_cmp);
        let pick = |q: f64| {
            ms.get(((ms.len() as f64 - 1.0) * q).round() as usize)
                .copied()
                .unwrap_or(0.0)
        };
        FrameTimes {
            mean: ms.iter().sum::<f64>() / ms.len().max(1) as f64,
            p50: pick(0.5),
            p95: pick(0.95),
        }
    }
}

/// Mean milliseconds per frame spent in each stage.
#[derive(Serialize)]
pub struct StagesMs {
    pub forces: f64,
    pub predict: f64,
    pub constraints: f64,
    pub collisions: f64,
    pub self_collision: f64,
    /// Parts of self_collision (the CPU backend's): candidate search,
    /// detection and corrections of the candidates, corrections applied.
    pub self_broad_phase: f64,
    pub self_narrow_phase: f64,
    pub self_solve: f64,
}

impl StagesMs {
    pub fn from(stages: &StageTimes, frames: u32) -> Self {
        let per = |d: Duration| d.as_secs_f64() * 1e3 / frames.max(1) as f64;
        StagesMs {
            forces: per(stages.forces),
            predict: per(stages.predict),
            constraints: per(stages.constraints),
            collisions: per(stages.collisions),
            self_collision: per(stages.self_collision),
            self_broad_phase: per(stages.self_broad_phase),
            self_narrow_phase: per(stages.self_narrow_phase),
            self_solve: per(stages.self_solve),
        }
    }
}

/// The mean compute dispatches a frame over `frames` frames of `sim`, on
/// a backend that dispatches (a GPU).
pub fn dispatches_per_frame(sim: &Simulation, frames: u32) -> Option<f64> {
    sim.backend()
        .dispatches_per_frame()
        .map(|_| sim.stages.dispatches as f64 / f64::from(frames.max(1)))
}

/// Builds of the self-contact candidates per frame of a run of `frames`
/// frames (the substeps per frame where the backend builds them every
/// substep); `None` without self-collision.
pub fn self_contact_builds_per_frame(sim: &Simulation, frames: u32) -> Option<f64> {
    sim.settings
        .self_collision
        .enabled
        .then(|| sim.stages.self_contact_builds as f64 / f64::from(frames.max(1)))
}

impl Report {
    /// The report of `sim` after its run.
    pub fn new(sim: &Simulation, scene: &Scene, frame_times: &[Duration], threads: usize) -> Self {
        Self::named(sim, &scene.name, scene.frame_dt(), frame_times, threads)
    }

    /// The report of `sim` after a run of frames of `frame_dt` seconds,
    /// named `name`.
    pub fn named(
        sim: &Simulation,
        name: &str,
        frame_dt: f32,
        frame_times: &[Duration],
        threads: usize,
    ) -> Self {
        let m = sim.metrics();
        let verdict = sim.stability.verdict();
        let frames = frame_times.len() as u32;
        Report {
            scene: name.into(),
            backend: sim.backend_name().into(),
            device: sim.device(),
            solver: sim.settings.kind,
            frames,
            frame_dt,
            substeps: sim.settings.substeps,
            iterations: sim.settings.iterations,
            threads,
            particles: sim.particles.len(),
            triangles: sim.model.triangles.len(),
            constraints: sim.constraint_count(),
            ms_per_frame: FrameTimes::from(frame_times),
            stages_ms: StagesMs::from(&sim.stages, frames),
            contacts_per_frame: sim.stages.contacts as f64 / frames.max(1) as f64,
            self_contacts_per_frame: sim.stages.self_contacts as f64 / frames.max(1) as f64,
            self_contact_candidates_per_frame: sim.stages.self_contact_candidates as f64
                / frames.max(1) as f64,
            self_contact_builds_per_frame: self_contact_builds_per_frame(sim, frames),
            dispatches_per_frame: dispatches_per_frame(sim, frames),
            max_stretch: m.max_stretch,
            mean_stretch: m.mean_stretch,
            nan: m.nan,
            unstable: m.unstable,
            unstable_at: verdict.map(|(t, _, _)| t),
            unstable_kind: verdict.map(|(_, kind, _)| kind.name()),
            unstable_particle: verdict.and_then(|(_, _, particle)| particle),
            self_intersections: m.self_intersections,
            self_intersections_every: None,
            collider_penetrations: m.collider_penetrations,
            kinetic_energy: m.kinetic_energy,
            origami: FoldMetrics::measure(sim),
            flat_foldability: None,
            layer_order: None,
        }
    }

    /// One line for the terminal.
    pub fn summary_line(&self) -> String {
        format!(
            "{}: {} frames, {} particles, {:.2} ms/frame (p95 {:.2}), max stretch {:.4}, nan {}, unstable {}, {} collider penetrations, {} self-intersections",
            self.scene, self.frames, self.particles, self.ms_per_frame.mean, self.ms_per_frame.p95, self.max_stretch, self.nan, self.unstable,
            self.collider_penetrations, self.self_intersections
        )
    }

    /// Writes `dir/report.json` and returns its path.
    pub fn write(&self, dir: &Path) -> Result<PathBuf, String> {
        let path = dir.join("report.json");
        let json = serde_json::to_string_pretty(self).map_err(|e| e.to_string())?;
        std::fs::write(&path, json + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(path)
    }

    /// The origami figures on one line, when there is paper.
    pub fn fold_line(&self) -> Option<String> {
        let o = self.origami.as_ref()?;
        let e = &o.max_fold_angle_error_deg;
        let mut line = format!(
            "fold progress {:.3}: largest fold-angle error {:.2} deg mountain, {:.2} deg valley, {:.2} deg flat facets; max strain {:.5}",
            o.fold_progress, e.mountain, e.valley, e.flat, o.max_strain
        );
        if let Some(h) = &o.worst_hinge {
            line += &format!(
                "; worst hinge: {} edge {:?} at {:.1} deg for {:.1}",
                h.kind, h.edge, h.angle_deg, h.target_deg
            );
        }
        if let Some(f) = &o.worst_facet {
            line += &format!("; worst facet {:?}", f.triangle);
        }
        if let Some(t) = self.unstable_at {
            line += &format!(
                "; unstable ({}) from {t:.3} s (particle {})",
                self.unstable_kind.unwrap_or("?"),
                self.unstable_particle.map_or("?".into(), |p| p.to_string())
            );
        }
        Some(line)
    }

    /// Per-stage timings, for --profile.
    pub fn profile_text(&self) -> String {
        let s = &self.stages_ms;
        format!(
            "profile (ms per frame): forces {:.3}, predict {:.3}, constraints {:.3}, collisions {:.3}, self-collision {:.3} (broad phase {:.3}, narrow phase {:.3}, solve {:.3}); per frame: {:.1} collider contacts, {:.1} self-contact candidates, {:.1} self-contacts acting",
            s.forces, s.predict, s.constraints, s.collisions, s.self_collision, s.self_broad_phase, s.self_narrow_phase, s.self_solve, self.contacts_per_frame, self.self_contact_candidates_per_frame, self.self_contacts_per_frame
        )
    }
}
