//! SVG importer with Origami Simulator's colour convention: the stroke
//! colour says what a segment is (black boundary, red mountain, blue valley,
//! green cut, yellow flat facet line, magenta undriven hinge); mountains and
//! valleys fold to opacity x 180 degrees.
//!
//! Reads `line`, `path`, `rect`, `polygon` and `polyline` under the root
//! `<svg>` and inside `<g>` groups (with their `transform`s and inherited
//! `stroke`). Paths take M, L, H, V, Z, C, S, Q, T in absolute and relative
//! form: curves (curved creases) become polylines of 8 straight pieces;
//! arcs (A) are refused with an error naming them. Rounded rectangle corners (`rx`) are drawn square.
//! Strokes of other colours are ignored with a warning. The y axis is turned
//! to point up, so the sheet looks like the drawing seen from +z.
//!
//! Illustrator rounds coordinates to three decimals and chains relative
//! commands, so end points that should meet can miss each other by a few
//! thousandths; the importer therefore merges points closer than
//! [`SVG_TOLERANCE`] times the drawing's diameter.

use std::collections::BTreeMap;

use glam::{DAffine2, DVec2};
use roxmltree::{Document, Node, ParsingOptions};

use super::path_data::{self, Subpath};
use super::pattern::{Assignment, CreasePattern, PatternBuilder, PatternError};
use super::planar::planarize;

/// Point-merge tolerance for SVG drawings, relative to the drawing's size.
pub const SVG_TOLERANCE: f64 = 1e-4;

/// An imported SVG: the pattern, already a clean planar graph, and the
/// warnings (ignored stroke colours).
#[derive(Clone, Debug, PartialEq)]
pub struct SvgImport {
    pub pattern: CreasePattern,
    pub warnings: Vec<String>,
}

/// What a stroke colour means.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Stroke {
    Meaningful(Assignment),
    /// `none`, or no stroke at all: not drawn, silently skipped.
    Absent,
    Other,
}

/// Parses the text of an SVG file.
pub fn parse_svg(text: &str) -> Result<SvgImport, PatternError> {
    let options = ParsingOptions {
        allow_dtd: true,
        ..ParsingOptions::default()
    };
    let doc = Document::parse_with_options(text, options).map_err(|e| {
        let pos = e.pos();
        let message = e.to_string();
        let suffix = format!(" at {}:{}", pos.row, pos.col);
        let reason = message.strip_suffix(&suffix).unwrap_or(&message);
        PatternError::new(
            format!("line {}, column {}", pos.row, pos.col),
            format!("bad XML: {reason}"),
        )
    })?;
    let root = doc.root_element();
    if root.tag_name().name() != "svg" {
        return Err(PatternError::new(
            "top level",
            format!(
                "expected an <svg> root element, found <{}>",
                root.tag_name().name()
            ),
        ));
    }
    let mut reader = Reader::default();
    reader.container(&doc, root, &Inherited::default())?;
    reader.finish()
}

/// What a `<g>` passes on to its children.
#[derive(Clone, Debug, Default)]
struct Inherited<'a> {
    transform: DAffine2,
    stroke: Option<&'a str>,
}

#[derive(Default)]
struct Reader {
    builder: PatternBuilder,
    segments: usize,
    /// Ignored colour -> (elements, line of the first).
    ignored: BTreeMap<String, (usize, u32)>,
}

impl Reader {
    fn container<'a>(
        &mut self,
        doc: &Document,
        node: Node<'a, '_>,
        inherited: &Inherited<'a>,
    ) -> Result<(), PatternError> {
        for child in node.children().filter(Node::is_element) {
            self.element(doc, child, inherited)?;
        }
        Ok(())
    }

    fn element<'a>(
        &mut self,
        doc: &Document,
        node: Node<'a, '_>,
        inherited: &Inherited<'a>,
    ) -> Result<(), PatternError> {
        let line = doc.text_pos_at(node.range().start).row;
        let located = |reason: String| PatternError::new(format!("line {line}"), reason);
        let local = Inherited {
            transform: inherited.transform * transform(node).map_err(located)?,
            stroke: property(node, "stroke").or(inherited.stroke),
        };
        if node.tag_name().name() == "g" {
            return self.container(doc, node, &local);
        }
        self.drawn(node, line, &local).map_err(located)
    }

    /// A drawn element: its segments, or a warning for an unknown colour.
    fn drawn(&mut self, node: Node, line: u32, local: &Inherited) -> Result<(), String> {
        let name = node.tag_name().name();
        let Some(subpaths) = shape(node).map_err(|e| format!("<{name}> {e}"))? else {
            return Ok(());
        };
        let assignment = match classify(local.stroke) {
            Stroke::Meaningful(a) => a,
            Stroke::Absent => return Ok(()),
            Stroke::Other => {
                let colour = local.stroke.unwrap_or_default().trim().to_string();
                self.ignored.entry(colour).or_insert((0, line)).0 += 1;
                return Ok(());
            }
        };
        let fold_angle = match assignment.fold_sign() {
            Some(sign) => Some(sign * 180.0 * opacity(node)?),
            None => None,
        };
        for subpath in subpaths {
            self.subpath(&subpath, local.transform, assignment, fold_angle)?;
        }
        Ok(())
    }

    fn subpath(
        &mut self,
        subpath: &Subpath,
        transform: DAffine2,
        assignment: Assignment,
        fold_angle: Option<f64>,
    ) -> Result<(), String> {
        let points: Vec<DVec2> = subpath
            .points
            .iter()
            .map(|&p| {
                let q = transform.transform_point2(p);
                DVec2::new(q.x, -q.y)
            })
            .collect();
        if points.iter().any(|p| !p.is_finite()) {
            return Err("coordinates overflow after the transform".into());
        }
        let closing = subpath
            .closed
            .then(|| [points[points.len() - 1], points[0]]);
        for pair in points.windows(2).map(|w| [w[0], w[1]]).chain(closing) {
            self.builder
                .segment(pair[0], pair[1], assignment, fold_angle);
            self.segments += 1;
        }
        Ok(())
    }

    fn finish(self) -> Result<SvgImport, PatternError> {
        let warnings: Vec<String> = self
            .ignored
            .iter()
            .map(|(colour, (count, line))| {
                format!(
                    "line {line}: stroke '{colour}' is not one of Origami Simulator's colours; \
                     {count} element(s) with it ignored"
                )
            })
            .collect();
        if self.segments == 0 {
            let mut reason = String::from(
                "no segments: no line, path, rect, polygon or polyline stroked black, red, blue, \
                 green, yellow or magenta",
            );
            if !warnings.is_empty() {
                reason.push_str(&format!(" ({})", warnings.join("; ")));
            }
            return Err(PatternError::new("", reason));
        }
        let pattern = planarize(&self.builder.finish(), SVG_TOLERANCE)?;
        Ok(SvgImport { pattern, warnings })
    }
}

/// A presentation property: the `style` declaration wins over the attribute.
fn property<'a>(node: Node<'a, '_>, name: &str) -> Option<&'a str> {
    style_declaration(node, name).or_else(|| node.attribute(name))
}

fn style_declaration<'a>(node: Node<'a, '_>, name: &str) -> Option<&'a str> {
    node.attribute("style")?
        .split(';')
        .filter_map(|decl| decl.split_once(':'))
        .find(|(key, _)| key.trim().eq_ignore_ascii_case(name))
        .map(|(_, value)| value.trim())
}

/// Origami Simulator's table, compared lowercased in hex6, hex3, name or
/// `rgb(r, g, b)` form.
fn classify(stroke: Option<&str>) -> Stroke {
    let Some(stroke) = stroke else {
        return Stroke::Absent;
    };
    let value = stroke.trim().to_ascii_lowercase();
    if value == "none" || value.is_empty() {
        return Stroke::Absent;
    }
    let Some(rgb) = parse_colour(&value) else {
        return Stroke::Other;
    };
    match rgb {
        [0, 0, 0] => Stroke::Meaningful(Assignment::Boundary),
        [255, 0, 0] => Stroke::Meaningful(Assignment::Mountain),
        [0, 0, 255] => Stroke::Meaningful(Assignment::Valley),
        [0, 255, 0] => Stroke::Meaningful(Assignment::Cut),
        [255, 255, 0] => Stroke::Meaningful(Assignment::Flat),
        [255, 0, 255] => Stroke::Meaningful(Assignment::Unassigned),
        _ => Stroke::Other,
    }
}

fn parse_colour(value: &str) -> Option<[u8; 3]> {
    if let Some(hex) = value.strip_prefix('#') {
        return parse_hex(hex);
    }
    if let Some(args) = value.strip_prefix("rgb(").and_then(|v| v.strip_suffix(')')) {
        let parts: Vec<&str> = args.split(',').map(str::trim).collect();
        let [r, g, b] = parts.as_slice() else {
            return None;
        };
        return Some([r.parse().ok()?, g.parse().ok()?, b.parse().ok()?]);
    }
    // Names as Origami Simulator reads them: "green" is its cut colour.
    match value {
        "black" => Some([0, 0, 0]),
        "red" => Some([255, 0, 0]),
        "blue" => Some([0, 0, 255]),
        "green" | "lime" => Some([0, 255, 0]),
        "yellow" => Some([255, 255, 0]),
        "magenta" | "fuchsia" => Some([255, 0, 255]),
        _ => None,
    }
}

fn parse_hex(hex: &str) -> Option<[u8; 3]> {
    if !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let digit = |i: usize| u8::from_str_radix(&hex[i..=i], 16).ok();
    match hex.len() {
        3 => Some([digit(0)? * 17, digit(1)? * 17, digit(2)? * 17]),
        6 => {
            let pair = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).ok();
            Some([pair(0)?, pair(2)?, pair(4)?])
        }
        _ => None,
    }
}

/// `opacity` attribute, else `opacity` style, else `stroke-opacity`
/// attribute, then style, else 1; clamped to [0, 1].
fn opacity(node: Node) -> Result<f64, String> {
    let value = node
        .attribute("opacity")
        .or_else(|| style_declaration(node, "opacity"))
        .or_else(|| node.attribute("stroke-opacity"))
        .or_else(|| style_declaration(node, "stroke-opacity"));
    let Some(text) = value else {
        return Ok(1.0);
    };
    let trimmed = text.trim();
    let (number, scale) = match trimmed.strip_suffix('%') {
        Some(percent) => (percent, 0.01),
        None => (trimmed, 1.0),
    };
    match number.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok((v * scale).clamp(0.0, 1.0)),
        _ => Err(format!("opacity: bad number '{text}'")),
    }
}

/// The element's own `transform` (identity when absent).
fn transform(node: Node) -> Result<DAffine2, String> {
    match node.attribute("transform") {
        Some(text) => path_data::parse_transform(text).map_err(|e| format!("transform: {e}")),
        None => Ok(DAffine2::IDENTITY),
    }
}

/// The polylines a drawn element stands for; `None` for elements that draw
/// no straight lines (text, animations, metadata, ...).
fn shape(node: Node) -> Result<Option<Vec<Subpath>>, String> {
    let shape = match node.tag_name().name() {
        "line" => {
            let [x1, y1, x2, y2] = ["x1", "y1", "x2", "y2"].map(|a| length(node, a));
            vec![Subpath {
                points: vec![DVec2::new(x1?, y1?), DVec2::new(x2?, y2?)],
                closed: false,
            }]
        }
        "rect" => rect(node)?,
        "polygon" | "polyline" => {
            let text = node.attribute("points").unwrap_or_default();
            let points = path_data::parse_points(text).map_err(|e| format!("points: {e}"))?;
            vec![Subpath {
                closed: node.tag_name().name() == "polygon" && points.len() > 2,
                points,
            }]
        }
        "path" => {
            let d = node.attribute("d").unwrap_or_default();
            path_data::parse_path(d).map_err(|e| format!("d: {e}"))?
        }
        _ => return Ok(None),
    };
    Ok(Some(
        shape.into_iter().filter(|s| s.points.len() > 1).collect(),
    ))
}

fn rect(node: Node) -> Result<Vec<Subpath>, String> {
    let [x, y, w, h] = ["x", "y", "width", "height"].map(|a| length(node, a));
    let (x, y, w, h) = (x?, y?, w?, h?);
    if w < 0.0 || h < 0.0 {
        return Err(format!("has a negative size ({w} x {h})"));
    }
    if w == 0.0 || h == 0.0 {
        return Ok(Vec::new());
    }
    Ok(vec![Subpath {
        points: vec![
            DVec2::new(x, y),
            DVec2::new(x + w, y),
            DVec2::new(x + w, y + h),
            DVec2::new(x, y + h),
        ],
        closed: true,
    }])
}

/// A coordinate attribute in user units (an optional `px` suffix); absent
/// means 0.
fn length(node: Node, name: &str) -> Result<f64, String> {
    let Some(text) = node.attribute(name) else {
        return Ok(0.0);
    };
    let trimmed = text.trim();
    let number = trimmed.strip_suffix("px").unwrap_or(trimmed);
    match number.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!(
            "{name}: bad length '{text}' (expected a number in user units)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn svg(body: &str) -> String {
        format!("<?xml version=\"1.0\"?>\r\n<!DOCTYPE svg PUBLIC \"-//W3C//DTD SVG 1.1//EN\" \"x.dtd\">\r\n<svg xmlns=\"http://www.w3.org/2000/svg\">\r\n<!-- c -->\r\n{body}\r\n</svg>")
    }

    fn count(p: &CreasePattern, a: Assignment) -> usize {
        p.edges.iter().filter(|e| e.assignment == a).count()
    }

    #[test]
    fn colours_in_every_form() {
        let body = r##"
            <rect x="0" y="0" width="10" height="10" stroke="#000"/>
            <line x1="0" y1="5" x2="10" y2="5" stroke="RED"/>
            <line x1="5" y1="0" x2="5" y2="5" style="stroke: rgb(0, 0, 255)"/>
            <line x1="5" y1="5" x2="5" y2="10" stroke="#FF00ff"/>
            <line x1="0" y1="0" x2="5" y2="5" stroke="yellow"/>
            <line x1="10" y1="0" x2="7" y2="3" stroke="green"/>
            <line x1="0" y1="10" x2="5" y2="5" stroke="#808080"/>
            <rect width="10" height="10" fill="#fff"/>"##;
        let import = parse_svg(&svg(body)).unwrap();
        let p = &import.pattern;
        assert_eq!(count(p, Assignment::Boundary), 8);
        assert_eq!(count(p, Assignment::Mountain), 2);
        assert_eq!(count(p, Assignment::Valley), 1);
        assert_eq!(count(p, Assignment::Unassigned), 1);
        assert_eq!(count(p, Assignment::Flat), 1);
        assert_eq!(count(p, Assignment::Cut), 1);
        assert_eq!(import.warnings.len(), 1);
        assert!(
            import.warnings[0].contains("#808080"),
            "{:?}",
            import.warnings
        );
    }

    #[test]
    fn opacity_sets_the_fold_angle_in_the_documented_order() {
        let body = r#"
            <line x1="0" y1="0" x2="1" y2="0" stroke="red" opacity="0.5" style="opacity:0.25"/>
            <line x1="0" y1="1" x2="1" y2="1" stroke="blue" style="opacity:0.25" stroke-opacity="0.1"/>
            <line x1="0" y1="2" x2="1" y2="2" stroke="blue" stroke-opacity="0.1" style="stroke-opacity:0.2"/>
            <line x1="0" y1="3" x2="1" y2="3" stroke="blue"/>"#;
        let p = parse_svg(&svg(body)).unwrap().pattern;
        let mut angles: Vec<f64> = p.edges.iter().map(|e| e.fold_angle.unwrap()).collect();
        angles.sort_by(f64::total_cmp);
        let expected = [-90.0, 18.0, 45.0, 180.0];
        for (a, e) in angles.iter().zip(expected) {
            assert!((a - e).abs() < 1e-9, "{angles:?}");
        }
    }

    #[test]
    fn groups_transforms_and_inherited_stroke() {
        let body = r#"<g stroke="blue" transform="translate(10 0) scale(2)">
            <line x1="0" y1="0" x2="1" y2="0"/></g>"#;
        let p = parse_svg(&svg(body)).unwrap().pattern;
        let xs: Vec<f64> = p.vertices.iter().map(|v| v.x).collect();
        assert_eq!(xs, [10.0, 12.0]);
        assert_eq!(p.edges[0].assignment, Assignment::Valley);
    }

    #[test]
    fn y_axis_points_up() {
        let p = parse_svg(&svg(r#"<line x1="0" y1="0" x2="0" y2="3" stroke="red"/>"#))
            .unwrap()
            .pattern;
        assert_eq!(p.vertices[1].y, -3.0);
    }

    #[test]
    fn errors_name_line_and_reason() {
        let e = parse_svg(&svg(r#"<path d="M0,0 A1,1 0 0 1 3,3" stroke="red"/>"#)).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("line 5: <path> d: arc command 'A'"),
            "{e}"
        );
        let e = parse_svg(&svg(r#"<line x1="a" stroke="red"/>"#)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 5: <line> x1: bad length 'a' (expected a number in user units)"
        );
        let e = parse_svg(&svg(r#"<line x2="1" stroke="red" opacity="half"/>"#)).unwrap_err();
        assert_eq!(e.to_string(), "line 5: opacity: bad number 'half'");
        let e = parse_svg(&svg(r#"<circle r="3" stroke="red"/>"#)).unwrap_err();
        assert!(e.reason.starts_with("no segments"), "{e}");
        let e = parse_svg("<svg><line").unwrap_err();
        assert!(e.to_string().starts_with("line 1, column "), "{e}");
        let e = parse_svg("<html/>").unwrap_err();
        assert_eq!(
            e.to_string(),
            "top level: expected an <svg> root element, found <html>"
        );
    }
}
