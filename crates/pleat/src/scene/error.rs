//! Scene errors: where (file and JSON path) and why.

use std::fmt;

/// One thing wrong with a scene.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    /// The scene file, as named in messages.
    pub file: String,
    /// JSON path such as `cloths[0].material.density`; empty for the whole file.
    pub path: String,
    /// What is wrong.
    pub reason: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.path.is_empty() {
            write!(f, "{}: {}", self.file, self.reason)
        } else {
            write!(f, "{}: {}: {}", self.file, self.path, self.reason)
        }
    }
}

/// Everything wrong with a scene, one error a line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct SceneErrors(pub Vec<SceneError>);

impl fmt::Display for SceneErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, e) in self.0.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{e}")?;
        }
        Ok(())
    }
}

impl SceneErrors {
    /// A single error: `reason` at the JSON `path` of `file`.
    pub fn single(file: &str, path: &str, reason: &str) -> Self {
        SceneErrors(vec![SceneError {
            file: file.into(),
            path: path.into(),
            reason: reason.into(),
        }])
    }

    /// From a serde error, keeping the JSON path and the line and column.
    pub fn from_json(file: &str, e: serde_path_to_error::Error<serde_json::Error>) -> Self {
        let path = e.path().to_string();
        let inner = e.inner();
        let path = if path == "." { String::new() } else { path };
        let reason = format!(
            "{} (line {}, column {})",
            strip_position(&inner.to_string()),
            inner.line(),
            inner.column()
        );
        SceneErrors::single(file, &path, &reason)
    }
}

/// serde_json appends " at line L column C"; we report the position ourselves.
fn strip_position(message: &str) -> &str {
    message
        .rfind(" at line ")
        .map_or(message, |i| &message[..i])
}
