//! Built-in parametric crease patterns: single line, parallel lines
//! (pleats), waterbomb base, Miura-ori, waterbomb tessellation, Yoshimura,
//! Kresling and the square twist.
//!
//! Every pattern is flat-foldable at each interior vertex: Maekawa's theorem
//! (|M - V| = 2) and Kawasaki's theorem (alternate sector angles sum to 180
//! degrees) hold, which the tests check. Segments may end on other segments
//! (T-junctions); the planar graph splits them. Out-of-range parameters are
//! clamped to the documented ranges rather than refused.

use std::f64::consts::PI;

use glam::DVec2;

use super::pattern::{Assignment, CreasePattern, PatternBuilder};

use Assignment::{Boundary, Mountain, Valley};

/// The names [`builtin`] knows.
pub const BUILTIN_NAMES: [&str; 8] = [
    "single-line",
    "parallel-lines",
    "waterbomb-base",
    "miura-ori",
    "waterbomb-tessellation",
    "yoshimura",
    "kresling",
    "square-twist",
];

/// A built-in pattern by name (case, `_` and spaces ignored: `Miura_Ori`
/// works) with default parameters.
pub fn builtin(name: &str) -> Option<CreasePattern> {
    let key: String = name
        .trim()
        .chars()
        .map(|c| match c {
            '_' | ' ' => '-',
            c => c.to_ascii_lowercase(),
        })
        .collect();
    match key.as_str() {
        "single-line" | "line" => Some(single_line()),
        "parallel-lines" | "pleats" => Some(parallel_lines(4)),
        "waterbomb-base" => Some(waterbomb_base()),
        "miura-ori" | "miura" => Some(miura_ori(&MiuraOri::default())),
        "waterbomb-tessellation" | "waterbomb" => Some(waterbomb_tessellation(4, 4)),
        "yoshimura" => Some(yoshimura(4, 6)),
        "kresling" => Some(kresling(&Kresling::default())),
        "square-twist" => Some(square_twist(30.0)),
        _ => None,
    }
}

/// `value` if finite and inside `[lo, hi]`, else the nearest bound (NaN
/// gives `fallback`).
fn clamp_or(value: f64, lo: f64, hi: f64, fallback: f64) -> f64 {
    if value.is_nan() {
        fallback
    } else {
        value.clamp(lo, hi)
    }
}

fn rectangle(b: &mut PatternBuilder, min: DVec2, max: DVec2) {
    let corners = [min, DVec2::new(max.x, min.y), max, DVec2::new(min.x, max.y)];
    for k in 0..4 {
        b.segment(corners[k], corners[(k + 1) % 4], Boundary, None);
    }
}

/// A unit square with one valley fold down the middle.
pub fn single_line() -> CreasePattern {
    parallel_lines(1)
}

/// A unit square with `n` (1 to 1000) evenly spaced vertical folds,
/// alternating valley and mountain: a pleat.
pub fn parallel_lines(n: usize) -> CreasePattern {
    let n = n.clamp(1, 1000);
    let mut b = PatternBuilder::default();
    rectangle(&mut b, DVec2::ZERO, DVec2::ONE);
    for i in 0..n {
        let x = (i + 1) as f64 / (n + 1) as f64;
        let kind = if i % 2 == 0 { Valley } else { Mountain };
        b.segment(DVec2::new(x, 0.0), DVec2::new(x, 1.0), kind, None);
    }
    b.finish()
}

/// The waterbomb base on a square of side 2: both diagonals mountain, the
/// horizontal midline valley (the vertical midline stays unfolded; the
/// centre is a degree-6 vertex with 4 mountains and 2 valleys).
pub fn waterbomb_base() -> CreasePattern {
    let mut b = PatternBuilder::default();
    rectangle(&mut b, DVec2::splat(-1.0), DVec2::ONE);
    for corner in [
        DVec2::new(-1.0, -1.0),
        DVec2::new(1.0, -1.0),
        DVec2::ONE,
        DVec2::new(-1.0, 1.0),
    ] {
        b.segment(DVec2::ZERO, corner, Mountain, None);
    }
    b.segment(DVec2::new(-1.0, 0.0), DVec2::new(1.0, 0.0), Valley, None);
    b.finish()
}

/// Parameters of [`miura_ori`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MiuraOri {
    /// Panel rows along the zigzag creases (1 to 200).
    pub rows: usize,
    /// Panel columns along the straight creases (1 to 200).
    pub columns: usize,
    /// Sector angle: the parallelogram's acute angle, degrees (5 to 90).
    pub sector_angle: f64,
    /// Panel side along the straight creases.
    pub a: f64,
    /// Panel side along the zigzag creases.
    pub b: f64,
}

impl Default for MiuraOri {
    fn default() -> Self {
        MiuraOri {
            rows: 4,
            columns: 4,
            sector_angle: 60.0,
            a: 1.0,
            b: 1.0,
        }
    }
}

fn positive_or_one(v: f64) -> f64 {
    if v.is_finite() && v > 0.0 {
        v
    } else {
        1.0
    }
}

/// Miura-ori: straight horizontal creases, zigzag creases across them;
/// vertex (i, j) sits at `x = i a (+ b cos(sector) on odd rows)`,
/// `y = j b sin(sector)`. Each zigzag line is all mountain or all valley,
/// alternating; the straight lines change at every vertex, so each
/// degree-4 vertex has three creases of one kind and one of the other.
pub fn miura_ori(params: &MiuraOri) -> CreasePattern {
    let rows = params.rows.clamp(1, 200);
    let columns = params.columns.clamp(1, 200);
    let gamma = clamp_or(params.sector_angle, 5.0, 90.0, 60.0).to_radians();
    let (a, side) = (positive_or_one(params.a), positive_or_one(params.b));
    let (shift, height) = (side * gamma.cos(), side * gamma.sin());
    let at = |i: usize, j: usize| {
        let offset = if j % 2 == 1 { shift } else { 0.0 };
        DVec2::new(i as f64 * a + offset, j as f64 * height)
    };
    let zigzag = |i: usize| if i % 2 == 0 { Mountain } else { Valley };
    let mut b = PatternBuilder::default();
    for j in 0..=rows {
        for i in 0..columns {
            let kind = match j {
                0 => Boundary,
                j if j == rows => Boundary,
                j if j % 2 == 1 => zigzag(i),
                _ => zigzag(i + 1),
            };
            b.segment(at(i, j), at(i + 1, j), kind, None);
        }
    }
    for i in 0..=columns {
        let kind = if i == 0 || i == columns {
            Boundary
        } else {
            zigzag(i)
        };
        for j in 0..rows {
            b.segment(at(i, j), at(i, j + 1), kind, None);
        }
    }
    b.finish()
}

/// The classic waterbomb tessellation: `rows` strips (1 to 100) of
/// waterbomb bases, `columns` (1 to 100) bases a strip, alternate strips
/// shifted by half a base. Cell units: each base is 2 x 2 with its diagonals
/// valley; vertical lines through every cell and the lines between strips
/// are mountains. Every interior vertex has 4 mountains and 2 valleys.
pub fn waterbomb_tessellation(rows: usize, columns: usize) -> CreasePattern {
    let (rows, columns) = (rows.clamp(1, 100), columns.clamp(1, 100));
    let (w, h) = ((2 * columns) as f64, (2 * rows) as f64);
    let mut b = PatternBuilder::default();
    rectangle(&mut b, DVec2::ZERO, DVec2::new(w, h));
    for x in 1..2 * columns {
        let x = x as f64;
        b.segment(DVec2::new(x, 0.0), DVec2::new(x, h), Mountain, None);
    }
    for r in 1..rows {
        let y = (2 * r) as f64;
        b.segment(DVec2::new(0.0, y), DVec2::new(w, y), Mountain, None);
    }
    for r in 0..rows {
        let centre_y = (2 * r + 1) as f64;
        for x in (r % 2..=2 * columns).step_by(2) {
            let centre = DVec2::new(x as f64, centre_y);
            for corner in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let end = centre + DVec2::from(corner);
                if (0.0..=w).contains(&end.x) {
                    b.segment(centre, end, Valley, None);
                }
            }
        }
    }
    b.finish()
}

/// The Yoshimura (diamond) pattern: `rows` (1 to 200) bands of `columns`
/// (1 to 200) equilateral triangles, alternate rows of vertices shifted by
/// half a triangle; horizontal lines valley, diagonals mountain, so every
/// interior vertex has 4 mountains and 2 valleys.
pub fn yoshimura(rows: usize, columns: usize) -> CreasePattern {
    let (rows, columns) = (rows.clamp(1, 200), columns.clamp(1, 200));
    let height = 3f64.sqrt() / 2.0;
    let w = columns as f64;
    let mut b = PatternBuilder::default();
    rectangle(&mut b, DVec2::ZERO, DVec2::new(w, rows as f64 * height));
    for j in 1..rows {
        let y = j as f64 * height;
        b.segment(DVec2::new(0.0, y), DVec2::new(w, y), Valley, None);
    }
    for j in 0..rows {
        let shift = if j % 2 == 1 { 0.5 } else { 0.0 };
        let count = if j % 2 == 1 { columns } else { columns + 1 };
        for i in 0..count {
            let p = DVec2::new(i as f64 + shift, j as f64 * height);
            for dx in [-0.5, 0.5] {
                let q = DVec2::new(p.x + dx, p.y + height);
                if (0.0..=w).contains(&q.x) {
                    b.segment(p, q, Mountain, None);
                }
            }
        }
    }
    b.finish()
}

/// Parameters of [`kresling`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kresling {
    /// Sides of the polygon the tube folds around (3 to 100); the flat
    /// pattern has this many panels a row.
    pub sides: usize,
    /// Rows of panels (1 to 100).
    pub rows: usize,
    /// How far each row is shifted, as a fraction of the panel width
    /// (0.05 to 0.95): the twist.
    pub twist: f64,
    /// Row height as a fraction of the panel width (0.05 to 10).
    pub height: f64,
}

impl Default for Kresling {
    fn default() -> Self {
        Kresling {
            sides: 6,
            rows: 3,
            twist: 0.5,
            height: 0.8,
        }
    }
}

/// The Kresling pattern: rows of parallelogram panels, each split by a
/// diagonal. Horizontal and slanted panel edges are mountains, the diagonals
/// valleys (4 mountains, 2 valleys at every interior vertex). The first and
/// last slanted edges are the sheet's boundary, to be joined into a tube.
pub fn kresling(params: &Kresling) -> CreasePattern {
    let sides = params.sides.clamp(3, 100);
    let rows = params.rows.clamp(1, 100);
    let twist = clamp_or(params.twist, 0.05, 0.95, 0.5);
    let height = clamp_or(params.height, 0.05, 10.0, 0.8);
    let at = |i: usize, j: usize| DVec2::new(i as f64 + j as f64 * twist, j as f64 * height);
    let mut b = PatternBuilder::default();
    for j in 0..=rows {
        let kind = if j == 0 || j == rows {
            Boundary
        } else {
            Mountain
        };
        for i in 0..sides {
            b.segment(at(i, j), at(i + 1, j), kind, None);
        }
    }
    for j in 0..rows {
        for i in 0..=sides {
            let kind = if i == 0 || i == sides {
                Boundary
            } else {
                Mountain
            };
            b.segment(at(i, j), at(i, j + 1), kind, None);
            if i < sides {
                b.segment(at(i, j), at(i + 1, j + 1), Valley, None);
            }
        }
    }
    b.finish()
}

/// The square twist on a 6 x 6 sheet: a central 2 x 2 square (mountain) and
/// four pleats leaving its sides at `twist` degrees (1 to 44) from the
/// sides' normals, each a valley from one corner and a mountain from the
/// next. Each corner has three mountains and one valley.
pub fn square_twist(twist: f64) -> CreasePattern {
    let tau = clamp_or(twist, 1.0, 44.0, 30.0).to_radians();
    let half = 3.0;
    let corners = [
        DVec2::new(-1.0, -1.0),
        DVec2::new(1.0, -1.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(-1.0, 1.0),
    ];
    let mut b = PatternBuilder::default();
    rectangle(&mut b, DVec2::splat(-half), DVec2::splat(half));
    for k in 0..4 {
        let (start, end) = (corners[k], corners[(k + 1) % 4]);
        b.segment(start, end, Mountain, None);
        // Outward normal of side k, turned by the twist.
        let normal = DVec2::from_angle(k as f64 * PI / 2.0 - PI / 2.0);
        let direction = DVec2::from_angle(tau).rotate(normal);
        b.segment(start, to_edge(start, direction, half), Valley, None);
        b.segment(end, to_edge(end, direction, half), Mountain, None);
    }
    b.finish()
}

/// Where the ray from `p` (inside the square `[-half, half]^2`) along
/// `direction` leaves it.
fn to_edge(p: DVec2, direction: DVec2, half: f64) -> DVec2 {
    let exit = |p: f64, d: f64| {
        if d > 0.0 {
            (half - p) / d
        } else if d < 0.0 {
            (-half - p) / d
        } else {
            f64::INFINITY
        }
    };
    p + direction * exit(p.x, direction.x).min(exit(p.y, direction.y))
}

#[cfg(test)]
mod tests {
    use super::super::fold::{parse_fold, to_fold_json};
    use super::super::planar::{planarize, DEFAULT_TOLERANCE};
    use super::super::sheet::{Sheet, SheetOptions};
    use super::*;

    /// Checks Maekawa and Kawasaki at every vertex not on the boundary and
    /// returns how many such vertices there are.
    fn check_flat_foldable(name: &str, pattern: &CreasePattern) -> usize {
        let graph = planarize(pattern, DEFAULT_TOLERANCE).unwrap();
        let mut interior = 0;
        for (v, &p) in graph.vertices.iter().enumerate() {
            let incident: Vec<_> = graph.edges.iter().filter(|e| e.v.contains(&v)).collect();
            if incident.iter().any(|e| e.assignment == Boundary) {
                continue;
            }
            interior += 1;
            let mountains = incident.iter().filter(|e| e.assignment == Mountain).count();
            let valleys = incident.iter().filter(|e| e.assignment == Valley).count();
            assert_eq!(
                incident.len(),
                mountains + valleys,
                "{name}: other edge at {p}"
            );
            if incident.len() == 2 {
                continue; // a straight line passing through
            }
            assert_eq!(
                mountains.abs_diff(valleys),
                2,
                "{name}: Maekawa fails at {p}: {mountains} M, {valleys} V"
            );
            let mut angles: Vec<f64> = incident
                .iter()
                .map(|e| {
                    let other = if e.v[0] == v { e.v[1] } else { e.v[0] };
                    let d = graph.vertices[other] - p;
                    d.y.atan2(d.x)
                })
                .collect();
            angles.sort_by(f64::total_cmp);
            let alternating: f64 = (0..angles.len())
                .map(|k| {
                    let next = angles.get(k + 1).copied().unwrap_or(angles[0] + 2.0 * PI);
                    let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                    sign * (next - angles[k])
                })
                .sum();
            assert!(
                alternating.abs() < 1e-9,
                "{name}: Kawasaki fails at {p}: {alternating}"
            );
        }
        interior
    }

    #[test]
    fn every_builtin_is_flat_foldable_and_builds_a_sheet() {
        for name in BUILTIN_NAMES {
            let pattern = builtin(name).unwrap();
            let interior = check_flat_foldable(name, &pattern);
            if !matches!(name, "single-line" | "parallel-lines") {
                assert!(interior > 0, "{name}: no interior vertex");
            }
            let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default()).unwrap();
            assert!(sheet.crease_count() > 0, "{name}");
        }
    }

    #[test]
    fn parameters_change_the_pattern_and_stay_flat_foldable() {
        let miura = MiuraOri {
            rows: 5,
            columns: 7,
            sector_angle: 70.0,
            a: 2.0,
            b: 1.5,
        };
        assert_eq!(check_flat_foldable("miura", &miura_ori(&miura)), 6 * 4);
        // 13 base centres and 9 vertices on each of the 2 lines between strips.
        assert_eq!(
            check_flat_foldable("waterbomb", &waterbomb_tessellation(3, 5)),
            31
        );
        assert_eq!(check_flat_foldable("yoshimura", &yoshimura(3, 5)), 9);
        let tall = Kresling {
            sides: 8,
            rows: 2,
            twist: 0.3,
            height: 1.2,
        };
        assert_eq!(check_flat_foldable("kresling", &kresling(&tall)), 7);
        assert_eq!(check_flat_foldable("twist", &square_twist(15.0)), 4);
        assert_eq!(check_flat_foldable("pleats", &parallel_lines(7)), 0);
    }

    #[test]
    fn silly_parameters_are_clamped() {
        let odd = MiuraOri {
            rows: 0,
            columns: usize::MAX,
            sector_angle: f64::NAN,
            a: -1.0,
            b: f64::INFINITY,
        };
        let p = miura_ori(&odd);
        assert_eq!(p.vertices.len(), 2 * 201);
        assert!(p.vertices.iter().all(|v| v.is_finite()));
        assert!(!square_twist(1e9).edges.is_empty());
    }

    #[test]
    fn names_are_forgiving_and_unknown_names_are_none() {
        assert_eq!(builtin("Miura_Ori"), builtin("miura-ori"));
        assert!(builtin("square twist").is_some());
        assert!(builtin("crane").is_none());
    }

    #[test]
    fn fold_round_trip_gives_the_same_graph() {
        for name in BUILTIN_NAMES {
            let pattern = builtin(name).unwrap();
            let again = parse_fold(&to_fold_json(&pattern)).unwrap();
            assert_eq!(pattern, again, "{name}");
        }
    }
}
