//! The crease pattern as imported: vertices, edges with their mountain/valley
//! assignment, the import error type and `load_pattern`, which picks the
//! importer from the file extension.

use std::collections::HashMap;
use std::fmt;
use std::path::Path;

use glam::DVec2;

use super::{cp, fold, svg};

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
    pub vertices: Vec<DVec2>,
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
    pub file: Option<String>,
    /// Empty when the error concerns the whole file.
    pub location: String,
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

/// Reads a crease pattern, choosing the importer from the extension
/// (`.cp`, `.fold`, `.svg`, any case). Errors name the file.
pub fn load_pattern(path: impl AsRef<Path>) -> Result<CreasePattern, PatternError> {
    load_pattern_with_warnings(path).map(|(pattern, _)| pattern)
}

/// As [`load_pattern`], also returning the importer's warnings (SVG strokes
/// of colours that mean nothing in Origami Simulator's convention).
pub fn load_pattern_with_warnings(
    path: impl AsRef<Path>,
) -> Result<(CreasePattern, Vec<String>), PatternError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    read_and_parse(path).map_err(|e| e.with_file(name))
}

fn read_and_parse(path: &Path) -> Result<(CreasePattern, Vec<String>), PatternError> {
    let bytes =
        std::fs::read(path).map_err(|e| PatternError::new("", format!("cannot read: {e}")))?;
    parse_by_extension(&extension_of(path), &bytes)
}

/// Reads a crease pattern held in memory (a file dropped on a web page),
/// choosing the importer from `name`'s extension as [`load_pattern`] does;
/// errors name `name`. Also returns the importer's warnings.
pub fn parse_pattern(
    name: &str,
    bytes: &[u8],
) -> Result<(CreasePattern, Vec<String>), PatternError> {
    parse_by_extension(&extension_of(Path::new(name)), bytes).map_err(|e| e.with_file(name))
}

fn extension_of(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default()
}

fn parse_by_extension(
    extension: &str,
    bytes: &[u8],
) -> Result<(CreasePattern, Vec<String>), PatternError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        PatternError::new(format!("byte {}", e.valid_up_to()), "not valid UTF-8 text")
    })?;
    match extension {
        "cp" => cp::parse_cp(text).map(|p| (p, Vec::new())),
        "fold" => fold::parse_fold(text).map(|p| (p, Vec::new())),
        "svg" => svg::parse_svg(text).map(|import| (import.pattern, import.warnings)),
        other => Err(PatternError::new(
            "",
            format!("unknown crease-pattern extension '.{other}' (expected .cp, .fold or .svg)"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_in_memory_read_as_files_do() {
        let (p, _) = parse_pattern(
            "drop.CP",
            b"1 0 0 1 0\n1 1 0 1 1\n1 1 1 0 1\n1 0 1 0 0\n2 0 0 1 1\n",
        )
        .unwrap();
        assert_eq!(p.edges.len(), 5);
        let e = parse_pattern("drop.cp", b"1 0 0 1\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("drop.cp: line 1"), "{e}");
        let e = parse_pattern("drop.png", b"").unwrap_err().to_string();
        assert!(e.contains("drop.png") && e.contains(".png"), "{e}");
    }

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

    #[test]
    fn unknown_extension_is_refused_with_file_name() {
        let dir = std::env::temp_dir().join("pleat-pattern-ext-test.txt");
        std::fs::write(&dir, "1 0 0 1 1").unwrap();
        let e = load_pattern(&dir).unwrap_err();
        assert!(e.to_string().contains("pleat-pattern-ext-test.txt"));
        assert!(e.reason.contains("unknown crease-pattern extension"));
    }
}
