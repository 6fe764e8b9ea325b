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

/// Something a scene is built from that may not be what its author meant
/// (an importer's warning on a crease pattern), where and why, as a
/// [`SceneError`] says it.
pub type SceneWarning = SceneError;

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

    /// From a serde error on the scene `text`, keeping the JSON path and
    /// the line and column. Where serde_json says only "expected value" of
    /// a value that is there but of the wrong type (a number where a mesh
    /// or a collider's shape is asked), the message names what is expected
    /// and what was found.
    pub fn from_json(
        file: &str,
        text: &str,
        e: serde_path_to_error::Error<serde_json::Error>,
    ) -> Self {
        let path = e.path().to_string();
        let inner = e.inner();
        let path = if path == "." { String::new() } else { path };
        let message = strip_position(&inner.to_string()).to_string();
        let message = wrong_kind(text, e.path())
            .filter(|_| message == "expected value")
            .unwrap_or(message);
        let reason = format!(
            "{message} (line {}, column {})",
            inner.line(),
            inner.column()
        );
        SceneErrors::single(file, &path, &reason)
    }
}

/// "expected ..., got ..." for the value at `path` of `text` where the
/// field there holds one of several kinds of object named by their key.
fn wrong_kind(text: &str, path: &serde_path_to_error::Path) -> Option<String> {
    use serde_path_to_error::Segment;
    let mut value = &serde_json::from_str::<serde_json::Value>(text).ok()?;
    let mut field = None;
    for segment in path.iter() {
        value = match segment {
            Segment::Seq { index } => value.get(*index)?,
            Segment::Map { key } => {
                field = Some(key.as_str());
                value.get(key)?
            }
            Segment::Enum { .. } | Segment::Unknown => return None,
        };
    }
    let keys = match field? {
        "mesh" => super::spec::MESH_KEYS,
        "shape" => super::spec::SHAPE_KEYS,
        _ => return None,
    };
    Some(format!(
        "expected an object with {}, got {}",
        one_of(keys),
        describe(value)
    ))
}

/// "`a`, `b` or `c`".
fn one_of(keys: &[&str]) -> String {
    let quoted: Vec<String> = keys.iter().map(|k| format!("`{k}`")).collect();
    match quoted.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// A JSON value as a message names it: "the number 5", "a list".
fn describe(value: &serde_json::Value) -> String {
    use serde_json::Value;
    match value {
        Value::Null => "null".into(),
        Value::Bool(b) => format!("`{b}`"),
        Value::Number(n) => format!("the number {n}"),
        Value::String(s) => format!("the string \"{s}\""),
        Value::Array(_) => "a list".into(),
        Value::Object(_) => "an object".into(),
    }
}

/// serde_json appends " at line L column C"; we report the position ourselves.
fn strip_position(message: &str) -> &str {
    message
        .rfind(" at line ")
        .map_or(message, |i| &message[..i])
}

#[cfg(test)]
mod tests {
    use super::super::spec::{MeshSpec, ShapeSpec, MESH_KEYS, SHAPE_KEYS};

    /// serde's own list of an enum's keys, from its error for an unknown one.
    fn serde_keys<T: serde::de::DeserializeOwned + std::fmt::Debug>() -> String {
        let e = serde_json::from_str::<T>(r#""no_such_key""#).unwrap_err();
        let text = e.to_string();
        let list = text.split("expected one of ").nth(1).unwrap();
        list.split(" at line").next().unwrap().to_string()
    }

    #[test]
    fn the_keys_in_messages_are_those_serde_reads() {
        let listed = |keys: &[&str]| {
            let quoted: Vec<String> = keys.iter().map(|k| format!("`{k}`")).collect();
            quoted.join(", ")
        };
        assert_eq!(serde_keys::<MeshSpec>(), listed(MESH_KEYS));
        assert_eq!(serde_keys::<ShapeSpec>(), listed(SHAPE_KEYS));
    }
}
