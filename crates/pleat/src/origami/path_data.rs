//! The small SVG grammars the importer needs: path data (`d`; cubic and
//! quadratic Bezier curves flattened into [`CURVE_SEGMENTS`] straight
//! pieces, as curved creases are folded as polylines; arcs refused), point
//! lists (`points`) and `transform` lists.

use glam::{DAffine2, DVec2};

/// Straight pieces a Bezier curve of path data becomes.
pub const CURVE_SEGMENTS: usize = 8;

/// Why path data, a point list or a transform list cannot be read.
/// Characters are counted from 1.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SyntaxError {
    /// No number where one is needed.
    #[error("expected a number at character {at}")]
    ExpectedNumber { at: usize },
    /// A number that does not parse or is not finite (`1e999`).
    #[error("bad number '{token}' at character {at}")]
    BadNumber { token: String, at: usize },
    /// Path data starts with numbers, not a command.
    #[error("path data must start with a moveto (M or m)")]
    NoMoveto,
    /// Path data starts with a command other than a moveto.
    #[error("path data must start with a moveto (M or m), found '{found}'")]
    FirstCommand { found: char },
    /// Numbers after a closepath, which takes none.
    #[error("expected a command after 'z'")]
    NumbersAfterClose,
    /// An elliptical arc (`A`, `a`).
    #[error(
        "arc command '{command}' is not supported (flatten arcs to line segments or Bezier curves)"
    )]
    Arc { command: char },
    /// A letter that is no path command.
    #[error("unknown command '{command}' at character {at}")]
    UnknownCommand { command: char, at: usize },
    /// A point list with an x and no y.
    #[error("odd number of coordinates ({count})")]
    OddCoordinates { count: usize },
    /// A transform function name not followed by `(`.
    #[error("expected '(' after '{name}' at character {at}")]
    ExpectedOpen { name: String, at: usize },
    /// A transform function's arguments never closed.
    #[error("missing ')' after '{name}('")]
    MissingClose { name: String },
    /// A transform function given a count of numbers it does not take.
    #[error("{name} takes {allowed:?} numbers, found {found}")]
    Arity {
        name: &'static str,
        allowed: &'static [usize],
        found: usize,
    },
    /// A transform function SVG does not have.
    #[error("unknown transform function '{name}'")]
    UnknownTransform { name: String },
}

/// One subpath of a path, polygon or polyline: its points in order and
/// whether it closes back to the first.
#[derive(Clone, Debug, PartialEq)]
pub struct Subpath {
    pub points: Vec<DVec2>,
    pub closed: bool,
}

/// Reads numbers, command letters and separators (whitespace, commas).
struct Scanner<'a> {
    text: &'a str,
    pos: usize,
}

impl<'a> Scanner<'a> {
    fn new(text: &'a str) -> Self {
        Scanner { text, pos: 0 }
    }

    fn skip_separators(&mut self) {
        let rest = &self.text[self.pos..];
        let trimmed = rest.trim_start_matches(|c: char| c.is_ascii_whitespace() || c == ',');
        self.pos += rest.len() - trimmed.len();
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip_separators();
        self.text.as_bytes().get(self.pos).copied()
    }

    /// The next command letter, consumed, if the next token is a letter.
    fn letter(&mut self) -> Option<u8> {
        let c = self.peek().filter(u8::is_ascii_alphabetic)?;
        self.pos += 1;
        Some(c)
    }

    /// Characters 1-based, for messages.
    fn position(&self) -> usize {
        self.text[..self.pos].chars().count() + 1
    }

    fn number(&mut self) -> Result<f64, SyntaxError> {
        self.skip_separators();
        let bytes = self.text.as_bytes();
        let start = self.pos;
        let mut end = start;
        let digits = |from: usize| {
            bytes[from..]
                .iter()
                .take_while(|b| b.is_ascii_digit())
                .count()
        };
        if matches!(bytes.get(end), Some(b'+' | b'-')) {
            end += 1;
        }
        let whole = digits(end);
        end += whole;
        let mut fraction = 0;
        if bytes.get(end) == Some(&b'.') {
            fraction = digits(end + 1);
            end += 1 + fraction;
        }
        if whole + fraction == 0 {
            return Err(SyntaxError::ExpectedNumber {
                at: self.position(),
            });
        }
        if matches!(bytes.get(end), Some(b'e' | b'E')) {
            let sign = usize::from(matches!(bytes.get(end + 1), Some(b'+' | b'-')));
            let exponent = digits(end + 1 + sign);
            if exponent > 0 {
                end += 1 + sign + exponent;
            }
        }
        let token = &self.text[start..end];
        match token.parse::<f64>() {
            Ok(v) if v.is_finite() => {
                self.pos = end;
                Ok(v)
            }
            _ => Err(SyntaxError::BadNumber {
                token: token.to_string(),
                at: self.position(),
            }),
        }
    }

    fn pair(&mut self) -> Result<DVec2, SyntaxError> {
        Ok(DVec2::new(self.number()?, self.number()?))
    }
}

/// Path data with M, L, H, V, Z, C, S, Q, T (absolute and relative) into
/// subpaths.
pub fn parse_path(d: &str) -> Result<Vec<Subpath>, SyntaxError> {
    let mut s = Scanner::new(d);
    let mut pen = PathPen::default();
    let mut command: Option<u8> = None;
    while s.peek().is_some() {
        let c = match (s.letter(), command) {
            (Some(letter), _) => letter,
            (None, Some(previous)) => repeated(previous)?,
            (None, None) => return Err(SyntaxError::NoMoveto),
        };
        if command.is_none() && !matches!(c, b'M' | b'm') {
            return Err(SyntaxError::FirstCommand { found: c as char });
        }
        pen.apply(c, &mut s)?;
        command = Some(c);
    }
    Ok(pen.finish())
}

/// The command a bare number repeats: a moveto's extra pairs are linetos.
fn repeated(previous: u8) -> Result<u8, SyntaxError> {
    match previous {
        b'M' => Ok(b'L'),
        b'm' => Ok(b'l'),
        b'Z' | b'z' => Err(SyntaxError::NumbersAfterClose),
        other => Ok(other),
    }
}

/// The current point and the subpaths drawn so far.
#[derive(Default)]
struct PathPen {
    at: DVec2,
    start: DVec2,
    current: Option<Subpath>,
    done: Vec<Subpath>,
    /// The last control point of the previous command when it was a cubic
    /// (`C`, `S`) or quadratic (`Q`, `T`) curve, which `S` and `T` reflect.
    last_cubic: Option<DVec2>,
    last_quadratic: Option<DVec2>,
}

impl PathPen {
    fn apply(&mut self, command: u8, s: &mut Scanner) -> Result<(), SyntaxError> {
        let relative = command.is_ascii_lowercase();
        let origin = if relative { self.at } else { DVec2::ZERO };
        let (last_cubic, last_quadratic) = (self.last_cubic.take(), self.last_quadratic.take());
        // The reflection of a previous control point about the current
        // point, or the current point itself.
        let reflect = |control: Option<DVec2>, at: DVec2| control.map_or(at, |c| 2.0 * at - c);
        match command.to_ascii_uppercase() {
            b'M' => {
                self.end_subpath();
                self.at = origin + s.pair()?;
                self.start = self.at;
                self.current = Some(Subpath {
                    points: vec![self.at],
                    closed: false,
                });
            }
            b'L' => self.line_to(origin + s.pair()?),
            b'H' => self.line_to(DVec2::new(origin.x + s.number()?, self.at.y)),
            b'V' => self.line_to(DVec2::new(self.at.x, origin.y + s.number()?)),
            b'Z' => {
                if let Some(current) = &mut self.current {
                    current.closed = true;
                }
                self.end_subpath();
                self.at = self.start;
            }
            b'C' => {
                let c1 = origin + s.pair()?;
                let c2 = origin + s.pair()?;
                let end = origin + s.pair()?;
                self.cubic_to(c1, c2, end);
            }
            b'S' => {
                let c1 = reflect(last_cubic, self.at);
                let c2 = origin + s.pair()?;
                let end = origin + s.pair()?;
                self.cubic_to(c1, c2, end);
            }
            b'Q' => {
                let c = origin + s.pair()?;
                let end = origin + s.pair()?;
                self.quadratic_to(c, end);
            }
            b'T' => {
                let c = reflect(last_quadratic, self.at);
                let end = origin + s.pair()?;
                self.quadratic_to(c, end);
            }
            b'A' => {
                return Err(SyntaxError::Arc {
                    command: command as char,
                })
            }
            _ => {
                return Err(SyntaxError::UnknownCommand {
                    command: command as char,
                    at: s.position() - 1,
                })
            }
        }
        Ok(())
    }

    fn line_to(&mut self, p: DVec2) {
        let start = self.at;
        self.current
            .get_or_insert_with(|| Subpath {
                points: vec![start],
                closed: false,
            })
            .points
            .push(p);
        self.at = p;
    }

    /// The cubic Bezier curve from the current point, flattened.
    fn cubic_to(&mut self, c1: DVec2, c2: DVec2, end: DVec2) {
        let p0 = self.at;
        for k in 1..=CURVE_SEGMENTS {
            let t = k as f64 / CURVE_SEGMENTS as f64;
            let u = 1.0 - t;
            let p = u * u * u * p0 + 3.0 * u * u * t * c1 + 3.0 * u * t * t * c2 + t * t * t * end;
            // The end point exactly, so that curves meet their neighbours.
            self.line_to(if k == CURVE_SEGMENTS { end } else { p });
        }
        self.last_cubic = Some(c2);
    }

    /// The quadratic Bezier curve from the current point, flattened.
    fn quadratic_to(&mut self, c: DVec2, end: DVec2) {
        let p0 = self.at;
        for k in 1..=CURVE_SEGMENTS {
            let t = k as f64 / CURVE_SEGMENTS as f64;
            let u = 1.0 - t;
            let p = u * u * p0 + 2.0 * u * t * c + t * t * end;
            self.line_to(if k == CURVE_SEGMENTS { end } else { p });
        }
        self.last_quadratic = Some(c);
    }

    fn end_subpath(&mut self) {
        if let Some(done) = self.current.take() {
            self.done.push(done);
        }
    }

    fn finish(mut self) -> Vec<Subpath> {
        self.end_subpath();
        self.done
    }
}

/// A `points` list: x, y pairs.
pub fn parse_points(text: &str) -> Result<Vec<DVec2>, SyntaxError> {
    let mut s = Scanner::new(text);
    let mut numbers = Vec::new();
    while s.peek().is_some() {
        numbers.push(s.number()?);
    }
    if numbers.len() % 2 == 1 {
        return Err(SyntaxError::OddCoordinates {
            count: numbers.len(),
        });
    }
    Ok(numbers
        .chunks_exact(2)
        .map(|c| DVec2::new(c[0], c[1]))
        .collect())
}

/// A `transform` list: matrix, translate, scale, rotate, skewX, skewY,
/// applied right to left as SVG does.
pub fn parse_transform(text: &str) -> Result<DAffine2, SyntaxError> {
    let mut s = Scanner::new(text);
    let mut total = DAffine2::IDENTITY;
    while s.peek().is_some() {
        let start = s.pos;
        let name_len = s.text[start..]
            .bytes()
            .take_while(u8::is_ascii_alphabetic)
            .count();
        let name = &s.text[start..start + name_len];
        s.pos += name_len;
        if s.peek() != Some(b'(') {
            return Err(SyntaxError::ExpectedOpen {
                name: name.to_string(),
                at: s.position(),
            });
        }
        s.pos += 1;
        let mut args = Vec::new();
        while s.peek().is_some_and(|c| c != b')') {
            args.push(s.number()?);
        }
        if s.peek().is_none() {
            return Err(SyntaxError::MissingClose {
                name: name.to_string(),
            });
        }
        s.pos += 1;
        total *= transform_function(name, &args)?;
    }
    Ok(total)
}

fn transform_function(name: &str, args: &[f64]) -> Result<DAffine2, SyntaxError> {
    let arity = |name: &'static str, allowed: &'static [usize]| {
        if allowed.contains(&args.len()) {
            Ok(())
        } else {
            Err(SyntaxError::Arity {
                name,
                allowed,
                found: args.len(),
            })
        }
    };
    match name {
        "matrix" => {
            arity("matrix", &[6])?;
            Ok(DAffine2::from_cols_array(&[
                args[0], args[1], args[2], args[3], args[4], args[5],
            ]))
        }
        "translate" => {
            arity("translate", &[1, 2])?;
            let ty = args.get(1).copied().unwrap_or(0.0);
            Ok(DAffine2::from_translation(DVec2::new(args[0], ty)))
        }
        "scale" => {
            arity("scale", &[1, 2])?;
            let sy = args.get(1).copied().unwrap_or(args[0]);
            Ok(DAffine2::from_scale(DVec2::new(args[0], sy)))
        }
        "rotate" => {
            arity("rotate", &[1, 3])?;
            let centre = if args.len() == 3 {
                DVec2::new(args[1], args[2])
            } else {
                DVec2::ZERO
            };
            Ok(DAffine2::from_translation(centre)
                * DAffine2::from_angle(args[0].to_radians())
                * DAffine2::from_translation(-centre))
        }
        "skewX" => {
            arity("skewX", &[1])?;
            Ok(DAffine2::from_cols_array(&[
                1.0,
                0.0,
                args[0].to_radians().tan(),
                1.0,
                0.0,
                0.0,
            ]))
        }
        "skewY" => {
            arity("skewY", &[1])?;
            Ok(DAffine2::from_cols_array(&[
                1.0,
                args[0].to_radians().tan(),
                0.0,
                1.0,
                0.0,
                0.0,
            ]))
        }
        other => Err(SyntaxError::UnknownTransform {
            name: other.to_string(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn points(sub: &Subpath) -> Vec<(f64, f64)> {
        sub.points.iter().map(|p| (p.x, p.y)).collect()
    }

    #[test]
    fn illustrator_path_with_relative_commands_and_subpaths() {
        let d = "M2545.941,2362.354H493V309.412h2052.941V2362.354z M493,1335.882h2052.941 M1519.471,309.412v1026.471";
        let subs = parse_path(d).unwrap();
        assert_eq!(subs.len(), 3);
        assert!(subs[0].closed);
        assert_eq!(subs[0].points.len(), 5);
        assert_eq!(points(&subs[1]), [(493.0, 1335.882), (2545.941, 1335.882)]);
        assert!((subs[2].points[1].y - 1335.883).abs() < 1e-9);
    }

    #[test]
    fn packed_numbers_implicit_linetos_and_drawing_after_close() {
        let subs = parse_path("m10-92.5.5 1 1e1,0L1 1z l1 0").unwrap();
        assert_eq!(
            points(&subs[0]),
            [(10.0, -92.5), (10.5, -91.5), (20.5, -91.5), (1.0, 1.0)]
        );
        assert!(subs[0].closed);
        assert_eq!(points(&subs[1]), [(10.0, -92.5), (11.0, -92.5)]);
    }

    #[test]
    fn bezier_curves_are_flattened_through_their_points() {
        // A cubic from (0, 0) to (3, 0) with controls (1, 3), (2, 3): its
        // middle is at (1.5, 2.25); then a smooth continuation (relative),
        // whose first control mirrors (2, 3) about (3, 0).
        let paths = parse_path("M0 0 C1 3 2 3 3 0 s2 -3 3 0").unwrap();
        let p = &paths[0].points;
        assert_eq!(p.len(), 1 + 2 * CURVE_SEGMENTS);
        let middle = p[CURVE_SEGMENTS / 2];
        assert!(
            (middle - DVec2::new(1.5, 2.25)).length() < 1e-12,
            "{middle}"
        );
        assert_eq!(p[CURVE_SEGMENTS], DVec2::new(3.0, 0.0));
        assert_eq!(*p.last().unwrap(), DVec2::new(6.0, 0.0));
        // The smooth curve is the first one turned over: below the axis.
        let second = p[CURVE_SEGMENTS + CURVE_SEGMENTS / 2];
        assert!(
            (second - DVec2::new(4.5, -2.25)).length() < 1e-12,
            "{second}"
        );
        // A quadratic and its smooth continuation.
        let q = parse_path("M0 0 Q1 2 2 0 T4 0").unwrap();
        let q = &q[0].points;
        assert!((q[CURVE_SEGMENTS / 2] - DVec2::new(1.0, 1.0)).length() < 1e-12);
        assert!((q[CURVE_SEGMENTS + CURVE_SEGMENTS / 2] - DVec2::new(3.0, -1.0)).length() < 1e-12);
        // An S after a line uses the current point as its first control.
        let s = parse_path("M0 0 L1 0 S2 1 3 0").unwrap();
        assert_eq!(*s[0].points.last().unwrap(), DVec2::new(3.0, 0.0));
    }

    #[test]
    fn path_errors() {
        assert!(parse_path("L1 1")
            .unwrap_err()
            .to_string()
            .contains("must start with a moveto"));
        assert!(parse_path("M1 1 a1 1 0 0 1 2 2")
            .unwrap_err()
            .to_string()
            .contains("arc command 'a'"));
        assert!(parse_path("M1 1 c1 1 2")
            .unwrap_err()
            .to_string()
            .contains("expected a number"));
        assert!(parse_path("M1 1 L2")
            .unwrap_err()
            .to_string()
            .contains("expected a number"));
        assert!(parse_path("M1 1 X")
            .unwrap_err()
            .to_string()
            .contains("unknown command 'X'"));
        assert!(parse_path("M1 1z 3")
            .unwrap_err()
            .to_string()
            .contains("after 'z'"));
        assert!(parse_path("M1e999 1")
            .unwrap_err()
            .to_string()
            .contains("bad number"));
        assert_eq!(
            parse_path("M1 1 X").unwrap_err(),
            SyntaxError::UnknownCommand {
                command: 'X',
                at: 6
            }
        );
    }

    #[test]
    fn points_lists() {
        assert_eq!(parse_points(" 0,0 1,2 ").unwrap().len(), 2);
        assert!(parse_points("0 0 1")
            .unwrap_err()
            .to_string()
            .contains("odd number"));
    }

    #[test]
    fn transforms_compose_like_svg() {
        assert_eq!(
            parse_transform("scale(1 2 3)").unwrap_err(),
            SyntaxError::Arity {
                name: "scale",
                allowed: &[1, 2],
                found: 3
            }
        );
        let t = parse_transform("translate(10, 5) scale(2) rotate(90)").unwrap();
        let p = t.transform_point2(DVec2::new(1.0, 0.0));
        assert!((p - DVec2::new(10.0, 7.0)).length() < 1e-12, "{p}");
        let m = parse_transform("matrix(1 0 0 1 3 4)").unwrap();
        assert_eq!(m.transform_point2(DVec2::ZERO), DVec2::new(3.0, 4.0));
        assert!(parse_transform("scale(1 2 3)")
            .unwrap_err()
            .to_string()
            .contains("scale takes"));
        assert!(parse_transform("spin(3)")
            .unwrap_err()
            .to_string()
            .contains("unknown transform"));
        assert!(parse_transform("scale(1")
            .unwrap_err()
            .to_string()
            .contains("missing ')'"));
    }
}
