//! Folding in steps: a fold made of steps, each with every crease's target
//! at its end and a number of frames. Within a step the fold progress runs
//! from 0 to 1 and each hinge is driven to `start + c * (end - start)`, its
//! start the previous step's end (the flat sheet before the first step),
//! so creases folded in an earlier step stay folded.
//!
//! A paper part keeps its steps' angles ([`crate::paper::Paper::steps`]),
//! found here from its crease pattern and each step's per-edge fold
//! angles ([`sheet_step_angles`]): from a multi-frame FOLD file's frames
//! ([`crate::origami::parse_fold_frames`]) or a scene's `fold.steps`. The
//! simulation walks the steps frame by frame ([`FoldSteps::at`]) and hands
//! the backend each step's start and end angles ([`HingeTargets`]) when
//! the step changes.

use std::collections::HashMap;

use crate::constraint::OrigamiHinge;
use crate::model::Model;
use crate::origami::{Assignment, CreasePattern, PatternEdge, PatternError, Sheet, SheetOptions};
use crate::paper::full_angle;

/// The frames of each step of a fold and every paper hinge's angle at
/// each step's end.
#[derive(Clone, Debug, PartialEq)]
pub struct FoldSteps {
    /// Frames of each step (at least 1 each).
    pub frames: Vec<u32>,
    /// Per step, the end angle of every hinge of the model's paper parts,
    /// part after part in the order of their hinges (radians, valley
    /// positive; `None` for a hinge that is not driven).
    pub angles: Vec<Vec<Option<f32>>>,
}

impl FoldSteps {
    /// The steps of `model`'s paper parts ([`crate::paper::Paper::steps`]),
    /// `frames[k]` frames for step `k`; `None` when no part folds in steps
    /// or `frames` is empty. A part with fewer steps than the others holds
    /// its last step's angles (a part without steps folds fully in the
    /// first).
    pub fn of_model(model: &Model, frames: &[u32]) -> Option<FoldSteps> {
        let papers: Vec<_> = model
            .cloths
            .iter()
            .filter_map(|c| c.paper.as_ref())
            .collect();
        let count = papers.iter().map(|p| p.steps.len()).max()?;
        if count == 0 || frames.is_empty() {
            return None;
        }
        let angles = (0..count)
            .map(|k| {
                papers
                    .iter()
                    .flat_map(|p| match p.steps.get(k).or(p.steps.last()) {
                        Some(step) => step.clone(),
                        None => p.hinges.iter().map(full_angle).collect(),
                    })
                    .collect()
            })
            .collect();
        let frames = (0..count)
            .map(|k| frames[k.min(frames.len() - 1)].max(1))
            .collect();
        Some(FoldSteps { frames, angles })
    }

    /// Number of steps.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Whether there is no step.
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Frames of all the steps together.
    pub fn total_frames(&self) -> u32 {
        self.frames.iter().sum()
    }

    /// The step and the progress within it during frame `frame` (counted
    /// from 1): linear from `1 / frames` to 1 over the step's frames; past
    /// the last step, the last at progress 1.
    pub fn at(&self, frame: u32) -> (usize, f32) {
        let mut first = 0;
        for (k, &n) in self.frames.iter().enumerate() {
            if frame <= first + n {
                let into = frame.saturating_sub(first).max(1);
                return (k, into as f32 / n.max(1) as f32);
            }
            first += n;
        }
        (self.len().saturating_sub(1), 1.0)
    }

    /// Each driven hinge's start and end angles in step `step` of `model`
    /// (the model these steps were made for).
    pub fn targets(&self, model: &Model, step: usize) -> HingeTargets {
        let end = &self.angles[step];
        let start = step.checked_sub(1).map(|k| &self.angles[k]);
        let mut by_edge = HashMap::new();
        let hinges = model
            .cloths
            .iter()
            .filter_map(|c| Some((c, c.paper.as_ref()?)))
            .flat_map(|(c, p)| p.hinges.iter().map(move |h| h.v.map(|i| c.global(i))));
        for (g, v) in hinges.enumerate() {
            let Some(Some(e)) = end.get(g) else {
                continue;
            };
            let s = start
                .and_then(|s| s.get(g).copied().flatten())
                .unwrap_or(0.0);
            by_edge.insert([v[0], v[1]], [s, *e]);
        }
        HingeTargets { by_edge }
    }
}

/// The start and end angles of each driven hinge in one step of a fold,
/// by its edge (global particle indices `v[0], v[1]` of the hinge).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HingeTargets {
    by_edge: HashMap<[u32; 2], [f32; 2]>,
}

impl HingeTargets {
    /// The start and end angles of the hinge on `v` (radians), if driven.
    pub fn get(&self, v: [u32; 4]) -> Option<[f32; 2]> {
        self.by_edge.get(&[v[0], v[1]]).copied()
    }

    /// Gives `hinge` its start and end angles in this step (leaving its
    /// tracked angle as it is); says whether they changed.
    pub fn apply(&self, hinge: &mut OrigamiHinge) -> bool {
        let Some([start, end]) = self.get(hinge.v) else {
            return false;
        };
        let changed = hinge.start_angle != start || hinge.full_angle != end;
        hinge.start_angle = start;
        hinge.full_angle = end;
        changed
    }

    /// The target of the hinge on `v` at progress `c` of the step, uncapped
    /// (radians); `None` when it is not driven.
    pub fn target(&self, v: [u32; 4], c: f32) -> Option<f32> {
        self.get(v).map(|[s, e]| s + c * (e - s))
    }
}

/// Every hinge's end angle in each step of `sheet` (built from `pattern`
/// with `options`): `steps[k][e]` is pattern edge `e`'s fold angle at the
/// end of step `k` (degrees, as [`crate::origami::PatternEdge::fold_angle`];
/// only mountain and valley edges take it). Each step's pattern is
/// triangulated again, and must give the same hinges.
pub fn sheet_step_angles(
    pattern: &CreasePattern,
    options: &SheetOptions,
    sheet: &Sheet,
    steps: &[Vec<Option<f64>>],
) -> Result<Vec<Vec<Option<f32>>>, PatternError> {
    steps
        .iter()
        .enumerate()
        .map(|(k, angles)| {
            if angles.len() != pattern.edges.len() {
                return Err(PatternError::new(
                    format!("step {}", k + 1),
                    format!(
                        "gives {} edge angles, but the pattern has {} edges",
                        angles.len(),
                        pattern.edges.len()
                    ),
                ));
            }
            let stepped = Sheet::from_pattern(&step_pattern(pattern, angles), options)?;
            let same = stepped.hinges.len() == sheet.hinges.len()
                && stepped
                    .hinges
                    .iter()
                    .zip(&sheet.hinges)
                    .all(|(a, b)| a.v == b.v);
            if !same {
                return Err(PatternError::new(
                    format!("step {}", k + 1),
                    "its angles triangulate the pattern differently",
                ));
            }
            Ok(stepped.hinges.iter().map(full_angle).collect())
        })
        .collect()
}

/// `pattern` as a step that gives its edges `angles` (degrees, valley
/// positive, one per edge) leaves it: each crease and flat line folded the
/// way its angle says ([`step_edge`]). Its sheet's hinges carry the step's
/// targets, and its flat-folded state ([`crate::origami::FlatFolded`]) is
/// the step's, where the step folds flat.
pub fn step_pattern(pattern: &CreasePattern, angles: &[Option<f64>]) -> CreasePattern {
    let mut at_step = pattern.clone();
    for (edge, &angle) in at_step.edges.iter_mut().zip(angles) {
        step_edge(edge, angle);
    }
    at_step
}

/// `edge` as a step that gives it `angle` (degrees, valley positive)
/// folds it: a crease or a flat line of the pattern folds the way the
/// angle's sign says, which may be the other way from the finished model
/// (a petal fold or a reverse fold turns creases over) or a line the model
/// leaves flat (a preliminary base's book folds, opened by the bird base).
/// Boundaries, cuts, auxiliary and unassigned lines keep what they are.
fn step_edge(edge: &mut PatternEdge, angle: Option<f64>) {
    if !matches!(
        edge.assignment,
        Assignment::Mountain | Assignment::Valley | Assignment::Flat
    ) {
        return;
    }
    match angle {
        Some(a) if a > 0.0 => edge.assignment = Assignment::Valley,
        Some(a) if a < 0.0 => edge.assignment = Assignment::Mountain,
        _ if edge.assignment == Assignment::Flat => return,
        _ => {}
    }
    edge.fold_angle = angle;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_folds_creases_and_flat_lines_the_way_its_angle_says() {
        let edge = |assignment| PatternEdge {
            v: [0, 1],
            assignment,
            fold_angle: None,
        };
        let stepped = |assignment, angle| {
            let mut e = edge(assignment);
            step_edge(&mut e, angle);
            (e.assignment, e.fold_angle)
        };
        use Assignment::*;
        assert_eq!(stepped(Mountain, Some(180.0)), (Valley, Some(180.0)));
        assert_eq!(stepped(Valley, Some(-90.0)), (Mountain, Some(-90.0)));
        assert_eq!(stepped(Flat, Some(-180.0)), (Mountain, Some(-180.0)));
        assert_eq!(stepped(Flat, Some(0.0)), (Flat, None));
        assert_eq!(stepped(Mountain, Some(0.0)), (Mountain, Some(0.0)));
        assert_eq!(stepped(Boundary, Some(180.0)), (Boundary, None));
        assert_eq!(stepped(Auxiliary, Some(180.0)), (Auxiliary, None));
    }

    #[test]
    fn steps_run_one_after_another_then_hold() {
        let steps = FoldSteps {
            frames: vec![2, 4],
            angles: vec![vec![], vec![]],
        };
        let at: Vec<(usize, f32)> = (1..=8).map(|f| steps.at(f)).collect();
        assert_eq!(
            at,
            [
                (0, 0.5),
                (0, 1.0),
                (1, 0.25),
                (1, 0.5),
                (1, 0.75),
                (1, 1.0),
                (1, 1.0),
                (1, 1.0)
            ]
        );
        assert_eq!(steps.total_frames(), 6);
    }
}
