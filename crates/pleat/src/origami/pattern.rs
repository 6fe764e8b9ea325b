//! The crease pattern as imported: vertices, edges with their mountain/valley
//! assignment, and the import error type.

use std::collections::HashMap;
use std::fmt;

use glam::DVec2;

/// What an edge of a crease pattern is (FOLD's `edges_assignment`, ORIPA's
/// line type, Origami Simulator's stroke colour).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Assignment {
    /// Outline of the paper, or the rim of a hole.
    Boundary,
    /// Mountain fold: folds away from the viewer (negative fold angle).
    Mountain,
    /// Valley fold: folds towards the viewer (positive fold angle).
    Valley,
    /// Facet line: a hinge that stays flat.
    Flat,
    /// A hinge with no prescribed direction; swings freely.
    Unassigned,
    /// A slit: the sheet is split along it.
    Cut,
    /// Construction line: splits faces but never folds.
    Auxiliary,
}

impl Assignment {
    /// Rank used when two edges of a pattern overlap: the higher rank wins.
    ///
    /// Boundary first (the outline must stay closed, and a crease lying on the
    /// outline folds nothing), then cuts, then creases (mountain, valley),
    /// then unassigned hinges, then flat facet lines, then auxiliary lines.
    pub fn overlap_rank(self) -> u8 {
        match self {
            Assignment::Boundary => 6,
            Assignment::Cut => 5,
            Assignment::Mountain | Assignment::Valley => 4,
            Assignment::Unassigned => 3,
            Assignment::Flat => 2,
            Assignment::Auxiliary => 1,
        }
    }

    /// The sign of the fold angle this assignment implies: +1 valley,
    /// -1 mountain, `None` for everything else.
    pub fn fold_sign(self) -> Option<f64> {
        match self {
            Assignment::Valley => Some(1.0),
            Assignment::Mountain => Some(-1.0),
            _ => None,
        }
    }
}

/// One straight segment of a crease pattern.
#[derive(Clone, Debug, PartialEq)]
pub struct PatternEdge {
    /// Indices into [`CreasePattern::vertices`].
    pub v: [usize; 2],
    /// What the segment is: boundary, mountain, valley, flat, unassigned, cut or auxiliary.
    pub assignment: Assignment,
    /// Target fold angle in degrees, signed: valley positive, mountain
    /// negative. `None`: the full fold (180 degrees) for creases, none for
    /// the rest.
    pub fold_angle: Option<f64>,
}

/// A flat crease pattern: points in the plane (arbitrary units) and the
/// segments between them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CreasePattern {
    /// Points in the plane (arbitrary units).
    pub vertices: Vec<DVec2>,
    /// The segments between the vertices.
    pub edges: Vec<PatternEdge>,
}

impl CreasePattern {
    /// Number of mountain, valley and unassigned edges.
    pub fn crease_count(&self) -> usize {
        self.edges
            .iter()
            .filter(|e| {
                matches!(
                    e.assignment,
                    Assignment::Mountain | Assignment::Valley | Assignment::Unassigned
                )
            })
            .count()
    }
}

/// Collects segments into a [`CreasePattern`], sharing a vertex between
/// segments whose end points are bit-for-bit equal (exact duplicates only;
/// near duplicates are the planar graph's job).
#[derive(Debug, Default)]
pub(crate) struct PatternBuilder {
    pattern: CreasePattern,
    index: HashMap<[u64; 2], usize>,
}

impl PatternBuilder {
    /// Adds the segment `a`-`b`.
    pub(crate) fn segment(
        &mut self,
        a: DVec2,
        b: DVec2,
        assignment: Assignment,
        fold_angle: Option<f64>,
    ) {
        let v = [self.vertex(a), self.vertex(b)];
        self.pattern.edges.push(PatternEdge {
            v,
            assignment,
            fold_angle,
        });
    }

    fn vertex(&mut self, p: DVec2) -> usize {
        // `+ 0.0` turns -0.0 into 0.0 so both hash alike.
        let key = [(p.x + 0.0).to_bits(), (p.y + 0.0).to_bits()];
        let vertices = &mut self.pattern.vertices;
        *self.index.entry(key).or_insert_with(|| {
            vertices.push(p);
            vertices.len() - 1
        })
    }

    pub(crate) fn finish(self) -> CreasePattern {
        self.pattern
    }
}

/// Why a pattern could not be imported: the file (when known), where in it
/// (`line 3`, or a JSON path such as `edges_vertices[4][1]`) and the reason.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PatternError {
    /// The file the error is in, when known.
    pub file: Option<String>,
    /// Empty when the error concerns the whole file.
    pub location: String,
    /// Why the import failed.
    pub reason: String,
}

impl PatternError {
    /// An error at `location` (may be empty) for `reason`.
    pub fn new(location: impl Into<String>, reason: impl Into<String>) -> Self {
        PatternError {
            file: None,
            location: location.into(),
            reason: reason.into(),
        }
    }

    /// The same error, naming the file it came from.
    pub fn with_file(mut self, file: impl Into<String>) -> Self {
        self.file = Some(file.into());
        self
    }
}

impl fmt::Display for PatternError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{file}: ")?;
        }
        if !self.location.is_empty() {
            write!(f, "{}: ", self.location)?;
        }
        f.write_str(&self.reason)
    }
}

impl std::error::Error for PatternError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_display_names_file_location_and_reason() {
        let e = PatternError::new("line 3", "expected 5 fields, found 4").with_file("lines.cp");
        assert_eq!(
            e.to_string(),
            "lines.cp: line 3: expected 5 fields, found 4"
        );
        let whole = PatternError::new("", "no segments");
        assert_eq!(whole.to_string(), "no segments");
    }

    #[test]
    fn builder_shares_exactly_equal_points() {
        let mut b = PatternBuilder::default();
        let (p, q, r) = (DVec2::ZERO, DVec2::X, DVec2::new(-0.0, 0.0));
        b.segment(p, q, Assignment::Valley, None);
        b.segment(q, r, Assignment::Mountain, None);
        let pattern = b.finish();
        assert_eq!(pattern.vertices.len(), 2);
        assert_eq!(pattern.edges[1].v, [1, 0]);
        assert_eq!(pattern.crease_count(), 2);
    }
}
