//! Reading a crease pattern from a file or from memory: the importer
//! (`.cp`, `.fold`, `.svg`, any case) is chosen by the extension.

use std::path::Path;

use super::pattern::{CreasePattern, PatternError};
use super::{cp, fold, svg};

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

/// The steps of a crease pattern's file (`name`'s extension chooses: only
/// a multi-frame FOLD file has any, [`fold::parse_fold_frames`]) for the
/// `pattern` read from it: per step, each edge's fold angle at its end.
/// Errors name `name`.
pub fn parse_pattern_steps(
    name: &str,
    bytes: &[u8],
    pattern: &CreasePattern,
) -> Result<Vec<Vec<Option<f64>>>, PatternError> {
    if extension_of(Path::new(name)) != "fold" {
        return Ok(Vec::new());
    }
    let text = std::str::from_utf8(bytes).map_err(|e| {
        PatternError::new(format!("byte {}", e.valid_up_to()), "not valid UTF-8 text")
    })?;
    fold::parse_fold_frames(text, pattern).map_err(|e| e.with_file(name))
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
        "fold" => fold::parse_fold_with_warnings(text),
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
    fn unknown_extension_is_refused_with_file_name() {
        let dir = std::env::temp_dir().join("pleat-pattern-ext-test.txt");
        std::fs::write(&dir, "1 0 0 1 1").unwrap();
        let e = load_pattern(&dir).unwrap_err();
        assert!(e.to_string().contains("pleat-pattern-ext-test.txt"));
        assert!(e.reason.contains("unknown crease-pattern extension"));
    }
}
