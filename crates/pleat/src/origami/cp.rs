//! ORIPA `.cp` importer: one segment a line, `type x1 y1 x2 y2`, type 0
//! auxiliary, 1 boundary (or cut), 2 mountain, 3 valley, 4 auxiliary (what
//! many editors write for auxiliary lines; read, never folded).
//!
//! Blank lines are skipped, fields may be separated by any whitespace, CR LF
//! line endings and a missing final newline are accepted. Coordinates are
//! kept as written.

use glam::DVec2;

use super::pattern::{Assignment, CreasePattern, PatternBuilder, PatternError};

const FIELD_NAMES: [&str; 5] = ["type", "x1", "y1", "x2", "y2"];

/// Parses the text of an ORIPA `.cp` file.
pub fn parse_cp(text: &str) -> Result<CreasePattern, PatternError> {
    let mut builder = PatternBuilder::default();
    let mut segments = 0;
    for (number, line) in text.lines().enumerate() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        let location = format!("line {}", number + 1);
        let (assignment, a, b) =
            parse_line(&fields).map_err(|e| PatternError::new(location, e.to_string()))?;
        builder.segment(a, b, assignment, None);
        segments += 1;
    }
    if segments == 0 {
        return Err(PatternError::new(
            "",
            "no segments (expected lines `type x1 y1 x2 y2`)",
        ));
    }
    Ok(builder.finish())
}

/// What is wrong with one line of a `.cp` file; [`parse_cp`] puts it in a
/// [`PatternError`] at the line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
enum LineError {
    /// Not the five fields `type x1 y1 x2 y2`.
    #[error("expected 5 fields, found {found}")]
    FieldCount { found: usize },
    /// A line type other than 0 to 4.
    #[error(
        "unknown line type '{field}' (expected 0 or 4 auxiliary, 1 boundary, 2 mountain, 3 valley)"
    )]
    LineType { field: String },
    /// A coordinate that is not a number.
    #[error("{name}: bad number '{field}'")]
    BadNumber { name: &'static str, field: String },
    /// A coordinate that is infinite or NaN.
    #[error("{name}: number '{field}' is not finite")]
    NotFinite { name: &'static str, field: String },
}

fn parse_line(fields: &[&str]) -> Result<(Assignment, DVec2, DVec2), LineError> {
    if fields.len() != FIELD_NAMES.len() {
        return Err(LineError::FieldCount {
            found: fields.len(),
        });
    }
    let assignment = line_type(fields[0])?;
    let mut numbers = [0.0; 4];
    for (i, value) in numbers.iter_mut().enumerate() {
        *value = coordinate(FIELD_NAMES[i + 1], fields[i + 1])?;
    }
    let [x1, y1, x2, y2] = numbers;
    Ok((assignment, DVec2::new(x1, y1), DVec2::new(x2, y2)))
}

fn line_type(field: &str) -> Result<Assignment, LineError> {
    match field {
        "0" | "4" => Ok(Assignment::Auxiliary),
        "1" => Ok(Assignment::Boundary),
        "2" => Ok(Assignment::Mountain),
        "3" => Ok(Assignment::Valley),
        other => Err(LineError::LineType {
            field: other.to_string(),
        }),
    }
}

fn coordinate(name: &'static str, field: &str) -> Result<f64, LineError> {
    match field.parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        Ok(_) => Err(LineError::NotFinite {
            name,
            field: field.to_string(),
        }),
        Err(_) => Err(LineError::BadNumber {
            name,
            field: field.to_string(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_types_scientific_notation_and_crlf() {
        let p = parse_cp(
            "1 -0.0 200.0 2.4492935982947064E-14 -200.0\r\n\r\n0 0 0 1 1\n2 0 0 1 0\n3 1 0 1 1\n4 0 1 1 0",
        )
        .unwrap();
        let kinds: Vec<_> = p.edges.iter().map(|e| e.assignment).collect();
        assert_eq!(
            kinds,
            [
                Assignment::Boundary,
                Assignment::Auxiliary,
                Assignment::Mountain,
                Assignment::Valley,
                Assignment::Auxiliary
            ]
        );
        assert_eq!(p.vertices[p.edges[0].v[1]].x, 2.4492935982947064E-14);
        // (0, 0), (1, 1), (1, 0) and (0, 1) are shared exactly.
        assert_eq!(p.vertices.len(), 6);
    }

    #[test]
    fn errors_name_line_and_reason() {
        let e = parse_cp("1 0 0 1 1\n\n2 0 0 1\n").unwrap_err();
        assert_eq!(e.to_string(), "line 3: expected 5 fields, found 4");
        let e = parse_cp("1 0 0 1 1\n2 0 zero 1 1").unwrap_err();
        assert_eq!(e.to_string(), "line 2: y1: bad number 'zero'");
        let e = parse_cp("7 0 0 1 1").unwrap_err();
        assert!(e.to_string().starts_with("line 1: unknown line type '7'"));
        let e = parse_cp("2 0 0 inf 1").unwrap_err();
        assert_eq!(e.to_string(), "line 1: x2: number 'inf' is not finite");
        let e = parse_cp(" \n\n").unwrap_err();
        assert!(e.reason.starts_with("no segments"));
    }
}
