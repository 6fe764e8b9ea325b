//! SVG importer with Origami Simulator's colour convention: the stroke
//! colour says what a segment is (black boundary, red mountain, blue valley,
//! green cut, yellow flat facet line, magenta undriven hinge); mountains and
//! valleys fold to opacity x 180 degrees.
//!
//! Reads `line`, `path`, `rect`, `polygon` and `polyline` under the root
//! `<svg>` and inside `<g>` groups (with their `transform`s and inherited
//! `stroke`), with `stroke` and opacity given as attributes, in a `style`
//! attribute or by the rules of `<style>` sheets (Illustrator's
//! `.st0{stroke:#FF0000}` classes: selectors by class, element name and id,
//! comma lists; see `Css`). Paths take M, L, H, V, Z, C, S, Q, T in absolute and relative
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

use super::path_data::{self, Subpath, SyntaxError};
use super::pattern::{Assignment, CreasePattern, PatternBuilder, PatternError};
use super::planar::planarize;

/// Point-merge tolerance for SVG drawings, relative to the drawing's size.
pub const SVG_TOLERANCE: f64 = 1e-4;

/// An imported SVG: the pattern, already a clean planar graph, and the
/// warnings (ignored stroke colours).
#[derive(Clone, Debug, PartialEq)]
pub struct SvgImport {
    /// The crease pattern, already a clean planar graph.
    pub pattern: CreasePattern,
    /// What the import ignored, such as unknown stroke colours, one message each.
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
    let css = Css::of(&doc);
    let mut reader = Reader::default();
    reader.container(&doc, &css, root, &Inherited::default())?;
    reader.finish()
}

/// What is wrong with one element of an SVG file; [`parse_svg`] puts it in
/// a [`PatternError`] at the element's line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
enum ElementError {
    /// The `transform` attribute cannot be read.
    #[error("transform: {0}")]
    Transform(SyntaxError),
    /// The geometry of a drawn element cannot be read.
    #[error("<{element}> {problem}")]
    Shape {
        /// The element's name (`path`, `rect`, ...).
        element: String,
        problem: ShapeError,
    },
    /// The opacity that sets the fold angle is not a number.
    #[error("opacity: bad number '{text}'")]
    Opacity { text: String },
    /// The element's transform takes its points past the largest number.
    #[error("coordinates overflow after the transform")]
    Overflow,
}

/// What is wrong with the geometry attributes of a drawn element.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
enum ShapeError {
    /// A path's `d`.
    #[error("d: {0}")]
    PathData(SyntaxError),
    /// A polygon's or polyline's `points`.
    #[error("points: {0}")]
    Points(SyntaxError),
    /// A coordinate or size attribute that is not a number.
    #[error("{attribute}: bad length '{text}' (expected a number in user units)")]
    Length {
        attribute: &'static str,
        text: String,
    },
    /// A rectangle of negative width or height.
    #[error("has a negative size ({width} x {height})")]
    NegativeSize { width: f64, height: f64 },
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
        css: &Css<'a>,
        node: Node<'a, '_>,
        inherited: &Inherited<'a>,
    ) -> Result<(), PatternError> {
        for child in node.children().filter(Node::is_element) {
            self.element(doc, css, child, inherited)?;
        }
        Ok(())
    }

    fn element<'a>(
        &mut self,
        doc: &Document,
        css: &Css<'a>,
        node: Node<'a, '_>,
        inherited: &Inherited<'a>,
    ) -> Result<(), PatternError> {
        let line = doc.text_pos_at(node.range().start).row;
        let located = |e: ElementError| PatternError::new(format!("line {line}"), e.to_string());
        let local = Inherited {
            transform: inherited.transform * transform(node).map_err(located)?,
            stroke: property(css, node, "stroke").or(inherited.stroke),
        };
        if node.tag_name().name() == "g" {
            return self.container(doc, css, node, &local);
        }
        self.drawn(css, node, line, &local).map_err(located)
    }

    /// A drawn element: its segments, or a warning for an unknown colour.
    fn drawn(
        &mut self,
        css: &Css,
        node: Node,
        line: u32,
        local: &Inherited,
    ) -> Result<(), ElementError> {
        let Some(subpaths) = shape(node).map_err(|problem| ElementError::Shape {
            element: node.tag_name().name().to_string(),
            problem,
        })?
        else {
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
            Some(sign) => Some(sign * 180.0 * opacity(css, node)?),
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
    ) -> Result<(), ElementError> {
        let points: Vec<DVec2> = subpath
            .points
            .iter()
            .map(|&p| {
                let q = transform.transform_point2(p);
                DVec2::new(q.x, -q.y)
            })
            .collect();
        if points.iter().any(|p| !p.is_finite()) {
            return Err(ElementError::Overflow);
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

/// A presentation property: the `style` declaration wins over the rules of
/// the style sheets, which win over the attribute (as in CSS).
fn property<'a>(css: &Css<'a>, node: Node<'a, '_>, name: &str) -> Option<&'a str> {
    style_declaration(node, name)
        .or_else(|| css.declaration(node, name))
        .or_else(|| node.attribute(name))
}

/// The rules of the document's `<style>` sheets, as far as crease patterns
/// use them: simple selectors (`.class`, `name`, `#id`, `name.class`, with
/// comma lists), the most specific matching rule winning (id over class
/// over element name), the later one among equals. Comments and at-rules
/// (`@media` ...) are skipped; combinators and pseudo-classes never match.
#[derive(Debug, Default)]
struct Css<'a> {
    rules: Vec<CssRule<'a>>,
}

#[derive(Debug)]
struct CssRule<'a> {
    selector: Selector<'a>,
    declarations: Vec<(&'a str, &'a str)>,
}

#[derive(Debug, Default, PartialEq)]
struct Selector<'a> {
    name: Option<&'a str>,
    class: Option<&'a str>,
    id: Option<&'a str>,
}

impl<'a> Selector<'a> {
    /// A simple selector, or `None` for what this reader does not match
    /// (combinators, attributes, pseudo-classes).
    fn parse(text: &'a str) -> Option<Self> {
        let text = text.trim();
        if text.is_empty() || text.contains(|c: char| c.is_whitespace() || "[]:>+~*".contains(c)) {
            return None;
        }
        let mut selector = Selector::default();
        let mut rest = text;
        let end = rest.find(['.', '#']).unwrap_or(rest.len());
        if end > 0 {
            selector.name = Some(&rest[..end]);
        }
        rest = &rest[end..];
        while let Some(kind) = rest.chars().next() {
            let body = &rest[1..];
            let end = body.find(['.', '#']).unwrap_or(body.len());
            let part = &body[..end];
            if part.is_empty() {
                return None;
            }
            let slot = if kind == '.' {
                &mut selector.class
            } else {
                &mut selector.id
            };
            if slot.is_some() {
                return None;
            }
            *slot = Some(part);
            rest = &body[end..];
        }
        Some(selector)
    }

    fn matches(&self, node: Node) -> bool {
        self.name.is_none_or(|n| n == node.tag_name().name())
            && self.id.is_none_or(|id| node.attribute("id") == Some(id))
            && self.class.is_none_or(|class| {
                node.attribute("class")
                    .is_some_and(|classes| classes.split_whitespace().any(|c| c == class))
            })
    }

    fn specificity(&self) -> u32 {
        100 * self.id.is_some() as u32
            + 10 * self.class.is_some() as u32
            + self.name.is_some() as u32
    }
}

impl<'a> Css<'a> {
    /// The rules of every `<style>` element of `doc`, in document order.
    fn of(doc: &'a Document) -> Self {
        let mut css = Css::default();
        for style in doc.descendants().filter(|n| n.has_tag_name("style")) {
            for text in style.children().filter_map(|t| t.text()) {
                css.parse(text);
            }
        }
        css
    }

    fn parse(&mut self, text: &'a str) {
        let mut rest = text;
        loop {
            rest = skip_comments(rest);
            let Some(open) = rest.find('{') else { break };
            let Some(close) = rest[open..].find('}').map(|i| open + i) else {
                break;
            };
            let selectors = skip_comments(&rest[..open]);
            let body = &rest[open + 1..close];
            if selectors.trim_start().starts_with('@') {
                // An at-rule: skip its block, nested rules and all.
                rest = skip_block(&rest[open..]);
                continue;
            }
            let declarations: Vec<(&str, &str)> = body
                .split(';')
                .filter_map(|d| d.split_once(':'))
                .map(|(k, v)| (k.trim(), v.trim()))
                .collect();
            for selector in selectors.split(',').filter_map(Selector::parse) {
                self.rules.push(CssRule {
                    selector,
                    declarations: declarations.clone(),
                });
            }
            rest = &rest[close + 1..];
        }
    }

    /// The value the style sheets give `node` for `name`, if any.
    fn declaration(&self, node: Node, name: &str) -> Option<&'a str> {
        let mut best: Option<(u32, &'a str)> = None;
        for rule in self.rules.iter().filter(|r| r.selector.matches(node)) {
            let specificity = rule.selector.specificity();
            if best.is_some_and(|(s, _)| s > specificity) {
                continue;
            }
            if let Some(&(_, value)) = rule
                .declarations
                .iter()
                .rev()
                .find(|(k, _)| k.eq_ignore_ascii_case(name))
            {
                best = Some((specificity, value));
            }
        }
        best.map(|(_, value)| value)
    }
}

/// `text` from its first character that is neither white space nor in a
/// `/* ... */` comment.
fn skip_comments(text: &str) -> &str {
    let mut rest = text.trim_start();
    while let Some(body) = rest.strip_prefix("/*") {
        rest = body
            .find("*/")
            .map_or("", |end| body[end + 2..].trim_start());
    }
    rest
}

/// `text` (starting at a `{`) after its matching `}`.
fn skip_block(text: &str) -> &str {
    let mut depth = 0usize;
    for (i, c) in text.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth = depth.saturating_sub(1);
                if depth == 0 {
                    return &text[i + 1..];
                }
            }
            _ => {}
        }
    }
    ""
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
/// attribute, then style, then the style sheets' `opacity` and
/// `stroke-opacity`, else 1; clamped to [0, 1].
fn opacity(css: &Css, node: Node) -> Result<f64, ElementError> {
    let value = node
        .attribute("opacity")
        .or_else(|| style_declaration(node, "opacity"))
        .or_else(|| node.attribute("stroke-opacity"))
        .or_else(|| style_declaration(node, "stroke-opacity"))
        .or_else(|| css.declaration(node, "opacity"))
        .or_else(|| css.declaration(node, "stroke-opacity"));
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
        _ => Err(ElementError::Opacity {
            text: text.to_string(),
        }),
    }
}

/// The element's own `transform` (identity when absent).
fn transform(node: Node) -> Result<DAffine2, ElementError> {
    match node.attribute("transform") {
        Some(text) => path_data::parse_transform(text).map_err(ElementError::Transform),
        None => Ok(DAffine2::IDENTITY),
    }
}

/// The polylines a drawn element stands for; `None` for elements that draw
/// no straight lines (text, animations, metadata, ...).
fn shape(node: Node) -> Result<Option<Vec<Subpath>>, ShapeError> {
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
            let points = path_data::parse_points(text).map_err(ShapeError::Points)?;
            vec![Subpath {
                closed: node.tag_name().name() == "polygon" && points.len() > 2,
                points,
            }]
        }
        "path" => {
            let d = node.attribute("d").unwrap_or_default();
            path_data::parse_path(d).map_err(ShapeError::PathData)?
        }
        _ => return Ok(None),
    };
    Ok(Some(
        shape.into_iter().filter(|s| s.points.len() > 1).collect(),
    ))
}

fn rect(node: Node) -> Result<Vec<Subpath>, ShapeError> {
    let [x, y, w, h] = ["x", "y", "width", "height"].map(|a| length(node, a));
    let (x, y, w, h) = (x?, y?, w?, h?);
    if w < 0.0 || h < 0.0 {
        return Err(ShapeError::NegativeSize {
            width: w,
            height: h,
        });
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
fn length(node: Node, name: &'static str) -> Result<f64, ShapeError> {
    let Some(text) = node.attribute(name) else {
        return Ok(0.0);
    };
    let trimmed = text.trim();
    let number = trimmed.strip_suffix("px").unwrap_or(trimmed);
    match number.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(ShapeError::Length {
            attribute: name,
            text: text.to_string(),
        }),
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
    fn style_sheet_classes_give_stroke_and_opacity() {
        // As Illustrator writes them (Origami Simulator's Origami_Sphere_16Flaps.svg).
        let body = r#"<style type="text/css">
            /* crease colours */
            .st0{fill:none;stroke:#FF0000;stroke-width:0.5;}
            .st1{fill:none;stroke:#0000FF;stroke-opacity:0.5;}
            line.edge, #outline { stroke: #000 }
            @media print { .st0 { stroke: #00FF00 } }
            g .st0 { stroke: #FFFF00 }
            .weak { stroke: #FF0000 } .weak { stroke-opacity: 25% }
        </style>
        <line x1="0" y1="0" x2="1" y2="0" class="st0"/>
        <line x1="0" y1="1" x2="1" y2="1" class="other st1"/>
        <line x1="0" y1="2" x2="1" y2="2" class="st1" stroke="red"/>
        <line x1="0" y1="3" x2="1" y2="3" class="st1" style="stroke:red"/>
        <line x1="0" y1="4" x2="1" y2="4" class="edge"/>
        <path d="M0,5 L1,5" class="edge"/>
        <polyline points="0,6 1,6" id="outline" class="st1"/>
        <line x1="0" y1="7" x2="1" y2="7" class="weak"/>"#;
        let p = parse_svg(&svg(body)).unwrap().pattern;
        let at = |y: f64| {
            let e = p
                .edges
                .iter()
                .find(|e| p.vertices[e.v[0]].y == -y)
                .unwrap_or_else(|| panic!("no edge at y = {y}"));
            (e.assignment, e.fold_angle)
        };
        assert_eq!(at(0.0), (Assignment::Mountain, Some(-180.0)));
        assert_eq!(at(1.0), (Assignment::Valley, Some(90.0)));
        // The style sheet wins over the attribute, the style attribute over both.
        assert_eq!(at(2.0), (Assignment::Valley, Some(90.0)));
        assert_eq!(at(3.0).0, Assignment::Mountain);
        assert_eq!(at(4.0).0, Assignment::Boundary);
        // `line.edge` does not select a path; the id wins over the class.
        assert!(p.edges.iter().all(|e| p.vertices[e.v[0]].y != -5.0));
        assert_eq!(at(6.0).0, Assignment::Boundary);
        assert_eq!(at(7.0), (Assignment::Mountain, Some(-45.0)));
    }

    #[test]
    fn selectors_this_reader_matches() {
        assert_eq!(
            Selector::parse("path.st0"),
            Some(Selector {
                name: Some("path"),
                class: Some("st0"),
                id: None
            })
        );
        assert_eq!(Selector::parse("#a").unwrap().specificity(), 100);
        for ignored in ["g .st0", "a > b", ".a:hover", "[x]", "*", ".", ".a.b", ""] {
            assert_eq!(Selector::parse(ignored), None, "{ignored}");
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
