//! The crease-pattern importers against real files made by other tools
//! (`patterns/shared`, copied unchanged from the project's shared folder with
//! their attribution in SOURCES.md), against malformed input, and against
//! mutated files that must never make them panic.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use pleat::origami::{
    load_pattern, load_pattern_with_warnings, parse_cp, parse_fold, parse_svg, Assignment,
    CreasePattern, PatternError, Sheet, SheetOptions,
};

/// The folder of `patterns/` named `name`.
fn patterns_dir(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patterns")
        .join(name)
}

fn shared_dir() -> PathBuf {
    patterns_dir("shared")
}

/// The crease-pattern files in `dir`, sorted.
fn pattern_files_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.expect("readable entry").path())
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("cp" | "fold" | "svg")
            )
        })
        .collect();
    files.sort();
    files
}

fn pattern_files() -> Vec<PathBuf> {
    pattern_files_in(&shared_dir())
}

fn name(path: &Path) -> String {
    path.file_name().unwrap().to_string_lossy().into_owned()
}

/// Checks the mesh invariants every sheet must have.
fn check_sheet(sheet: &Sheet, file: &str) {
    assert!(!sheet.triangles.is_empty(), "{file}: no triangles");
    let mut used = vec![false; sheet.positions.len()];
    for t in &sheet.triangles {
        let [a, b, c] = t.map(|i| sheet.positions[i as usize].truncate().as_dvec2());
        let area = 0.5 * (b - a).perp_dot(c - a);
        assert!(
            area > 0.0,
            "{file}: triangle {t:?} is not counter-clockwise ({area})"
        );
        for &i in t {
            used[i as usize] = true;
        }
    }
    assert!(used.iter().all(|&u| u), "{file}: unused vertex");
    assert!(sheet.positions.iter().all(|p| p.z == 0.0 && p.is_finite()));

    // Centred, longest side 1 m.
    let min = sheet
        .positions
        .iter()
        .fold(glam::Vec3::INFINITY, |m, p| m.min(*p));
    let max = sheet
        .positions
        .iter()
        .fold(glam::Vec3::NEG_INFINITY, |m, p| m.max(*p));
    assert!(
        (max - min).max_element() - 1.0 < 1e-5,
        "{file}: size {:?}",
        max - min
    );
    assert!((min + max).length() < 1e-5, "{file}: not centred");

    assert!(!sheet.hinges.is_empty(), "{file}: no hinges");
    assert!(sheet.crease_count() > 0, "{file}: no creases");
    let directed: HashSet<[u32; 3]> = sheet
        .triangles
        .iter()
        .flat_map(|&[a, b, c]| [[a, b, c], [b, c, a], [c, a, b]])
        .collect();
    for h in &sheet.hinges {
        let [v0, v1, v2, v3] = h.v;
        assert!(
            directed.contains(&[v0, v1, v2]),
            "{file}: hinge {h:?} first wing"
        );
        assert!(
            directed.contains(&[v1, v0, v3]),
            "{file}: hinge {h:?} second wing"
        );
        assert!(!matches!(
            h.assignment,
            Assignment::Boundary | Assignment::Cut
        ));
        if let Some(angle) = h.fold_angle {
            assert!(angle.abs() <= std::f32::consts::PI + 1e-6);
        }
    }

    // Euler characteristic V - E + F: 1 for a disc, less with holes or cuts
    // running in from the rim (none of the shared patterns has either).
    let edges: HashSet<[u32; 2]> = sheet
        .triangles
        .iter()
        .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    let chi = sheet.positions.len() as i64 - edges.len() as i64 + sheet.triangles.len() as i64;
    assert_eq!(chi, 1, "{file}: Euler characteristic");
}

#[test]
fn every_shared_pattern_imports_and_builds_a_sound_sheet() {
    let files = pattern_files();
    assert_eq!(files.len(), 14, "{files:?}");
    for path in files {
        let file = name(&path);
        let pattern = load_pattern(&path).unwrap_or_else(|e| panic!("{e}"));
        let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default())
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        check_sheet(&sheet, &file);
    }
}

#[test]
fn refined_sheets_stay_sound() {
    for path in pattern_files() {
        let file = name(&path);
        let pattern = load_pattern(&path).unwrap();
        let plain = Sheet::from_pattern(&pattern, &SheetOptions::default()).unwrap();
        let options = SheetOptions {
            size: 2.0,
            max_edge: Some(0.25),
            ..SheetOptions::default()
        };
        let refined = Sheet::from_pattern(&pattern, &options).unwrap();
        assert!(refined.triangles.len() >= plain.triangles.len(), "{file}");
        // About 150 triangles of side 0.25 m fill 2 m x 2 m, more near small
        // angles between creases; refinement that spirals into a point makes
        // tens of thousands.
        let bound = plain.triangles.len() + 3000;
        assert!(
            refined.triangles.len() < bound,
            "{file}: {}",
            refined.triangles.len()
        );
        assert!(refined.crease_count() >= plain.crease_count(), "{file}");
        let scaled = Sheet {
            positions: refined.positions.iter().map(|p| *p * 0.5).collect(),
            ..refined
        };
        check_sheet(&scaled, &file);
    }
}

#[test]
fn known_facts_about_the_shared_files() {
    let sheet = |file: &str| {
        let pattern = load_pattern(shared_dir().join(file)).unwrap();
        Sheet::from_pattern(&pattern, &SheetOptions::default()).unwrap()
    };
    // One valley through the middle of a square: two triangles a side.
    let line = sheet("line.cp");
    let valleys: Vec<_> = line
        .hinges
        .iter()
        .filter(|h| h.assignment == Assignment::Valley)
        .collect();
    assert!(!valleys.is_empty() && valleys.iter().all(|h| h.fold_angle.is_none()));
    // The cube net folds its valleys to 90 degrees.
    let cube = sheet("cube-cp.fold");
    let angles: HashSet<i32> = cube
        .hinges
        .iter()
        .filter(|h| h.assignment == Assignment::Valley)
        .map(|h| h.fold_angle.unwrap().to_degrees().round() as i32)
        .collect();
    assert_eq!(angles, HashSet::from([90]));
    // waterbombBase.svg: valleys at opacity 0.5 fold to 90 degrees.
    let waterbomb = sheet("waterbombBase.svg");
    assert!(waterbomb
        .hinges
        .iter()
        .filter(|h| h.assignment == Assignment::Valley)
        .all(|h| (h.fold_angle.unwrap() - std::f32::consts::FRAC_PI_2).abs() < 1e-6));
    // hypar.svg's magenta lines are free hinges.
    assert!(sheet("hypar.svg")
        .hinges
        .iter()
        .any(|h| h.assignment == Assignment::Unassigned && h.fold_angle.is_none()));
    // birdBase.svg has yellow facet lines and <animate> children.
    let (bird, warnings) = load_pattern_with_warnings(shared_dir().join("birdBase.svg")).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(bird.edges.iter().any(|e| e.assignment == Assignment::Flat));
}

/// Origami Simulator files that needed a tolerant importer: CSS-styled
/// strokes, curves finer than the merge tolerance (tests/data/SOURCES.md).
#[test]
fn css_styled_and_finely_curved_svgs_are_read() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    for (file, min_creases) in [("Leafy_Opus_T-69.svg", 700), ("HexSpiralTess.svg", 2000)] {
        let (pattern, warnings) = load_pattern_with_warnings(data.join(file)).unwrap();
        assert!(warnings.is_empty(), "{file}: {warnings:?}");
        let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default())
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(
            sheet.crease_count() >= min_creases,
            "{file}: {} creases",
            sheet.crease_count()
        );
    }
}

/// Origami Simulator's FTpoly7 is drawn on a 10000-unit grid, and its
/// central polygons shrink to 10 units, finer than the 0.3 % merge
/// tolerance (42 units). Its import keeps them: the sheet has the 300
/// valley creases Origami Simulator's own import makes of it (the 228
/// drawn, split where others meet them), where merging them away left 266.
#[test]
fn a_twist_finer_than_the_merge_tolerance_keeps_its_creases() {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patterns/origami-simulator/FTpoly7.svg");
    let pattern = load_pattern(&file).unwrap();
    let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default()).unwrap();
    check_sheet(&sheet, "FTpoly7.svg");
    let valleys = sheet
        .hinges
        .iter()
        .filter(|h| h.assignment == Assignment::Valley)
        .count();
    assert_eq!(valleys, 300);
}

/// `(what, input, location, reason)` for one error kind.
type Case = (&'static str, &'static str, &'static str, &'static str);

fn check_cases(parse: impl Fn(&str) -> Result<CreasePattern, PatternError>, cases: &[Case]) {
    for &(what, input, location, reason) in cases {
        let error = parse(input).expect_err(what);
        assert_eq!(error.location, location, "{what}: {error}");
        assert!(error.reason.contains(reason), "{what}: {error}");
        let message = error.with_file("bad").to_string();
        assert!(
            message.starts_with(&format!("bad: {location}")),
            "{what}: {message}"
        );
    }
}

#[test]
fn malformed_cp_files_are_refused_with_line_and_reason() {
    check_cases(
        parse_cp,
        &[
            (
                "field count",
                "1 0 0 1 1\n2 0 0 1\n",
                "line 2",
                "expected 5 fields, found 4",
            ),
            (
                "extra field",
                "1 0 0 1 1 7",
                "line 1",
                "expected 5 fields, found 6",
            ),
            (
                "bad number",
                "\n\n3 0 0 1e 1",
                "line 3",
                "x2: bad number '1e'",
            ),
            (
                "not finite",
                "3 0 NaN 1 1",
                "line 1",
                "y1: number 'NaN' is not finite",
            ),
            (
                "unknown type",
                "5 0 0 1 1",
                "line 1",
                "unknown line type '5'",
            ),
            ("empty", "\r\n", "", "no segments"),
        ],
    );
}

#[test]
fn malformed_fold_files_are_refused_with_json_path_and_reason() {
    check_cases(
        parse_fold,
        &[
            (
                "bad JSON",
                "{\"vertices_coords\": [[0,0],]}",
                "line 1, column 28",
                "bad JSON: trailing comma",
            ),
            (
                "not an object",
                "[]",
                "top level",
                "expected a JSON object, found an array",
            ),
            (
                "missing coords",
                "{\"edges_vertices\": []}",
                "vertices_coords",
                "missing",
            ),
            (
                "wrong type with path",
                r#"{"vertices_coords": [[0,0],[1,0]], "edges_vertices": [[0,"1"]]}"#,
                "edges_vertices[0][1]",
                "expected a vertex index",
            ),
            (
                "index out of range",
                r#"{"vertices_coords": [[0,0],[1,0]], "edges_vertices": [[0,1],[1,5]]}"#,
                "edges_vertices[1][1]",
                "vertex index 5 out of range",
            ),
            (
                "bad coordinate",
                r#"{"vertices_coords": [[0,0],[1]], "edges_vertices": []}"#,
                "vertices_coords[1]",
                "expected [x, y] or [x, y, z]",
            ),
            (
                "unknown assignment",
                r#"{"vertices_coords": [[0,0],[1,0]], "edges_vertices": [[0,1]], "edges_assignment": ["Q"]}"#,
                "edges_assignment[0]",
                "unknown assignment 'Q'",
            ),
            (
                "length mismatch",
                r#"{"vertices_coords": [[0,0],[1,0]], "edges_vertices": [[0,1]], "edges_foldAngle": [1, 2]}"#,
                "edges_foldAngle",
                "has 2 entries, but edges_vertices has 1",
            ),
            (
                "bad angle",
                r#"{"vertices_coords": [[0,0],[1,0]], "edges_vertices": [[0,1]], "edges_foldAngle": [true]}"#,
                "edges_foldAngle[0]",
                "expected a number, found a boolean",
            ),
            (
                "folded state",
                r#"{"vertices_coords": [[0,0,0],[1,0,0],[0,1,0],[1,1,0.5]], "edges_vertices": [[0,1]]}"#,
                "vertices_coords[1]",
                "a folded state (3D vertices_coords) with no faces_vertices to unfold it by",
            ),
            (
                "folded state that cannot lie flat",
                r#"{"vertices_coords": [[0,0,1],[1,1,0],[-1,1,0],[-1,-1,0],[1,-1,0]],
                    "faces_vertices": [[0,1,2],[0,2,3],[0,3,4],[0,4,1]]}"#,
                "vertices_coords[0]",
                "the faces around it hold 282.1 degrees of paper, not 360",
            ),
            (
                "no edges",
                r#"{"vertices_coords": [[0,0]]}"#,
                "edges_vertices",
                "missing (and no faces_vertices",
            ),
        ],
    );
}

fn svg_pattern(text: &str) -> Result<CreasePattern, PatternError> {
    parse_svg(text).map(|import| import.pattern)
}

#[test]
fn malformed_svg_files_are_refused_with_line_and_reason() {
    check_cases(
        svg_pattern,
        &[
            ("bad XML", "<svg>\n<line></svg>", "line 2, column 7", "bad XML: expected 'line' tag, not 'svg'"),
            ("wrong root", "<html/>", "top level", "expected an <svg> root element"),
            (
                "no segments",
                "<svg><rect width=\"9\" height=\"9\" fill=\"red\"/><line x2=\"1\" stroke=\"#123\"/></svg>",
                "",
                "no segments",
            ),
            (
                "arc",
                "<svg>\n\n<path stroke=\"red\" d=\"M0 0 a1 1 0 0 1 3 3\"/></svg>",
                "line 3",
                "<path> d: arc command 'a' is not supported",
            ),
            (
                "bad path",
                "<svg><path stroke=\"red\" d=\"M0 0 L1\"/></svg>",
                "line 1",
                "<path> d: expected a number at character 8",
            ),
            (
                "bad length",
                "<svg><line stroke=\"red\" x1=\"1cm\"/></svg>",
                "line 1",
                "<line> x1: bad length '1cm'",
            ),
            (
                "odd points",
                "<svg><polyline stroke=\"blue\" points=\"0 0 1\"/></svg>",
                "line 1",
                "<polyline> points: odd number of coordinates",
            ),
            (
                "negative rect",
                "<svg><rect stroke=\"black\" width=\"-1\" height=\"2\"/></svg>",
                "line 1",
                "<rect> has a negative size",
            ),
            (
                "bad opacity",
                "<svg><line stroke=\"red\" x2=\"1\" opacity=\"x\"/></svg>",
                "line 1",
                "opacity: bad number 'x'",
            ),
            (
                "bad transform",
                "<svg><g transform=\"skew(3)\"><line stroke=\"red\" x2=\"1\"/></g></svg>",
                "line 1",
                "transform: unknown transform function 'skew'",
            ),
        ],
    );
}

#[test]
fn load_pattern_names_the_file() {
    let path = std::env::temp_dir().join(format!("pleat-bad-{}.cp", std::process::id()));
    std::fs::write(&path, "1 0 0 1 1\n2 0 0 1\n").unwrap();
    let message = load_pattern(&path).unwrap_err().to_string();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(
        message,
        format!("{}: line 2: expected 5 fields, found 4", path.display())
    );
    let missing = load_pattern("/nonexistent/x.fold").unwrap_err().to_string();
    assert!(
        missing.starts_with("/nonexistent/x.fold: cannot read"),
        "{missing}"
    );
}

/// xorshift64*: a small deterministic generator for the mutations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

fn import_and_build(file: &str, text: &str) {
    let parsed = match file.rsplit('.').next() {
        Some("cp") => parse_cp(text),
        Some("fold") => parse_fold(text),
        _ => svg_pattern(text),
    };
    if let Ok(pattern) = parsed {
        // Errors are fine; a panic fails the test.
        let _ = Sheet::from_pattern(&pattern, &SheetOptions::default());
    }
}

#[test]
fn mutated_files_never_panic() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for path in pattern_files() {
        mutate_and_import(&name(&path), &std::fs::read(&path).unwrap(), &mut rng);
    }
    // A flat-folded state with its layer order (`faceOrders`), as `pleat
    // check --folded-out` writes it.
    let sheet = Sheet::from_pattern(
        &pleat::origami::builtin("waterbomb-base").unwrap(),
        &SheetOptions::default(),
    )
    .unwrap();
    let folded = pleat::origami::FlatFolded::solve(&sheet).unwrap();
    let text = folded.to_fold_json(&sheet, "waterbomb-base").to_string();
    mutate_and_import("folded.fold", text.as_bytes(), &mut rng);
}

/// Imports `bytes` (the file `file`) cut short at 40 places and with 150
/// random mutations of one to four bytes each.
fn mutate_and_import(file: &str, bytes: &[u8], rng: &mut Rng) {
    // Bytes that matter to the grammars.
    let interesting = b"0123456789.-+eE,; \n<>/\"=[]{}:MmLlHhVvZzCc#";
    for k in 1..=40 {
        let cut = bytes.len() * k / 41;
        import_and_build(file, &String::from_utf8_lossy(&bytes[..cut]));
    }
    for _ in 0..150 {
        let mut mutated = bytes.to_vec();
        for _ in 0..1 + rng.below(4) {
            let at = rng.below(mutated.len());
            mutated[at] = match rng.below(3) {
                0 => rng.next() as u8,
                1 => interesting[rng.below(interesting.len())],
                _ => mutated[at] ^ (1 << rng.below(8)),
            };
        }
        import_and_build(file, &String::from_utf8_lossy(&mutated));
    }
}

/// Every pattern here with a layer order, written as its flat-folded state
/// (`pleat check --folded-out`: the vertices where they land, in 2D, the
/// triangles as faces and their `faceOrders`, no creases), reads back into
/// its own mountains and valleys: folded flat, only the layer order tells
/// which way each crease went; the lines the fold leaves flat come back as
/// facet lines. With the orders reversed every crease comes back the other
/// way; without them, unassigned.
#[test]
fn a_flat_folded_state_reads_back_into_its_mountains_and_valleys() {
    use pleat::origami::{builtin, check_flat_foldability, FlatFolded, BUILTIN_NAMES};
    let mut patterns: Vec<(String, CreasePattern)> = BUILTIN_NAMES
        .iter()
        .map(|&name| (name.to_owned(), builtin(name).unwrap()))
        .collect();
    for dir in ["shared", "fold-examples", "origami-simulator"] {
        let files = pattern_files_in(&patterns_dir(dir));
        patterns.extend(files.iter().map(|p| (name(p), load_pattern(p).unwrap())));
    }
    let mut read_back = Vec::new();
    for (file, pattern) in &patterns {
        // As `pleat check` does: only a pattern flat-foldable as drawn.
        let flat = check_flat_foldability(pattern).unwrap();
        if !flat.is_flat_foldable() || flat.vertices_skipped > 0 {
            continue;
        }
        let sheet = Sheet::from_pattern(pattern, &SheetOptions::default()).unwrap();
        let Ok(folded) = FlatFolded::solve(&sheet) else {
            continue;
        };
        let json = folded.to_fold_json(&sheet, file);
        let creases = |json: &serde_json::Value| {
            let again = parse_fold(&json.to_string()).unwrap_or_else(|e| panic!("{file}: {e}"));
            let by_edge: std::collections::HashMap<[usize; 2], Assignment> = again
                .edges
                .iter()
                .map(|e| ([e.v[0].min(e.v[1]), e.v[0].max(e.v[1])], e.assignment))
                .collect();
            sheet
                .hinges
                .iter()
                .filter(|h| {
                    matches!(
                        h.assignment,
                        Assignment::Mountain | Assignment::Valley | Assignment::Flat
                    )
                })
                .map(|h| {
                    let key = [h.v[0].min(h.v[1]), h.v[0].max(h.v[1])].map(|v| v as usize);
                    (h.assignment, by_edge[&key])
                })
                .collect::<Vec<_>>()
        };
        let creases_with_orders = creases(&json);
        let wrong: Vec<_> = creases_with_orders
            .iter()
            .filter(|(was, is)| was != is)
            .collect();
        assert!(
            wrong.is_empty(),
            "{file}: {} of {} creases read back wrong, the first {:?}",
            wrong.len(),
            creases_with_orders.len(),
            &wrong[..wrong.len().min(4)]
        );
        // The sheet seen from its back: every order and crease reversed.
        let mut reversed = json.clone();
        for order in reversed["faceOrders"].as_array_mut().unwrap() {
            order[2] = (-order[2].as_i64().unwrap()).into();
        }
        let flipped = |a: Assignment| match a {
            Assignment::Mountain => Assignment::Valley,
            Assignment::Valley => Assignment::Mountain,
            other => other,
        };
        assert!(
            creases(&reversed)
                .iter()
                .all(|&(was, is)| is == flipped(was)),
            "{file}"
        );
        let mut without = json.clone();
        without.as_object_mut().unwrap().remove("faceOrders");
        assert!(
            creases(&without).iter().all(|&(was, is)| is
                == match was {
                    Assignment::Flat => Assignment::Flat,
                    _ => Assignment::Unassigned,
                }),
            "{file}"
        );
        read_back.push(file.clone());
    }
    assert!(read_back.len() >= 19, "{read_back:?}");
}
