//! Scene files: JSON descriptions of cloths, materials, pins, colliders,
//! wind, solver settings and frames.
//!
//! [`Scene::parse`] refuses unknown fields, wrong types and out-of-range
//! values with errors that name the file, the JSON path and the reason;
//! [`Scene::build`] turns a valid scene into a [`Simulation`](crate::Simulation).

mod build;
mod error;
mod files;
pub mod presets;
mod spec;
mod validate;

pub use error::{SceneError, SceneErrors, SceneWarning};
pub use files::{FileError, Folder, InMemory, SceneFiles};
pub use spec::*;

use std::path::Path;

impl Scene {
    /// Parses and validates scene JSON; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Scene, SceneErrors> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let mut scene: Scene = serde_path_to_error::deserialize(de)
            .map_err(|e| SceneErrors::from_json(file, text, e))?;
        let errors = validate::validate(&scene, file);
        if !errors.is_empty() {
            return Err(SceneErrors(errors));
        }
        if scene.name.is_empty() {
            scene.name = Path::new(file)
                .file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        }
        Ok(scene)
    }

    /// Reads, parses and validates a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneErrors> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| SceneErrors::single(&file, "", &format!("cannot read the file: {e}")))?;
        Scene::parse(&text, &file)
    }

    /// Seconds per frame.
    pub fn frame_dt(&self) -> f32 {
        1.0 / self.fps
    }
}
